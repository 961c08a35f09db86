#include "core/io/read_watch.hpp"
#include "core/runtime/parallel.hpp"

#include <algorithm>

namespace sdfgen {

void ReadWatch::advance(std::uint64_t bytes) {
    throwIfCancelled(control_);
    done_ = std::min(total_, done_ + bytes);
    if (!control_.progress || total_ == 0) return;
    if (done_ == total_ || (done_ - reported_) * 100 >= total_) {
        reported_ = done_;
        control_.progress(double(done_) / double(total_));
    }
}

} // namespace sdfgen
