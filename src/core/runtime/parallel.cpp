#include "core/runtime/parallel.hpp"
#include "sdfgen/error.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <mutex>
#include <string>

namespace sdfgen {

RunControl RunControl::phase(double from, double to) const {
    RunControl part = *this;
    if (progress) part.progress = [report = progress, from, to](double f) { report(from + (to - from) * f); };
    return part;
}

int arenaSize(const RunControl& control) {
    if (control.threads < 0 || control.threads > kMaxThreads) {
        throw Error("threads must be from 0 (all cores) to " + std::to_string(kMaxThreads) + ", not " + std::to_string(control.threads));
    }
    return control.threads > 0 ? control.threads : tbb::task_arena::automatic;
}

void throwIfCancelled(const RunControl& control) {
    if (control.cancel && control.cancel->load(std::memory_order_relaxed)) throw Cancelled();
}

ProgressCounter::ProgressCounter(const RunControl& control, std::size_t total)
    : control_(control), total_(std::max<std::size_t>(total, 1)), step_(std::max<std::size_t>(1, total / 200)) {}

void ProgressCounter::checkCancel() const {
    if (control_.cancel && control_.cancel->load(std::memory_order_relaxed)) throw Cancelled();
}

void ProgressCounter::add(std::size_t units) {
    checkCancel();
    const std::size_t before = done_.fetch_add(units, std::memory_order_relaxed), after = before + units;
    if (!control_.progress || before / step_ == after / step_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    if (after <= reported_) return; // a later count was reported first
    reported_ = after;
    control_.progress(std::min(1.0, double(after) / double(total_)));
}

void ProgressCounter::finish() {
    if (control_.progress) control_.progress(1.0);
}

RunControl quiet(const RunControl& control) {
    RunControl part = control;
    part.progress = nullptr;
    return part;
}

void parallelFor(std::size_t count, const RunControl& control, const std::function<void(std::size_t)>& body) {
    std::atomic<std::size_t> finished{0};
    std::atomic<bool> stopped{false};
    std::mutex progressMutex;
    std::size_t reported = 0; // under progressMutex: reports never run backwards
    // About 200 reports in all: enough for a smooth bar, few enough to cost nothing.
    const std::size_t reportEvery = std::max<std::size_t>(1, count / 200);
    auto cancelled = [&] { return control.cancel && control.cancel->load(std::memory_order_relaxed); };

    tbb::task_arena arena(arenaSize(control));
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 1), [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t i = range.begin(); i != range.end(); ++i) {
                if (stopped.load(std::memory_order_relaxed)) return;
                if (cancelled()) {
                    stopped = true;
                    return;
                }
                body(i);
                const std::size_t done = finished.fetch_add(1, std::memory_order_relaxed) + 1;
                if (control.progress && done % reportEvery == 0 && progressMutex.try_lock()) {
                    if (done > reported) {
                        reported = done;
                        control.progress(double(done) / double(count));
                    }
                    progressMutex.unlock();
                }
            }
        });
    });
    if (stopped || cancelled()) throw Cancelled();
    if (control.progress) control.progress(1.0);
}

void parallelInvoke(const RunControl& control, const std::function<void()>& first, const std::function<void()>& second) {
    const int size = arenaSize(control);
    if (size == 1) {
        first();
        second();
        return;
    }
    tbb::task_arena arena(size);
    arena.execute([&] { tbb::parallel_invoke(first, second); });
}

} // namespace sdfgen
