#pragma once
// Progress and Cancel for the field readers: each counts the bytes it has read of the whole through
// a ReadWatch, which reports them through RunControl::progress and stops the read (Cancelled) soon
// after RunControl::cancel is raised.
#include "sdfgen/run_control.hpp"

#include <cstdint>

namespace sdfgen {

class ReadWatch {
public:
    ReadWatch(const RunControl& control, std::uint64_t totalBytes) : control_(control), total_(totalBytes) {}
    // Counts `bytes` more read; throws Cancelled when the control's cancel flag is raised. Reports
    // about every 1% (and at the end), never backwards.
    void advance(std::uint64_t bytes);

private:
    const RunControl& control_;
    std::uint64_t total_;
    std::uint64_t done_ = 0;
    std::uint64_t reported_ = 0;
};

} // namespace sdfgen
