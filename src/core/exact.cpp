#include "core/exact.hpp"
#include "core/geometry.hpp"
#include "core/parallel.hpp"
#include "core/topology.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <cmath>
#include <limits>

namespace sdfgen {

namespace {

// Where sample (i, j, k) is, in the coordinates the mesh is stored in. The one place that knows.
glm::vec3 samplePoint(const Grid& grid, int i, int j, int k) { return grid.sample(i, j, k); }

// The exact nearest triangle of every sample: store(index, triangle, closest point in double).
template <class Store>
void forEachNearest(const Mesh& mesh, const Bvh& tree, const Grid& grid, const RunControl& control, const Store& store) {
    using namespace simd;
    const glm::ivec3 dims = grid.dims;
    // A packet is a 2x2x2 block of samples (lane bits: x, y, z), the most compact set of eight;
    // a work item is a column of blocks along x.
    const int blocksY = (dims.y + 1) / 2, blocksZ = (dims.z + 1) / 2;
    parallelFor(std::size_t(blocksY) * std::size_t(blocksZ), control, [&](std::size_t column) {
        const int j0 = 2 * int(column % std::size_t(blocksY));
        const int k0 = 2 * int(column / std::size_t(blocksY));
        i8 previous = splat(-1); // triangles found by the previous block of this column
        for (int i0 = 0; i0 < dims.x; i0 += 2) {
            glm::ivec3 cell[8];
            PointPacket packet;
            for (int lane = 0; lane < 8; ++lane) {
                // Lanes past the grid's end repeat the last sample; they are not stored.
                cell[lane] = glm::min(glm::ivec3(i0 + (lane & 1), j0 + ((lane >> 1) & 1), k0 + (lane >> 2)), dims - 1);
                const glm::vec3 p = samplePoint(grid, cell[lane].x, cell[lane].y, cell[lane].z);
                packet.px[lane] = p.x;
                packet.py[lane] = p.y;
                packet.pz[lane] = p.z;
            }
            packet.bestSquared = splat(std::numeric_limits<float>::infinity());
            packet.triangle = splat(0);
            for (int lane = 0; lane < 8; ++lane) {
                const std::int32_t seed = previous[lane];
                if (seed < 0 || (lane > 0 && seed == previous[lane - 1])) continue;
                const f8 d = tree.distanceSquared(packet.px, packet.py, packet.pz, std::uint32_t(seed));
                const i8 closer = d < packet.bestSquared;
                packet.bestSquared = select(closer, d, packet.bestSquared);
                packet.triangle = select(closer, splat(seed), packet.triangle);
            }
            // The seeds are real triangles, so their distance bounds the search. Widened by a few
            // ulps, a float-rounded seed never hides a triangle that is nearer in exact terms; where
            // nothing beats the bound, the seed stays the answer.
            packet.bestSquared *= 1.000001f;
            tree.nearest(packet);
            previous = packet.triangle;
            for (int lane = 0; lane < 8; ++lane) {
                const glm::ivec3 c = cell[lane];
                if (c != glm::ivec3(i0 + (lane & 1), j0 + ((lane >> 1) & 1), k0 + (lane >> 2))) continue;
                const std::uint32_t t = std::uint32_t(packet.triangle[lane]);
                const glm::dvec3 p(samplePoint(grid, c.x, c.y, c.z));
                const ClosestPoint closest = closestPointOnTriangle(p, glm::dvec3(mesh.vertex(t, 0)),
                                                                    glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2)));
                store(grid.index(c.x, c.y, c.z), t, p, closest);
            }
        }
    });
}

} // namespace

NearestField computeNearest(const Mesh& mesh, const Bvh& tree, const Grid& grid, const RunControl& control) {
    NearestField result;
    result.distance.resize(grid.sampleCount());
    result.triangle.resize(grid.sampleCount());
    forEachNearest(mesh, tree, grid, control, [&](std::size_t index, std::uint32_t t, const glm::dvec3&, const ClosestPoint& closest) {
        result.distance[index] = float(std::sqrt(closest.distanceSquared));
        result.triangle[index] = t;
    });
    return result;
}

void computeExactField(const Mesh& mesh, const Bvh& tree, const Grid& grid, const MeshTopology* pseudonormalSigns,
                       float* values, const RunControl& control) {
    forEachNearest(mesh, tree, grid, control, [&](std::size_t index, std::uint32_t t, const glm::dvec3& p, const ClosestPoint& closest) {
        const float distance = float(std::sqrt(closest.distanceSquared));
        const bool inside = pseudonormalSigns && glm::dot(p - closest.point, pseudonormalSigns->pseudonormal(t, closest.feature)) < 0.0;
        values[index] = inside ? -distance : distance;
    });
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
            const glm::dvec3 p(grid.sample(i, j, k));
            double nearest = std::numeric_limits<double>::infinity(), angle = 0.0;
            for (std::size_t c = 0; c < corners.size(); c += 3) {
                nearest = std::min(nearest, closestPointOnTriangle(p, corners[c], corners[c + 1], corners[c + 2]).distanceSquared);
                angle += solidAngle(p, corners[c], corners[c + 1], corners[c + 2]);
            }
            const double distance = std::sqrt(nearest);
            field.values[grid.index(i, j, k)] = float(angle / (4.0 * M_PI) > 0.5 ? -distance : distance);
        }
    });
    return field;
}

} // namespace sdfgen
