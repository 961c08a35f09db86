#include "nearest.hpp"

#include "core/mesh/geometry.hpp"
#include "core/runtime/parallel.hpp"

#include <glm/geometric.hpp>

#include <array>
#include <cmath>
#include <vector>

namespace sdfgen::python {

namespace {

// The closest point's feature as the corners that span it (first) and its weights on them.
struct Feature {
    std::array<int, 3> order; // corner positions within the triangle, spanning corners first
    int size;
    glm::dvec3 weights;
};

Feature featureOf(const ClosestPoint& closest, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const glm::dvec3 corner[3] = {a, b, c};
    auto edge = [&](int from, int to) { // closest.point = corner[from] + t (corner[to] - corner[from])
        const glm::dvec3 d = corner[to] - corner[from];
        const double t = glm::dot(closest.point - corner[from], d) / glm::dot(d, d);
        return Feature{{from, to, 3 - from - to}, 2, {1.0 - t, t, 0.0}};
    };
    switch (closest.feature) {
    case TriangleFeature::VertexA: return {{0, 1, 2}, 1, {1.0, 0.0, 0.0}};
    case TriangleFeature::VertexB: return {{1, 2, 0}, 1, {1.0, 0.0, 0.0}};
    case TriangleFeature::VertexC: return {{2, 0, 1}, 1, {1.0, 0.0, 0.0}};
    case TriangleFeature::EdgeAB: return edge(0, 1);
    case TriangleFeature::EdgeBC: return edge(1, 2);
    case TriangleFeature::EdgeCA: return edge(2, 0);
    case TriangleFeature::Face: break;
    }
    const glm::dvec3 ab = b - a, ac = c - a, aq = closest.point - a;
    const double d00 = glm::dot(ab, ab), d01 = glm::dot(ab, ac), d11 = glm::dot(ac, ac);
    const double d20 = glm::dot(aq, ab), d21 = glm::dot(aq, ac);
    const double denominator = d00 * d11 - d01 * d01;
    const double wb = (d11 * d20 - d01 * d21) / denominator, wc = (d00 * d21 - d01 * d20) / denominator;
    return {{0, 1, 2}, 3, {1.0 - wb - wc, wb, wc}};
}

} // namespace

void measureNearest(const Model& model, const double* points, std::size_t count, const double* vertices,
                    std::optional<SignMethod> sign, const NearestTerms& out, const RunControl& control) {
    const Mesh& mesh = model.mesh();
    std::vector<std::int64_t> triangle(count);
    std::vector<float> signedDistance(sign ? count : 0);
    PointQueryOutputs query;
    query.triangle = triangle.data();
    if (sign) query.signedDistance = signedDistance.data();
    model.query(points, count, query, sign.value_or(SignMethod::Auto), control);

    constexpr std::size_t kBlock = 4096;
    parallelFor((count + kBlock - 1) / kBlock, control, [&](std::size_t block) {
        for (std::size_t i = block * kBlock, end = std::min(count, i + kBlock); i < end; ++i) {
            const glm::uvec3& corners = mesh.triangles[std::size_t(triangle[i])];
            glm::dvec3 p(points[3 * i], points[3 * i + 1], points[3 * i + 2]);
            glm::dvec3 corner[3];
            double unit = 1.0;
            if (vertices) {
                for (int c = 0; c < 3; ++c) {
                    const double* v = vertices + 3 * std::size_t(corners[c]);
                    corner[c] = glm::dvec3(v[0], v[1], v[2]);
                }
            } else { // as Model::query measures: in the local frame, from the float positions
                p = mesh.toLocal(p);
                for (int c = 0; c < 3; ++c) corner[c] = glm::dvec3(mesh.positions[corners[c]]);
                unit = mesh.unit;
            }
            const ClosestPoint closest = closestPointOnTriangle(p, corner[0], corner[1], corner[2]);
            const double length = std::sqrt(closest.distanceSquared);
            const double side = sign && std::signbit(signedDistance[i]) ? -1.0 : 1.0;
            if (out.distance) out.distance[i] = side * (length * unit);
            if (out.gradient) {
                const glm::dvec3 g = length > 0.0 ? (p - closest.point) * (side / length) : glm::dvec3(0.0);
                for (int a = 0; a < 3; ++a) out.gradient[3 * i + std::size_t(a)] = g[a];
            }
            if (out.closest) {
                const glm::dvec3 c = vertices ? closest.point : mesh.toWorld(closest.point);
                for (int a = 0; a < 3; ++a) out.closest[3 * i + std::size_t(a)] = c[a];
            }
            if (out.corners || out.weights || out.featureSize) {
                const Feature feature = featureOf(closest, corner[0], corner[1], corner[2]);
                for (int k = 0; k < 3; ++k) {
                    if (out.corners) out.corners[3 * i + std::size_t(k)] = corners[feature.order[std::size_t(k)]];
                    if (out.weights) out.weights[3 * i + std::size_t(k)] = feature.weights[k];
                }
                if (out.featureSize) out.featureSize[i] = std::int8_t(feature.size);
            }
        }
    });
}

} // namespace sdfgen::python
