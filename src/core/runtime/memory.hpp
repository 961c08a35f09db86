#pragma once
#include "core/runtime/parallel.hpp"
#include "sdfgen/memory.hpp"
#include "sdfgen/run_control.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace sdfgen {

// Hands the whole pages within [data, data + bytes) back to the system: memory whose contents
// are no longer needed while its owner lives on a little (they read as zeros afterwards).
void releasePages(void* data, std::size_t bytes);

// Asks the system to back the whole 2 MiB pages within [data, data + bytes) with transparent huge
// pages as they are first touched, for a buffer of kHugePagesFrom bytes or more (a hint: ignored
// where refused or unsupported). Where the kernel gives huge pages only to memory that asks
// (transparent_hugepage "madvise"), a large field otherwise faults once per 4 KiB page, which on
// a virtual machine costs a bake several percent. The sdfgen executable's operator new does this
// for all its large blocks (src/cli/huge_pages.cpp); this does it for the library's fields and
// bricks in any process (Python, C++ programs), whose allocator the library leaves alone.
constexpr std::size_t kHugePagesFrom = std::size_t(32) << 20;
void adviseHugePages(void* data, std::size_t bytes);

// `values` grown to `count` zeros in chunks, checking Cancel between them: zeroing a large grid
// takes seconds, which a cancelled bake would otherwise wait out. A large one on huge pages.
template <typename T>
void zeroFilled(std::vector<T>& values, std::size_t count, const RunControl& control) {
    constexpr std::size_t kChunk = std::size_t(1) << 20;
    values.reserve(count);
    adviseHugePages(values.data(), count * sizeof(T));
    for (std::size_t filled = values.size(); filled < count; filled = values.size()) {
        throwIfCancelled(control);
        values.resize(std::min(count, filled + kChunk));
    }
}

// Has the system back the whole pages within [data, data + bytes) with memory now, from
// control.threads threads (a buffer's first touch, otherwise one page fault at a time on one
// thread); where the system cannot, they are backed when first written, as usual.
void populatePages(void* data, std::size_t bytes, const RunControl& control);

// The memory limits on a process's control groups (Slurm's task/cgroup, container runtimes): the
// lowest limit on its cgroup or any parent, and the least room left under any of them (limit minus
// usage). cgroup v2 (memory.max, memory.current; mounted at `root`, or at root/unified beside v1)
// and v1 (root/memory: memory.limit_in_bytes, memory.usage_in_bytes). `cgroupFile` is the
// process's /proc/self/cgroup. Each is UINT64_MAX when no limit is found.
struct CgroupMemory {
    std::uint64_t limit = UINT64_MAX;
    std::uint64_t room = UINT64_MAX;
};
CgroupMemory cgroupMemory(const std::string& cgroupFile = "/proc/self/cgroup", const std::string& root = "/sys/fs/cgroup");

// Hands the pages of freed heap memory back to the system (glibc keeps them resident for reuse):
// called between phases, so that one phase's scratch does not add to the next one's peak.
void releaseFreedMemory();

} // namespace sdfgen
