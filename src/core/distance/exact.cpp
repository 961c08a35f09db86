// The exact kernel's dispatch (core/distance/kernel.hpp) and the brute-force reference; the kernel itself
// is in exact_kernel.inc.
#include "core/distance/exact.hpp"
#include "core/mesh/geometry.hpp"
#include "core/distance/kernel.hpp"
#include "core/runtime/parallel.hpp"
#include "core/mesh/sample_positions.hpp"
#include "core/accel/topology.hpp"
#include "sdfgen/error.hpp"

#include <glm/geometric.hpp>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace sdfgen {

const kernel::Table& kernel::active() {
#if defined(__x86_64__) || defined(__i386__)
    if (simdPath() >= SimdPath::Avx2) return avx2::table;
#endif
    return baseline::table;
}

NearestField computeNearest(const Mesh& mesh, const WideBvh& tree, const Grid& grid, const RunControl& control) {
    return kernel::active().computeNearest(mesh, tree, grid, control);
}

NearestField computeNearest(const Mesh& mesh, const Bvh& tree, const Grid& grid, const RunControl& control) {
    return computeNearest(mesh, WideBvh(mesh, tree), grid, control);
}

void computeExactField(const Mesh& mesh, const WideBvh& tree, const Grid& grid, const MeshTopology* pseudonormal, bool flipped,
                       float* values, const RunControl& control, const ChannelWriter* channels) {
    kernel::active().computeExactField(mesh, tree, grid, pseudonormal, flipped, values, control, channels);
}

void computeExactBricks(const Mesh& mesh, const WideBvh& tree, const Grid& grid, const glm::ivec3* bricks, std::size_t count,
                        double skipBeyond, const MeshTopology* pseudonormal, bool flipped, float* values, const RunControl& control) {
    kernel::active().computeExactBricks(mesh, tree, grid, bricks, count, skipBeyond, pseudonormal, flipped, values, control);
}

float sampleValue(const Mesh& mesh, const MeshTopology* pseudonormal, bool flipped, const glm::dvec3& p, std::uint32_t t) {
    const ClosestPoint closest =
        closestPointOnTriangle(p, glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2)));
    const float distance = float(std::sqrt(closest.distanceSquared) * mesh.unit);
    const bool inside = pseudonormal && (glm::dot(p - closest.point, pseudonormal->pseudonormal(t, closest.feature)) < 0.0) != flipped;
    return inside ? -distance : distance;
}

float exactSignedSample(const Mesh& mesh, const WideBvh& tree, const MeshTopology& topology, bool flipped, const glm::dvec3& p,
                        std::uint32_t& hint) {
    return sampleValue(mesh, &topology, flipped, p, nearestTriangle(tree, glm::vec3(p), hint));
}

void forEachNearestRow(const Mesh& mesh, const WideBvh& tree, const Grid& grid, const NearestRowStore& store, const RunControl& control) {
    kernel::active().forEachNearestRow(mesh, tree, grid, store, control);
}

std::uint32_t nearestTriangle(const WideBvh& tree, const glm::vec3& p, std::uint32_t& hint) {
    return kernel::active().nearestTriangle(tree, p, hint);
}

Field computeBruteForce(const Mesh& mesh, const Grid& grid, const RunControl& control) {
    Field field;
    field.source = mesh.source;
    field.grid = grid;
    field.values.resize(grid.sampleCount());
    std::vector<glm::dvec3> corners(3 * mesh.triangleCount());
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        for (int c = 0; c < 3; ++c) corners[3 * t + std::size_t(c)] = glm::dvec3(mesh.vertex(t, c));
    }
    const std::size_t rows = std::size_t(grid.dims.y) * std::size_t(grid.dims.z);
    parallelFor(rows, control, [&](std::size_t row) {
        const int j = int(row % std::size_t(grid.dims.y)), k = int(row / std::size_t(grid.dims.y));
        for (int i = 0; i < grid.dims.x; ++i) {
            const glm::dvec3 p = localPosition(mesh, grid, i, j, k);
            double nearest = std::numeric_limits<double>::infinity(), angle = 0.0;
            for (std::size_t c = 0; c < corners.size(); c += 3) {
                nearest = std::min(nearest, closestPointOnTriangle(p, corners[c], corners[c + 1], corners[c + 2]).distanceSquared);
                angle += solidAngle(p, corners[c], corners[c + 1], corners[c + 2]);
            }
            const double distance = std::sqrt(nearest) * mesh.unit;
            field.values[grid.index(i, j, k)] = float(std::fabs(angle / (4.0 * M_PI)) > 0.5 ? -distance : distance);
        }
    });
    return field;
}

} // namespace sdfgen
