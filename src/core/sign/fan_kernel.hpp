#pragma once
// The fan kernel (core/sign/fan_kernel.inc), compiled for AVX2 (fan_avx2.cpp) and for baseline
// x86-64 (fan_baseline.cpp): windings[s] = the summed winding number of `count` fans of weight 1
// at points[s], s < n <= kFanPoints, or NaN where a point lies on a fan's edge (no angle). The
// sign stage's own dispatch: the copy for simdPath() (core/simd/path.hpp).
#include "core/simd/path.hpp"

#include <glm/vec3.hpp>
#include <cstddef>

namespace sdfgen {

struct Cap;

namespace fans {
using Kernel = void (*)(const Cap* const* fans, std::size_t count, const glm::dvec3* points, int n, double* windings);
namespace baseline {
void fanWindings(const Cap* const* fans, std::size_t count, const glm::dvec3* points, int n, double* windings);
}
#if defined(__x86_64__) || defined(__i386__)
namespace avx2 {
void fanWindings(const Cap* const* fans, std::size_t count, const glm::dvec3* points, int n, double* windings);
}
#endif

inline Kernel active() {
#if defined(__x86_64__) || defined(__i386__)
    if (simdPath() == SimdPath::Avx2) return avx2::fanWindings;
#endif
    return baseline::fanWindings;
}
} // namespace fans

} // namespace sdfgen
