#pragma once
#include <atomic>
#include <cstddef>
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

// Runs body(i) for i in [0, count) on control.threads threads (TBB), reporting progress as items
// finish and checking the cancel flag between items; throws Cancelled if it was raised. Items must
// be independent so that the result never depends on the thread count or the schedule.
void parallelFor(std::size_t count, const RunControl& control, const std::function<void(std::size_t)>& body);

} // namespace sdfgen
