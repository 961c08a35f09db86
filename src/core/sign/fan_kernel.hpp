#pragma once
// The fan kernels (core/sign/fan_kernel.inc), compiled for AVX-512 (fan_avx512.cpp), AVX2
// (fan_avx2.cpp) and baseline x86-64 (fan_baseline.cpp): the fan kernel, windings[s] = the summed
// winding number of `count` fans of weight 1 at points[s], s < n <= kFanPoints, or NaN where a
// point lies on a fan (onFanTriangle: the caller measures those fans one by one); the fan-terms
// kernel, the expansions of up to kFanPoints fans over one ball; and the fields kernel, those
// expansions without their winding numbers. The sign stage's own dispatch: the copy for
// simdPath() (core/simd/path.hpp).
#include "core/simd/path.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <cmath>
#include <cstddef>

namespace sdfgen {

struct Cap;
struct FanTerms;

namespace fans {
// Whether p lies on a fan triangle, or within rounding of it, given the triangle's factor den +
// i·det seen from p (fanSolidAngle's) and la, lb, lc its corners' distances from p: det ~ 0 (p in
// its plane) and den <= ~0 (p inside or on its border, where the angle jumps by 2π). There the
// angle's side is rounding's choice and may not be the side that the crossings counted along p's
// row took. The slack covers the rounding of det and den (kOnFanSlack, relative) and that of the
// crossing's x in the row scan (about 1e-15 in the mesh's local unit, which kOnFanReach keeps in
// reach near small fans); a point flagged beyond rounding only costs a slower measurement.
constexpr double kOnFanSlack = 1e-10, kOnFanReach = 1e-5;
inline bool onFanTriangle(double det, double den, double la, double lb, double lc) {
    const double slack = kOnFanSlack * (la + kOnFanReach) * (lb + kOnFanReach) * (lc + kOnFanReach);
    return std::fabs(det) <= slack && den <= slack;
}

// How a kernel call's points see a fan. Far: no point is nearer the fan's box than the box is
// across, nor within 1e-12 of it, and the fan has at most kMaxFactors triangles, every corner
// within 1e6 of every point: each factor of a fan triangle (a, b, c) is at least 2.5 |a||b||c|
// (the corners are seen within 60 degrees of each other), so the fan's factors move the product by
// 2^±600 at most. Near: some point may be near the fan, where a factor may come near 0 and a point
// may lie on it; a factor that does not put a point on it (onFanTriangle) is at least that test's
// slack (1e-25: lengths count from kOnFanReach) and at most 5 |a||b||c|, so its factors, whose
// corners are within 1e6 of every point, move the product by 2^±420 at most. Wide: the rest
// (points or corners beyond the distances of any grid in local coordinates, or more factors),
// whose product is rescaled after each factor. Inline: the kernel asks it of every fan.
struct FanReach {
    static constexpr std::size_t kMaxFactors = 5; // the bounds hold for fans of up to that many triangles
    glm::dvec3 lo, hi;                            // the points' box
    FanReach(const glm::dvec3* points, int n) : lo(points[0]), hi(points[0]) {
        for (int s = 1; s < n; ++s) lo = glm::min(lo, points[s]), hi = glm::max(hi, points[s]);
    }
    enum class Seen { Far, Near, Wide };
    // Of a fan with box [capLo, capHi] and `factors` triangles.
    bool wide(const glm::dvec3& capLo, const glm::dvec3& capHi, std::size_t factors) const {
        const glm::dvec3 farthest = glm::max(hi - capLo, capHi - lo);
        return !(glm::dot(farthest, farthest) < 1e12) || factors > kMaxFactors;
    }
    Seen seen(const glm::dvec3& capLo, const glm::dvec3& capHi, std::size_t factors) const {
        if (wide(capLo, capHi, factors)) return Seen::Wide;
        const glm::dvec3 gap = glm::max(glm::max(capLo - hi, lo - capHi), glm::dvec3(0.0)), across = capHi - capLo;
        const double gap2 = glm::dot(gap, gap);
        return gap2 > glm::dot(across, across) && gap2 > 1e-24 ? Seen::Far : Seen::Near;
    }
};

using Kernel = void (*)(const Cap* const* fans, std::size_t count, const glm::dvec3* points, int n, double* windings);
// The fan-terms kernel: ok[f] = fanTerms(*caps[f], centre, reach, out[f]) for f < n <= kFanPoints,
// each cap of at most Cap::kMaxEdges edges, the caps in the lanes of a vector (the same
// operations, so the same answers but for rounding).
using TermsKernel = void (*)(const Cap* const* caps, int n, const glm::dvec3& centre, double reach, FanTerms* out, bool* ok);
// The fields kernel: the fan-terms kernel's terms but the winding number (value 0), for the
// bounds that need only the loops' field (WindingCaps::windingVariation); ok[f] false only where
// the ball reaches an edge (the field is smooth across the fan).
using FieldsKernel = TermsKernel;
// The kernels' own atan2, which both take for their angles, on its own so that each path's copy is
// tested against std::atan2: out[s] = atan2(y[s], x[s]) for s < n, to a few ulps of π, signed
// zeros as std::atan2 takes them.
using AnglesKernel = void (*)(const double* y, const double* x, std::size_t n, double* out);
#define SDFGEN_FAN_KERNELS                                                                                                      \
    void fanWindings(const Cap* const* fans, std::size_t count, const glm::dvec3* points, int n, double* windings);             \
    void fanTerms(const Cap* const* caps, int n, const glm::dvec3& centre, double reach, FanTerms* out, bool* ok);           \
    void fanFields(const Cap* const* caps, int n, const glm::dvec3& centre, double reach, FanTerms* out, bool* ok);          \
    void angles(const double* y, const double* x, std::size_t n, double* out);
namespace baseline {
SDFGEN_FAN_KERNELS
}
#if defined(__x86_64__) || defined(__i386__)
namespace avx2 {
SDFGEN_FAN_KERNELS
}
namespace avx512 {
SDFGEN_FAN_KERNELS
}
#else
namespace avx2 = baseline; // other CPUs build the baseline copy only
namespace avx512 = baseline;
#endif
#undef SDFGEN_FAN_KERNELS

// The copy of a kernel for simdPath().
template <class K>
K forPath(K baseline, K avx2, K avx512) {
    switch (simdPath()) {
    case SimdPath::Avx512: return avx512;
    case SimdPath::Avx2: return avx2;
    default: return baseline;
    }
}
inline Kernel active() { return forPath(baseline::fanWindings, avx2::fanWindings, avx512::fanWindings); }
inline TermsKernel activeTerms() { return forPath(baseline::fanTerms, avx2::fanTerms, avx512::fanTerms); }
inline FieldsKernel activeFields() { return forPath(baseline::fanFields, avx2::fanFields, avx512::fanFields); }
inline AnglesKernel activeAngles() { return forPath(baseline::angles, avx2::angles, avx512::angles); }
} // namespace fans

} // namespace sdfgen
