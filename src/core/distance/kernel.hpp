#pragma once
// The exact distance kernel (core/distance/exact_kernel.inc: the wide tree's searches and the brick
// candidate lists), the ray kernel (core/distance/ray_kernel.inc) and the winding sign's fan kernel
// (core/sign/fan_kernel.inc) are compiled twice, for AVX2 (exact_avx2.cpp, ray_avx2.cpp,
// fan_avx2.cpp) and for baseline x86-64 (SSE2, exact_baseline.cpp, ray_baseline.cpp,
// fan_baseline.cpp), both without fused multiply-adds, so that the two give bit-identical
// answers; the copy to run is chosen once per process from the CPU (AVX2 where it has it). The
// environment variable SDFGEN_SIMD=baseline (or avx2) forces a path; setSimdPath does the same
// from code (tests, benchmarks).
#include "core/distance/exact.hpp"
#include "core/accel/ray_tree.hpp"
#include "core/sign/winding_sign.hpp"

namespace sdfgen {

enum class SimdPath { Baseline, Avx2 };
const char* toString(SimdPath path);

// The path the kernel runs now (chosen at first use when not set).
SimdPath simdPath();
// Whether this binary has the path and this CPU can run it.
bool simdPathAvailable(SimdPath path);
// Runs the kernel on `path` from now on; throws Error when it is not available. Not to be called
// while a search runs on another thread.
void setSimdPath(SimdPath path);

namespace kernel {

// One compiled copy of the kernels.
struct Table {
    SimdPath path;
    NearestField (*computeNearest)(const Mesh&, const WideBvh&, const Grid&, const RunControl&);
    void (*computeExactField)(const Mesh&, const WideBvh&, const Grid&, const MeshTopology*, bool, float*, const RunControl&,
                              const ChannelOutputs*);
    void (*computeExactBricks)(const Mesh&, const WideBvh&, const Grid&, const glm::ivec3*, std::size_t, double, const MeshTopology*, bool,
                               float*, const RunControl&);
    std::vector<std::uint8_t> (*insideByClosestFeature)(const Mesh&, const WideBvh&, const Grid&, const MeshTopology&, bool,
                                                        const RunControl&);
    std::uint32_t (*nearestTriangle)(const WideBvh&, const glm::vec3&, std::uint32_t&);
    std::uint32_t (*nearest)(const WideBvh&, float, float, float, NearestSoFar&);
    // The ray kernel's copy for the same path (core/distance/ray_kernel.inc).
    void (*traceBlock)(const RayTree&, const glm::vec3*, int, RayBlock&);
    // The fan kernel's copy for the same path (core/sign/fan_kernel.inc).
    void (*fanWindings)(const Cap* const*, std::size_t, const glm::dvec3*, int, double*);
};

namespace baseline {
extern const Table table;
}
#if defined(__x86_64__) || defined(__i386__)
namespace avx2 {
extern const Table table;
}
#endif

// The copy for simdPath().
const Table& active();

} // namespace kernel
} // namespace sdfgen
