#pragma once
#include "sdfgen/field.hpp"
#include "sdfgen/bake.hpp"
#include "sdfgen/mesh.hpp"
#include "sdfgen/run_control.hpp"
#include "sdfgen/sparse_field.hpp"

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace sdfgen::app {

// Long work on a background thread, watched from the UI thread through the core's RunControl:
// progress, Cancel, elapsed time. The work runs with a control whose cancel flag and progress
// this task holds; Cancelled (or any exception) ends it with a message.
class BackgroundTask {
public:
    ~BackgroundTask() { stop(); }
    // Starts `work` (stopping any task still running) with `threads` worker threads (0: all cores).
    // `work` returns normally on success; an exception's message becomes error(), "cancelled"
    // for Cancelled.
    void start(int threads, std::function<void(RunControl&)> work);
    // Asks the task to stop and waits for it; its result is dropped.
    void stop();
    void cancel() { cancel_ = true; }
    bool running() const { return thread_.joinable() && !finished_; }
    // Running, or finished and not collected yet.
    bool pending() const { return thread_.joinable(); }
    double progress() const { return progress_; }
    double elapsed() const;
    // When the task has finished since the last call: joins it, sets `error` (empty on success)
    // and `seconds`, and returns true. False while running or idle.
    bool finish(std::string& error, double& seconds);

private:
    std::thread thread_;
    std::atomic<bool> cancel_{false};
    std::atomic<bool> finished_{false};
    std::atomic<double> progress_{0.0};
    std::chrono::steady_clock::time_point started_;
    double seconds_ = 0.0;
    std::string error_; // written by the worker before finished_ is raised
};

// How a bake runs, beside what it bakes (BakeSettings): the place for a device choice.
struct GenerationOptions {
    int threads = 0; // 0: all cores
};

// A bake running on a background thread: progress, cancel, result.
class Generation {
public:
    // Starts baking `mesh` (shared, so it outlives the job).
    void start(std::shared_ptr<const Mesh> mesh, const BakeSettings& settings, const GenerationOptions& options);
    void stop() { task_.stop(); }
    void cancel() { task_.cancel(); }
    bool running() const { return task_.running(); }
    bool pending() const { return task_.pending(); }
    double progress() const { return task_.progress(); }
    double elapsed() const { return task_.elapsed(); }
    // When the job has finished since the last call: hands over the result (empty on failure,
    // with the message in `error`) and the warnings of the mesh and the bake (one line each,
    // naming the mesh), and returns true. False while running or idle.
    bool collect(std::optional<BakeResult>& result, std::string& error, std::vector<std::string>& warnings, double& seconds);

private:
    BackgroundTask task_;
    // Written by the worker, read once it has finished.
    std::optional<BakeResult> result_;
    std::vector<std::string> warnings_;
};

// A field file read on a background thread, as it will be shown: a dense field, or a band field
// with the dense resampling the views show (render::bandDisplay, made on the same thread).
struct LoadedField {
    std::optional<Field> field;        // what the views show
    std::optional<SparseField> band;   // the band field itself, when the file holds one
    std::string bandLine;              // render::BandDisplay::line of band
};

class FieldLoad {
public:
    // Starts reading `path` (stopping a load still running); `textureLimit` is the largest 3D
    // texture, for a band field's resampling.
    void start(const std::string& path, int threads, int textureLimit);
    void stop() { task_.stop(); }
    void cancel() { task_.cancel(); }
    bool running() const { return task_.running(); }
    bool pending() const { return task_.pending(); }
    double progress() const { return task_.progress(); }
    double elapsed() const { return task_.elapsed(); }
    const std::string& path() const { return path_; }
    // The GUI test's stand-in for a slow disk (SDFGEN_DEBUG_READ_DELAY_MS): each progress report
    // of a load waits this long.
    int delayPerReportMs = 0;
    // When the load has finished since the last call: hands over the field (empty on failure,
    // with the message in `error`: "cancelled" when cancelled) and returns true.
    bool collect(std::optional<LoadedField>& result, std::string& error);

private:
    BackgroundTask task_;
    std::string path_;
    std::optional<LoadedField> result_; // written by the worker, read once it has finished
};

} // namespace sdfgen::app
