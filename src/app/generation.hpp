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

namespace sdfgen::app {

// A bake running on a background thread, watched from the UI thread: progress, cancel, result.
class Generation {
public:
    ~Generation() { stop(); }
    // Starts baking `mesh` (the mesh must outlive the job; it is shared).
    void start(std::shared_ptr<const Mesh> mesh, const BakeSettings& settings, int threads);
    // Asks the job to stop and waits for it.
    void stop();
    void cancel() { cancel_ = true; }
    bool running() const { return thread_.joinable() && !finished_; }
    double progress() const { return progress_; }
    double elapsed() const;
    // When the job has finished since the last call: joins it, hands over the result (empty on
    // failure, with the message in `error`) and returns true. False while running or idle.
    bool collect(std::optional<BakeResult>& result, std::string& error, double& seconds);

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
};

} // namespace sdfgen::app
