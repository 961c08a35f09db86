#include "nearest.hpp"

#include "core/runtime/parallel.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/triangle.hpp"

#include <glm/geometric.hpp>

#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace sdfgen::python {

namespace {

// The closest point's feature as the corners that span it (first) and its weights on them.
struct Feature {
    std::array<int, 3> order; // corner positions within the triangle, spanning corners first
    int size;
};

Feature featureOf(TriangleFeature feature) {
    switch (feature) {
    case TriangleFeature::VertexA: return {{0, 1, 2}, 1};
    case TriangleFeature::VertexB: return {{1, 2, 0}, 1};
    case TriangleFeature::VertexC: return {{2, 0, 1}, 1};
    case TriangleFeature::EdgeAB: return {{0, 1, 2}, 2};
    case TriangleFeature::EdgeBC: return {{1, 2, 0}, 2};
    case TriangleFeature::EdgeCA: return {{2, 0, 1}, 2};
    case TriangleFeature::Face: break;
    }
    return {{0, 1, 2}, 3};
}

} // namespace

void measureNearest(const Model& model, const double* points, std::size_t count, const double* vertices,
                    std::optional<SignMethod> sign, const NearestTerms& out, const RunControl& control) {
    const Mesh& mesh = model.mesh();
    std::vector<std::int64_t> triangle(count);
    std::vector<float> signedDistance(sign ? count : 0);
    // The query's gradient orients the face normal given at distance 0 (reversed where auto finds
    // the mesh inside out), the one every front end gives there.
    std::vector<double> queryGradient(sign && out.gradient ? 3 * count : 0);
    PointQueryOutputs query;
    query.triangle = triangle.data();
    if (sign) query.signedDistance = signedDistance.data();
    if (!queryGradient.empty()) query.gradient = queryGradient.data();
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
                glm::dvec3 g;
                if (length > 0.0) {
                    g = (p - closest.point) * (side / length);
                } else if (sign && !vertices) { // on the surface: the query's own (the mesh's face normal, oriented)
                    g = glm::dvec3(queryGradient[3 * i], queryGradient[3 * i + 1], queryGradient[3 * i + 2]);
                } else { // the face normal of the given corners (oriented as the query's, when signed)
                    g = glm::normalize(glm::cross(corner[1] - corner[0], corner[2] - corner[0]));
                    if (sign) {
                        const glm::dvec3 oriented(queryGradient[3 * i], queryGradient[3 * i + 1], queryGradient[3 * i + 2]);
                        if (glm::dot(g, oriented) < 0.0) g = -g;
                    }
                }
                for (int a = 0; a < 3; ++a) out.gradient[3 * i + std::size_t(a)] = g[a];
            }
            if (out.closest) {
                const glm::dvec3 c = vertices ? closest.point : mesh.toWorld(closest.point);
                for (int a = 0; a < 3; ++a) out.closest[3 * i + std::size_t(a)] = c[a];
            }
            if (out.triangle) out.triangle[i] = triangle[i];
            if (out.corners || out.weights || out.featureSize || out.barycentric) {
                const glm::dvec3 weights = barycentricOf(closest, corner[0], corner[1], corner[2]);
                const Feature feature = featureOf(closest.feature);
                for (int k = 0; k < 3; ++k) {
                    const int at = feature.order[std::size_t(k)];
                    if (out.corners) out.corners[3 * i + std::size_t(k)] = corners[at];
                    if (out.weights) out.weights[3 * i + std::size_t(k)] = weights[at];
                    if (out.barycentric) out.barycentric[3 * i + std::size_t(k)] = weights[k];
                }
                if (out.featureSize) out.featureSize[i] = std::int8_t(feature.size);
            }
        }
    });
}

void scatterVertexGradient(const std::int64_t* corners, const double* weights, const double* gradient, const double* upstream,
                           std::size_t count, double* vertexGradient, std::size_t vertexCount) {
    for (std::size_t i = 0; i < count; ++i) {
        for (std::size_t k = 0; k < 3; ++k) {
            const std::int64_t corner = corners[3 * i + k];
            if (corner < 0 || std::uint64_t(corner) >= vertexCount) throw Error("vertex gradient: corner " + std::to_string(corner) + " out of range");
            const double weighted = weights[3 * i + k] * upstream[i];
            for (std::size_t a = 0; a < 3; ++a) vertexGradient[3 * std::size_t(corner) + a] += weighted * -gradient[3 * i + a];
        }
    }
}

void runSideBySide(std::size_t count, const std::function<bool(std::size_t)>& alone,
                   const std::function<void(std::size_t, const RunControl&)>& work, const RunControl& control) {
    std::vector<std::size_t> together, apart; // asked once: work may change what alone() reads
    for (std::size_t i = 0; i < count; ++i) (alone(i) ? apart : together).push_back(i);
    // Warnings are collected per item and passed on from the calling thread (RunControl::warn is
    // never called concurrently).
    std::vector<std::vector<std::string>> warnings(count);
    auto controlOf = [&](std::size_t i, int threads) {
        RunControl part = quiet(control);
        part.threads = threads;
        part.warn = [&warnings, i](const std::string& warning) { warnings[i].push_back(warning); };
        return part;
    };
    parallelFor(together.size(), quiet(control), [&](std::size_t k) { work(together[k], controlOf(together[k], 1)); });
    for (std::size_t i : apart) work(i, controlOf(i, control.threads));
    if (control.warn) {
        for (const std::vector<std::string>& itemWarnings : warnings) {
            for (const std::string& warning : itemWarnings) control.warn(warning);
        }
    }
}

void measureNearestBatch(const std::vector<NearestJob>& jobs, std::optional<SignMethod> sign, const RunControl& control) {
    // From this many points a job's own parallel query keeps the pool busy.
    constexpr std::size_t kJobAlone = 16384;
    runSideBySide(
        jobs.size(), [&](std::size_t j) { return jobs[j].count >= kJobAlone; },
        [&](std::size_t j, const RunControl& part) {
            const NearestJob& job = jobs[j];
            measureNearest(*job.model, job.points, job.count, job.vertices, sign, job.out, part);
        },
        control);
}

} // namespace sdfgen::python
