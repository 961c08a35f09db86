#pragma once
#include "sdfgen/bake.hpp"
#include "sdfgen/grid.hpp"
#include "sdfgen/mesh.hpp"
#include "sdfgen/run_control.hpp"

#include <cstdint>
#include <string>

namespace sdfgen {

class Bvh;

// Hands the whole pages within [data, data + bytes) back to the system: memory whose contents
// are no longer needed while its owner lives on a little (they read as zeros afterwards).
void releasePages(void* data, std::size_t bytes);

// Has the system back the whole pages within [data, data + bytes) with memory now, from
// control.threads threads (a buffer's first touch, otherwise one page fault at a time on one
// thread); where the system cannot, they are backed when first written, as usual.
void populatePages(void* data, std::size_t bytes, const RunControl& control);

// Bytes of physical memory on this machine (0 when unknown).
std::uint64_t physicalMemoryBytes();

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

// Bytes this process may use at most: the physical memory, or less under a cgroup limit (0 when
// nothing is known).
std::uint64_t usableMemoryBytes();

// Bytes this process can still take: MemAvailable from /proc/meminfo, lowered to the room left
// under its cgroups' memory limits; the physical memory when neither is readable (0 when nothing
// is known).
std::uint64_t availableMemoryBytes();

// The peak bytes bake() allocates for this mesh, grid and settings, counting every buffer the
// chosen distance method and sign hold at once (see bake.cpp, exact.cpp, ray_generator.cpp,
// winding_sign.cpp, topology.cpp): per sample, the ray field, the distances, the nearest triangles, the
// inside flags and the result; per triangle and vertex, the topology; for the winding sign, the
// rows' crossings (estimated from the mesh's area projected along x); `onDevice` (the exact
// distances on a compute device), the device's host-side tables (src/gpu/gl_device.cpp: its
// tree's triangles, the pseudonormals, the closed surface's corners) and its per-sample crossing
// counts and sides; for a ray field, its own wide tree; for closest-point searches on the CPU,
// the wide tree (built by the first bake that needs it; counted even when a Model holds it
// already). Auto counts the dearer of its two choices. The binary tree is not counted: it exists
// before the bake. Given the tree, the rows' crossings count each set of exact copies of a
// triangle once (Bvh::copies), as the scan does. The projected area is summed in parallel on
// control.threads threads, in fixed blocks: the same estimate for any count.
std::uint64_t estimateBakeBytes(const Mesh& mesh, const Grid& grid, const BakeSettings& settings, bool onDevice = false,
                                const Bvh* tree = nullptr, const RunControl& control = {});

// Throws Error("grid NXxNYxNZ (method M, sign S) needs about X MiB but only Y MiB of memory is
// available") when the estimate exceeds the available memory.
void checkBakeMemory(const Mesh& mesh, const Bvh& tree, const Grid& grid, const BakeSettings& settings, bool onDevice,
                     const RunControl& control = {});

// "123 MiB", rounded, for messages.
std::string mebibytes(double bytes);

// Hands the pages of freed heap memory back to the system (glibc keeps them resident for reuse):
// called between phases, so that one phase's scratch does not add to the next one's peak.
void releaseFreedMemory();

} // namespace sdfgen
