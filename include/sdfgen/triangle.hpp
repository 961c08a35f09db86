#pragma once
// The point of a triangle nearest to a point, in double: what Model::query measures for each point,
// for callers that measure it again on moved vertices (the Python layer's vertex gradients).
#include <glm/vec3.hpp>
#include <glm/ext/vector_double3.hpp>
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

// The barycentric weights of `closest` (found on triangle (a, b, c)) on a, b and c, from its
// feature: exactly 1 on a vertex, 0 on the corner off an edge, so that only the corners spanning
// the feature carry weight; they sum to 1.
glm::dvec3 barycentricOf(const ClosestPoint& closest, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c);

} // namespace sdfgen
