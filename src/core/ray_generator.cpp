#include "core/ray_generator.hpp"
#include "core/directions.hpp"
#include "sdfgen/error.hpp"
#include "core/parallel.hpp"

#include <glm/geometric.hpp>
#include <chrono>
#include <cmath>
#include <limits>

namespace sdfgen {

namespace {

// Distance from p to the farthest corner of b: an upper bound on the distance to anything in b.
float farthestCornerDistance(const glm::vec3& p, const Bounds& b) {
    const glm::vec3 far = glm::max(glm::abs(p - b.min), glm::abs(p - b.max));
    return glm::length(far);
}

} // namespace

Field generateRayField(const Mesh& mesh, const Bvh& tree, const Grid& grid, int rays, const RunControl& control) {
    using namespace simd;
    if (rays < 1) throw Error("rays per sample must be at least 1 (got " + std::to_string(rays) + ")");
    const std::vector<glm::vec3> directions = sphereDirections(rays);
    const float infinity = std::numeric_limits<float>::infinity();
    const int nx = grid.dims.x;

    Field field;
    field.source = mesh.source;
    field.method = "rays";
    field.parameters = {{"rays", std::to_string(rays)}};
    field.grid = grid;
    field.values.resize(grid.sampleCount());

    // One work item is one x row; within it, eight neighbouring samples trace each direction
    // together as a packet (parallel rays a voxel apart take nearly the same path through the tree).
    const std::size_t rows = std::size_t(grid.dims.y) * std::size_t(grid.dims.z);
    parallelFor(rows, control, [&](std::size_t row) {
        const int j = int(row % std::size_t(grid.dims.y));
        const int k = int(row / std::size_t(grid.dims.y));
        for (int i0 = 0; i0 < nx; i0 += 8) {
            const int lanes = std::min(8, nx - i0);
            RayPacket packet;
            i8 active = splat(0);
            for (int lane = 0; lane < 8; ++lane) {
                packet.ox[lane] = float(localPosition(mesh, grid, i0 + std::min(lane, lanes - 1), j, k).x);
                active[lane] = lane < lanes ? -1 : 0;
            }
            const glm::vec3 rowSample(localPosition(mesh, grid, i0, j, k));
            packet.oy = splat(rowSample.y);
            packet.oz = splat(rowSample.z);

            f8 nearest = splat(infinity);
            i8 hits = splat(0), backs = splat(0);
            i8 decided = ~active; // idle lanes never need a vote
            for (int r = 0; r < rays; ++r) {
                // Once a lane's vote cannot change, only hits closer than its nearest so far matter,
                // which prunes most of the tree; the result is the same as tracing every ray fully.
                packet.direction = directions[std::size_t(r)];
                packet.tMax = select(active, select(decided, nearest, splat(infinity)), splat(-1.0f));
                tree.intersect(packet);
                nearest = select(packet.hit, min(nearest, packet.tMax), nearest);
                const i8 voting = packet.hit & ~decided;
                hits -= voting;  // masks are -1 where true
                backs -= voting & packet.backFace;
                const i8 fronts = hits - backs;
                const i8 remaining = splat(rays - r - 1);
                decided |= (backs > fronts + remaining) | (fronts >= backs + remaining);
            }
            for (int lane = 0; lane < lanes; ++lane) {
                const std::size_t index = grid.index(i0 + lane, j, k);
                if (hits[lane] == 0) {
                    const glm::vec3 p(localPosition(mesh, grid, i0 + lane, j, k));
                    field.values[index] = float(double(farthestCornerDistance(p, mesh.bounds)) * mesh.unit);
                } else {
                    const bool inside = backs[lane] > hits[lane] - backs[lane];
                    const float distance = float(double(nearest[lane]) * mesh.unit);
                    field.values[index] = inside ? -distance : distance;
                }
            }
        }
    });
    return field;
}

} // namespace sdfgen
