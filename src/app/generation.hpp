#pragma once
#include "sdfgen/field.hpp"
#include "sdfgen/bake.hpp"
#include "sdfgen/mesh.hpp"

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace sdfgen::app {

// How a bake runs, beside what it bakes (BakeSettings): the place for a device choice.
struct GenerationOptions {
    int threads = 0; // 0: all cores
};

// A bake running on a background thread, watched from the UI thread: progress, cancel, result.
class Generation {
public:
    ~Generation() { stop(); }
    // Starts baking `mesh` (shared, so it outlives the job).
    void start(std::shared_ptr<const Mesh> mesh, const BakeSettings& settings, const GenerationOptions& options);
    // Asks the job to stop and waits for it.
    void stop();
    void cancel() { cancel_ = true; }
    bool running() const { return thread_.joinable() && !finished_; }
    // Running, or finished with a result not collected yet.
    bool pending() const { return thread_.joinable(); }
    double progress() const { return progress_; }
    double elapsed() const;
    // When the job has finished since the last call: joins it, hands over the result (empty on
    // failure, with the message in `error`) and the warnings of the mesh and the bake (one line
    // each, naming the mesh), and returns true. False while running or idle.
    bool collect(std::optional<BakeResult>& result, std::string& error, std::vector<std::string>& warnings, double& seconds);

private:
    std::thread thread_;
    std::atomic<bool> cancel_{false};
    std::atomic<bool> finished_{false};
    std::atomic<double> progress_{0.0};
    std::chrono::steady_clock::time_point started_;
    double seconds_ = 0.0;
    std::mutex mutex_;
    std::optional<BakeResult> result_;
    std::string error_;
    std::vector<std::string> warnings_;
};

} // namespace sdfgen::app
