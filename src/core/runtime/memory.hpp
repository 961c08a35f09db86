#pragma once
#include "sdfgen/memory.hpp"
#include "sdfgen/run_control.hpp"

#include <cstdint>
#include <string>

namespace sdfgen {

// Hands the whole pages within [data, data + bytes) back to the system: memory whose contents
// are no longer needed while its owner lives on a little (they read as zeros afterwards).
void releasePages(void* data, std::size_t bytes);

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
