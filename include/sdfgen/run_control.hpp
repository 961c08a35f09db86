#pragma once
#include <atomic>
#include <functional>
#include <string>

namespace sdfgen {

// The most worker threads a RunControl may ask for: every front end refuses more (TBB cannot set
// up arenas far larger, and no machine sdfgen runs on has as many cores).
constexpr int kMaxThreads = 1024;

// How long-running work is run and watched: thread count, progress reports, cancellation and
// warnings. Front ends build one before anything long starts (loading a mesh, building its trees)
// and pass it to every call, Model's construction included.
struct RunControl {
    int threads = 0; // 0 = all hardware threads; at most kMaxThreads (Error beyond, or below 0)
    // Called with the fraction done (0..1), from worker threads but never concurrently.
    std::function<void(double)> progress;
    // When set and raised, the work stops soon and throws Cancelled.
    const std::atomic<bool>* cancel = nullptr;
    // Called once per warning (one line that names the file, e.g. "a.obj: dropped 3 zero-area
    // triangles"): what was skipped, doubtful or surprising but did not stop the work. Called from
    // the thread that called the library, never concurrently. Without it warnings are dropped
    // (BakeResult::warnings and Mesh::warnings still hold them).
    std::function<void(const std::string&)> warn;

    // The same control with progress mapped into [from, to] of the whole: one phase of a longer job.
    RunControl phase(double from, double to) const;
};

} // namespace sdfgen
