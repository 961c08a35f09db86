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

    // Eight neighbouring samples, a 2x2x2 block, trace each direction together as a packet:
    // parallel rays less than two voxels apart take nearly the same path through the tree. Each
    // lane's answer is the one it would get alone (the traversal order depends on the direction
    // only), so the blocking changes speed, not the field. One work item is a row of blocks.
    const int blocksX = (nx + 1) / 2, blocksY = (grid.dims.y + 1) / 2, blocksZ = (grid.dims.z + 1) / 2;
    parallelFor(std::size_t(blocksY) * std::size_t(blocksZ), control, [&](std::size_t blockRow) {
        const int j0 = 2 * int(blockRow % std::size_t(blocksY));
        const int k0 = 2 * int(blockRow / std::size_t(blocksY));
        for (int bx = 0; bx < blocksX; ++bx) {
            const int i0 = 2 * bx;
            RayPacket packet;
            i8 active = splat(0);
            glm::ivec3 sample[8];
            for (int lane = 0; lane < 8; ++lane) {
                const glm::ivec3 s(i0 + (lane & 1), j0 + ((lane >> 1) & 1), k0 + (lane >> 2));
                const bool inGrid = s.x < nx && s.y < grid.dims.y && s.z < grid.dims.z;
                sample[lane] = inGrid ? s : glm::ivec3(i0, j0, k0); // idle lanes trace the block's first sample
                const glm::vec3 p(localPosition(mesh, grid, sample[lane].x, sample[lane].y, sample[lane].z));
                packet.ox[lane] = p.x;
                packet.oy[lane] = p.y;
                packet.oz[lane] = p.z;
                active[lane] = inGrid ? -1 : 0;
            }

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
            for (int lane = 0; lane < 8; ++lane) {
                if (!active[lane]) continue;
                const std::size_t index = grid.index(sample[lane].x, sample[lane].y, sample[lane].z);
                if (hits[lane] == 0) {
                    const glm::vec3 p(packet.ox[lane], packet.oy[lane], packet.oz[lane]);
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
