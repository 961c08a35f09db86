#pragma once
#include <atomic>
#include <functional>

namespace sdfgen {

// How long-running work is run and watched: thread count, progress reports and cancellation.
struct RunControl {
    int threads = 0; // 0 = all hardware threads
    // Called with the fraction done (0..1), from worker threads but never concurrently.
    std::function<void(double)> progress;
    // When set and raised, the work stops soon and throws Cancelled.
    const std::atomic<bool>* cancel = nullptr;

    // The same control with progress mapped into [from, to] of the whole: one phase of a longer job.
    RunControl phase(double from, double to) const;
};

} // namespace sdfgen
