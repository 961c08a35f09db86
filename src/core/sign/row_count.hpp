#pragma once
// A point's count of row crossings (crossingsAhead, core/sign/winding_sign.hpp): the predicates
// shared with the bake's row scan, and the count through the wide tree compiled for AVX2
// (row_count_avx2.cpp) and for baseline x86-64 (row_count_baseline.cpp), from
// core/sign/row_count.inc. The sign stage's own dispatch: the copy for simdPath() (core/simd/path.hpp).
#include "core/accel/bvh.hpp"
#include "core/accel/wide_bvh.hpp"
#include "core/mesh/geometry.hpp"
#include "core/simd/path.hpp"
#include "core/sign/winding_sign.hpp"
#include "sdfgen/mesh.hpp"

#include <cmath>
#include <cstdint>
#include <limits>

namespace sdfgen::rows {

using Side = WideBvh::RowSide;

// The orientation of triangle (a, b, c) where the row through p (along +x) crosses it on `side` of
// p, else 0: the predicates and arithmetic of RowCrossings' scan, so that point queries and fans
// measured on their own count what the bake's rows count. Behind: the crossings that are not ahead
// (the same arithmetic, so that each crossing of the row is counted on exactly one side).
template <Side side = Side::Ahead>
inline int crossing(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    int orientation;
    glm::dvec3 w;
    if (!pointInTriangle2d({p.y, p.z}, {a.y, a.z}, {b.y, b.z}, {c.y, c.z}, orientation, w)) return 0;
    const bool ahead = w.x * a.x + w.y * b.x + w.z * c.x > p.x;
    return ahead == (side == Side::Ahead) ? orientation : 0;
}

// The crossings on `side` of p of the triangles that forEachCandidate(x, y, z, visit) hands on (at
// least every triangle whose box the row through p meets on that side), copies of a triangle and
// caps counted with their weight.
template <Side side, class ForEachCandidate>
inline int count(const Mesh& mesh, const Bvh& tree, const WindingCaps& caps, const glm::dvec3& p, ForEachCandidate&& forEachCandidate) {
    // The same line and the same predicates as insideByWinding's row through p, so that a query at a
    // sample's position counts exactly the crossings its row scan counts ahead of it.
    // The row through p is the line at p's own (y, z), in double, as the row scan has it; its float
    // rounding only bounds the tree's walk (a triangle whose float box holds (y, z) holds its
    // rounding), as does x, one float beyond p.x away from the side counted.
    int sum = 0;
    auto add = [&](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, int weight) { sum += crossing<side>(p, a, b, c) * weight; };
    const float x = std::nextafter(float(p.x), side == Side::Ahead ? -std::numeric_limits<float>::infinity()
                                                                   : std::numeric_limits<float>::infinity());
    forEachCandidate(x, float(p.y), float(p.z), [&](std::uint32_t t) {
        add(glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2)), int(tree.copies(t)));
    });
    caps.forEachCapOnRow(p, [&](const Cap& cap) {
        for (std::size_t i = 0; i < cap.loop.size(); ++i) add(cap.loop[(i + 1) % cap.loop.size()], cap.loop[i], cap.centre, cap.weight);
    });
    return sum;
}

using Kernel = int (*)(const Mesh& mesh, const WideBvh& wide, const Bvh& tree, const WindingCaps& caps, const glm::dvec3& p, bool fansClose);
namespace baseline {
int crossingsAhead(const Mesh& mesh, const WideBvh& wide, const Bvh& tree, const WindingCaps& caps, const glm::dvec3& p, bool fansClose);
}
#if defined(__x86_64__) || defined(__i386__)
namespace avx2 {
int crossingsAhead(const Mesh& mesh, const WideBvh& wide, const Bvh& tree, const WindingCaps& caps, const glm::dvec3& p, bool fansClose);
}
#endif

inline Kernel active() {
#if defined(__x86_64__) || defined(__i386__)
    if (simdPath() >= SimdPath::Avx2) return avx2::crossingsAhead;
#endif
    return baseline::crossingsAhead;
}

} // namespace sdfgen::rows
