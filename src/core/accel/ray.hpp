#pragma once
#include "core/simd/simd.hpp"

#include <glm/vec3.hpp>
#include <glm/geometric.hpp>

namespace sdfgen {

// A triangle in the form Möller–Trumbore wants: one corner and the two edges leaving it.
struct PreparedTriangle {
    glm::vec3 v0, e1, e2;
};

inline PreparedTriangle prepareTriangle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    return {a, b - a, c - a};
}

// Möller–Trumbore for one direction `d` shared by one ray (Real = float) or eight rays with
// different origins (Real = simd::f8). Returns the mask of rays that hit the triangle at a
// distance 0 <= t < tMax (edges and corners count as hits) and writes their t. `backFace` tells
// whether d runs along the face normal (counter-clockwise winding), i.e. the ray leaves the solid.
template <class Real>
inline auto intersectTriangle(const Real& ox, const Real& oy, const Real& oz, const glm::vec3& d,
                              const PreparedTriangle& tri, const Real& tMax, Real& t, bool& backFace) {
    // Everything that depends on the direction alone is computed once for all rays.
    const glm::vec3 p = glm::cross(d, tri.e2);
    const float det = glm::dot(tri.e1, p);
    backFace = det < 0.0f;
    const float invDet = 1.0f / det;  // det == 0 (ray parallel to the plane) gives inf/NaN: no hit below
    const Real tx = ox - tri.v0.x, ty = oy - tri.v0.y, tz = oz - tri.v0.z;
    const Real u = (tx * p.x + ty * p.y + tz * p.z) * invDet;
    const Real qx = ty * tri.e1.z - tz * tri.e1.y;
    const Real qy = tz * tri.e1.x - tx * tri.e1.z;
    const Real qz = tx * tri.e1.y - ty * tri.e1.x;
    const Real v = (d.x * qx + d.y * qy + d.z * qz) * invDet;
    t = (tri.e2.x * qx + tri.e2.y * qy + tri.e2.z * qz) * invDet;
    return (u >= 0.0f) & (v >= 0.0f) & (u + v <= 1.0f) & (t >= 0.0f) & (t < tMax);
}

} // namespace sdfgen
