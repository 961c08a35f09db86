#pragma once
// Exact orientation predicates on single-precision points (the mesh's local coordinates), for the
// mesh check: a double evaluation decides whenever its rounding-error bound allows, and otherwise
// the determinant is summed exactly, so the answer is the sign of the true value for every finite
// input.
#include <glm/vec3.hpp>

namespace sdfgen {

// The sign of (b - a) × (c - a) · (d - a), six times the signed volume of tetrahedron abcd: +1 when
// d lies on the side of plane abc that its counter-clockwise normal faces, -1 on the other side, 0
// when the four points are coplanar.
int orient3d(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& d);

// orient3d without the floating-point filter: always the exact sum (what orient3d falls back to).
int orient3dExact(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& d);

// Whether the closed segment pq and the closed triangle abc have a point in common: touching counts
// (an endpoint on the triangle, the segment through an edge or a vertex, a segment in the
// triangle's plane overlapping it). A triangle without area meets nothing here; its edges, tested
// as segments against the other triangle, still find what it touches.
bool segmentMeetsTriangle(const glm::vec3& p, const glm::vec3& q, const glm::vec3& a, const glm::vec3& b,
                          const glm::vec3& c);

} // namespace sdfgen
