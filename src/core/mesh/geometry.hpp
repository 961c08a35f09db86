#pragma once
// Exact-as-possible geometric primitives in double precision, shared by the generators, the sign
// methods and the reference (brute-force) mode.
#include "sdfgen/triangle.hpp"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <cstdint>

namespace sdfgen {

// Signed solid angle of triangle (a, b, c) seen from p, in [-2π, 2π]: positive when p sees the
// triangle's back (p is on the side its counter-clockwise normal points away from), so that
// summing over a closed outward surface gives 4π inside and 0 outside (Van Oosterom & Strackee 1983).
double solidAngle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c);

// Twice the signed area of the 2D triangle (0, u, v) as `area`, and its sign with ties broken by a
// fixed symbolic perturbation: the sign flips when u and v are swapped and is 0 only when u == v.
// Points on a shared edge therefore fall into exactly one of the two triangles. Inline, as is
// pointInTriangle2d: the winding sign's crossing scan tests every candidate row with them.
inline int orientation2d(const glm::dvec2& u, const glm::dvec2& v, double& area) {
    // The sign comes from comparing the two rounded products, never from their difference: a
    // compiler may fuse the subtraction into an FMA, which would break the exact antisymmetry.
    const double left = u.y * v.x, right = u.x * v.y;
    area = left - right;
    if (left > right) return 1;
    if (left < right) return -1;
    // Exactly zero: perturb symbolically. Antisymmetric in (u, v), so each edge's tie is decided
    // the same way for both triangles sharing it.
    if (v.y > u.y) return 1;
    if (v.y < u.y) return -1;
    if (u.x > v.x) return 1;
    if (u.x < v.x) return -1;
    return 0;
}

// Whether q lies in the 2D triangle (a, b, c) under that tie-breaking rule; on success `orientation`
// is the triangle's orientation (+1 counter-clockwise, -1 clockwise) and `weights` q's barycentric
// coordinates. Triangles with zero area contain nothing.
inline bool pointInTriangle2d(const glm::dvec2& q, const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c,
                              int& orientation, glm::dvec3& weights) {
    const glm::dvec2 pa = a - q, pb = b - q, pc = c - q;
    // orientation2d's sign is the comparison of its two rounded products wherever they differ, so
    // an edge whose left product is certainly above its right and another's certainly below give
    // signs that disagree: q is out, with no tie broken. Compared without branches, this rejects
    // nearly every candidate row of the winding sign's crossing scan at once.
    const double l1 = pb.y * pc.x, r1 = pb.x * pc.y, l2 = pc.y * pa.x, r2 = pc.x * pa.y, l3 = pa.y * pb.x, r3 = pa.x * pb.y;
    if (((l1 > r1) | (l2 > r2) | (l3 > r3)) & ((l1 < r1) | (l2 < r2) | (l3 < r3))) return false;
    double wa, wb, wc;
    const int sa = orientation2d(pb, pc, wa);
    if (sa == 0) return false;
    const int sb = orientation2d(pc, pa, wb);
    if (sb != sa) return false;
    const int sc = orientation2d(pa, pb, wc);
    if (sc != sa) return false;
    const double sum = wa + wb + wc;
    if (sum == 0.0) return false; // zero-area projection: the line grazes the triangle edge-on
    weights = glm::dvec3(wa, wb, wc) / sum;
    orientation = -sa; // orientation2d measures clockwise-positive (u.y v.x - u.x v.y)
    return true;
}

} // namespace sdfgen
