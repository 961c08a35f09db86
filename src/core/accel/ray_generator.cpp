#include "core/accel/ray_generator.hpp"
#include "core/accel/directions.hpp"
#include "core/accel/ray_tree.hpp"
#include "sdfgen/error.hpp"
#include "core/runtime/parallel.hpp"
#include "core/mesh/sample_positions.hpp"

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
    if (rays < 1) throw Error("rays per sample must be at least 1 (got " + std::to_string(rays) + ")");
    const std::vector<glm::vec3> directions = sphereDirections(rays);
    const int nx = grid.dims.x;

    Field field;
    field.source = mesh.source;
    field.method = "rays";
    field.parameters = {{"rays", std::to_string(rays)}};
    field.grid = grid;
    field.values.resize(grid.sampleCount());

    // Eight neighbouring samples, a 2x2x2 block, trace each direction together as a packet:
    // parallel rays less than two voxels apart take nearly the same path through the tree. The
    // blocks are the same whatever the thread count (and each lane's hits are those of the binary
    // tree's traversal for the block, see core/accel/ray_kernel.inc). One work item is a row of blocks.
    const RayTree rayTree(mesh, tree);
    const rays::TraceKernel traceBlock = rays::activeTrace();
    const int blocksX = (nx + 1) / 2, blocksY = (grid.dims.y + 1) / 2, blocksZ = (grid.dims.z + 1) / 2;
    parallelFor(std::size_t(blocksY) * std::size_t(blocksZ), control, [&](std::size_t blockRow) {
        const int j0 = 2 * int(blockRow % std::size_t(blocksY));
        const int k0 = 2 * int(blockRow / std::size_t(blocksY));
        for (int bx = 0; bx < blocksX; ++bx) {
            const int i0 = 2 * bx;
            RayBlock block;
            glm::ivec3 sample[8];
            for (int lane = 0; lane < 8; ++lane) {
                const glm::ivec3 s(i0 + (lane & 1), j0 + ((lane >> 1) & 1), k0 + (lane >> 2));
                const bool inGrid = s.x < nx && s.y < grid.dims.y && s.z < grid.dims.z;
                sample[lane] = inGrid ? s : glm::ivec3(i0, j0, k0); // idle lanes trace the block's first sample
                const glm::vec3 p(localPosition(mesh, grid, sample[lane].x, sample[lane].y, sample[lane].z));
                block.ox[lane] = p.x;
                block.oy[lane] = p.y;
                block.oz[lane] = p.z;
                block.active[lane] = inGrid ? -1 : 0;
            }
            traceBlock(rayTree, directions.data(), rays, block);
            for (int lane = 0; lane < 8; ++lane) {
                if (!block.active[lane]) continue;
                const std::size_t index = grid.index(sample[lane].x, sample[lane].y, sample[lane].z);
                if (block.hits[lane] == 0) {
                    const glm::vec3 p(block.ox[lane], block.oy[lane], block.oz[lane]);
                    field.values[index] = float(double(farthestCornerDistance(p, mesh.bounds)) * mesh.unit);
                } else {
                    const bool inside = block.backs[lane] > block.hits[lane] - block.backs[lane];
                    const float distance = float(double(block.nearest[lane]) * mesh.unit);
                    field.values[index] = inside ? -distance : distance;
                }
            }
        }
    });
    return field;
}

} // namespace sdfgen
