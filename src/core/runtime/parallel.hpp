#pragma once
#include "sdfgen/run_control.hpp"

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <functional>
#include <mutex>
#include <vector>

namespace sdfgen {

// The size of the TBB arena control.threads asks for (tbb::task_arena::automatic for 0). Throws
// Error for a count below 0 or above kMaxThreads: every arena is made through it.
int arenaSize(const RunControl& control);

// Throws Cancelled when control.cancel is raised: for the start of work that checks no flag of its own.
void throwIfCancelled(const RunControl& control);

// Runs body(i) for i in [0, count) on control.threads threads (TBB), reporting progress as items
// finish and checking the cancel flag between items; throws Cancelled if it was raised. Items must
// be independent so that the result never depends on the thread count or the schedule.
void parallelFor(std::size_t count, const RunControl& control, const std::function<void(std::size_t)>& body);

// Runs two independent jobs at once on control.threads threads (one after the other on one
// thread); each may run parallel loops of its own. Rethrows what either threw.
void parallelInvoke(const RunControl& control, const std::function<void()>& first, const std::function<void()>& second);

// Progress and cancel for work done in units from any number of threads (a serial loop, a tree
// build): about 200 reports in all, never backwards, and Cancelled thrown from add() or
// checkCancel() once the cancel flag is raised.
class ProgressCounter {
public:
    ProgressCounter(const RunControl& control, std::size_t total);
    void add(std::size_t units);
    void checkCancel() const;
    void finish(); // reports 1 (all done)

private:
    const RunControl& control_;
    std::size_t total_, step_;
    std::atomic<std::size_t> done_{0};
    std::mutex mutex_;
    std::size_t reported_ = 0; // under mutex_
};

// A copy of `control` that keeps its threads and cancel flag but reports no progress: for work
// done lazily inside another phase, whose own fractions would run backwards in that phase's bar.
RunControl quiet(const RunControl& control);

} // namespace sdfgen
