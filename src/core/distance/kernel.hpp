#pragma once
// The exact distance kernel (core/distance/exact_kernel.inc: the wide tree's searches and the brick
// candidate lists), compiled for AVX2 (exact_avx2.cpp) and for baseline x86-64 (exact_baseline.cpp):
// this stage's table of copies, the one for simdPath() running (core/simd/path.hpp). The tree's own
// kernels (the nearest-triangle search, the rays) dispatch in core/accel/.
#include "core/distance/exact.hpp"
#include "core/simd/path.hpp"

namespace sdfgen {

namespace kernel {

// One compiled copy of the kernels.
struct Table {
    NearestField (*computeNearest)(const Mesh&, const WideBvh&, const Grid&, const RunControl&);
    void (*computeExactField)(const Mesh&, const WideBvh&, const Grid&, const MeshTopology*, bool, float*, const RunControl&,
                              const ChannelWriter*);
    void (*computeExactBricks)(const Mesh&, const WideBvh&, const Grid&, const glm::ivec3*, std::size_t, double, const MeshTopology*, bool,
                               float*, const RunControl&);
    void (*forEachNearestRow)(const Mesh&, const WideBvh&, const Grid&, const NearestRowStore&, const RunControl&);
    std::uint32_t (*nearestTriangle)(const WideBvh&, const glm::vec3&, std::uint32_t&);
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
