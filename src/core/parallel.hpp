#pragma once
#include "sdfgen/run_control.hpp"

#include <cstddef>
#include <functional>

namespace sdfgen {

// Runs body(i) for i in [0, count) on control.threads threads (TBB), reporting progress as items
// finish and checking the cancel flag between items; throws Cancelled if it was raised. Items must
// be independent so that the result never depends on the thread count or the schedule.
void parallelFor(std::size_t count, const RunControl& control, const std::function<void(std::size_t)>& body);

} // namespace sdfgen
