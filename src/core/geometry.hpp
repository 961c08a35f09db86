#pragma once
// Exact-as-possible geometric primitives in double precision, shared by the generators, the sign
// methods and the reference (brute-force) mode.
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <cstdint>

namespace sdfgen {

// Which part of a triangle (a, b, c) holds the closest point.
enum class TriangleFeature : std::uint8_t { Face, EdgeAB, EdgeBC, EdgeCA, VertexA, VertexB, VertexC };

struct ClosestPoint {
    glm::dvec3 point;
    double distanceSquared;
    TriangleFeature feature;
};

// The point of triangle (a, b, c) nearest to p, by Voronoi regions (Ericson, Real-Time Collision
// Detection, 5.1.5). Degenerate triangles are handled (the nearest edge or vertex wins).
ClosestPoint closestPointOnTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c);

// Signed solid angle of triangle (a, b, c) seen from p, in [-2π, 2π]: positive when p sees the
// triangle's back (p is on the side its counter-clockwise normal points away from), so that
// summing over a closed outward surface gives 4π inside and 0 outside (Van Oosterom & Strackee 1983).
double solidAngle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c);

// Twice the signed area of the 2D triangle (0, u, v) as `area`, and its sign with ties broken by a
// fixed symbolic perturbation: the sign flips when u and v are swapped and is 0 only when u == v.
// Points on a shared edge therefore fall into exactly one of the two triangles.
int orientation2d(const glm::dvec2& u, const glm::dvec2& v, double& area);

// Whether q lies in the 2D triangle (a, b, c) under that tie-breaking rule; on success `orientation`
// is the triangle's orientation (+1 counter-clockwise, -1 clockwise) and `weights` q's barycentric
// coordinates. Triangles with zero area contain nothing.
bool pointInTriangle2d(const glm::dvec2& q, const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c,
                       int& orientation, glm::dvec3& weights);

} // namespace sdfgen
