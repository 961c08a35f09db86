#pragma once
#include "sdfgen/field.hpp"
#include "sdfgen/bake.hpp"
#include "sdfgen/compare.hpp"
#include "sdfgen/mesh.hpp"
#include "sdfgen/model.hpp"
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
// this task holds; Cancelled (or any exception) ends it with a message. The jobs below derive
// from it, each adding what its work makes and how that is handed over; each stops its work in
// its own destructor (the work writes the job's members).
class BackgroundTask {
public:
    // Asks the task to stop and waits for it; its result is dropped.
    void stop();
    // Asks the task to stop without waiting (the UI thread stays live): it ends soon, with
    // "cancelled" and no result, even when its work had just finished.
    void cancel() { cancel_ = true; }
    bool cancelled() const { return cancel_; } // since the last start: a running task is winding down
    bool running() const { return thread_.joinable() && !finished_; }
    // Running, or finished and not collected yet.
    bool pending() const { return thread_.joinable(); }
    double progress() const { return progress_; }
    double elapsed() const;

protected:
    ~BackgroundTask() { stop(); }
    // Starts `work` (stopping any task still running) with `threads` worker threads (0: all cores).
    // `work` returns normally on success; an exception's message becomes the error, "cancelled"
    // for Cancelled.
    void start(int threads, std::function<void(RunControl&)> work);
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

// The scene mesh's one Model, serving its bakes and the probe (Model's const calls may run on
// several threads at once: model.hpp). It is built on first use by whichever asks first: a bake
// on its thread, with its control (threads, progress, Cancel: a build cancelled is made again by
// the next use), or the probe on the GUI thread. Shared, so that a bake still winding down keeps
// the model of the scene it started with.
class MeshModel {
public:
    explicit MeshModel(std::shared_ptr<const Mesh> mesh) : mesh_(std::move(mesh)) {}
    // The model, built now if it is not yet (waiting for a build on another thread); `warnings`
    // gets the mesh's (Model's construction says them once; each bake repeats them).
    std::shared_ptr<const Model> get(const RunControl& control, std::vector<std::string>* warnings = nullptr);
    // As get, but none while another thread builds it: the GUI thread does not wait for a bake's build.
    std::shared_ptr<const Model> getWithoutWaiting(const RunControl& control);

private:
    std::shared_ptr<const Model> built(const RunControl& control, std::vector<std::string>* warnings); // mutex_ held

    std::mutex mutex_; // held while building
    std::shared_ptr<const Mesh> mesh_;
    std::shared_ptr<const Model> model_;
    std::vector<std::string> warnings_;
};

// How a bake runs, beside what it bakes (BakeSettings): the place for a device choice.
struct GenerationOptions {
    int threads = 0; // 0: all cores
};

// A bake running on a background thread: progress, cancel, result.
class Generation : public BackgroundTask {
public:
    ~Generation() { stop(); }
    // Starts baking the scene's model (shared, so it outlives the job; built by the job if it is not yet).
    void start(std::shared_ptr<MeshModel> model, const BakeSettings& settings, const GenerationOptions& options);
    // When the job has finished since the last call: hands over the result (empty on failure,
    // with the message in `error`) and the warnings of the mesh and the bake (one line each,
    // naming the mesh), and returns true. False while running or idle.
    bool collect(std::optional<BakeResult>& result, std::string& error, std::vector<std::string>& warnings, double& seconds);

private:
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

class FieldLoad : public BackgroundTask {
public:
    ~FieldLoad() { stop(); }
    // Starts reading `path` (stopping a load still running); `textureLimit` is the largest 3D
    // texture, for a band field's resampling.
    void start(const std::string& path, int threads, int textureLimit);
    const std::string& path() const { return path_; }
    // The GUI test's stand-in for a slow disk (SDFGEN_DEBUG_READ_DELAY_MS): each progress report
    // of a load waits this long (less when cancelled meanwhile).
    int delayPerReportMs = 0;
    // When the load has finished since the last call: hands over the field (empty on failure,
    // with the message in `error`: "cancelled" when cancelled) and returns true.
    bool collect(std::optional<LoadedField>& result, std::string& error);

private:
    std::string path_;
    std::optional<LoadedField> result_; // written by the worker, read once it has finished
};

// What a comparison found: the figures of `sdfgen compare` and where the signs differ.
struct ComparedFields {
    FieldDifference difference;
    std::vector<std::size_t> signDifferences; // indices into the values of `grid`
    Grid grid;
};

// The field shown compared with a field file, on a background thread: the file is read (with
// progress and Cancel), then compared. The field shown is shared, so it outlives the job.
class FieldComparison : public BackgroundTask {
public:
    ~FieldComparison() { stop(); }
    // A band field (`band`) is compared by its own samples, made dense on the job's thread. A
    // comparison still running is cancelled (it stops within a block of the file or a million
    // samples) and this one takes its place.
    void start(std::shared_ptr<const Field> shown, std::shared_ptr<const SparseField> band, const std::string& path, int threads);
    const std::string& path() const { return path_; }
    // When the comparison has finished since the last call: hands over what it found (empty on
    // failure, with the message in `error`) and returns true.
    bool collect(std::optional<ComparedFields>& result, std::string& error);

private:
    std::string path_;
    std::optional<ComparedFields> result_; // written by the worker, read once it has finished
};

} // namespace sdfgen::app
