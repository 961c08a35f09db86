#pragma once
#include "sdfgen/mesh.hpp"

#include <glm/vec3.hpp>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace sdfgen {

// A dense grid of cubic voxels in world coordinates; samples sit at voxel centres
// origin + (i + 1/2, j + 1/2, k + 1/2) * voxel and are stored x fastest, then y, then z.
struct Grid {
    glm::dvec3 origin{0.0}; // the grid's minimum corner
    double voxel = 1.0;     // edge of the cubic voxels
    glm::ivec3 dims{0};

    std::size_t sampleCount() const { return std::size_t(dims.x) * std::size_t(dims.y) * std::size_t(dims.z); }
    std::size_t index(int i, int j, int k) const {
        return (std::size_t(k) * std::size_t(dims.y) + std::size_t(j)) * std::size_t(dims.x) + std::size_t(i);
    }
    // World position of sample (i, j, k). Every generator and point query computes sample positions
    // with this one expression, so a query at a sample's position returns exactly its value.
    glm::dvec3 position(int i, int j, int k) const {
        return origin + glm::dvec3(double(i) + 0.5, double(j) + 0.5, double(k) + 0.5) * voxel;
    }
};

// Sample (i, j, k) of `grid` in `mesh`'s local coordinates: the one expression every generator and
// point query uses, so that they agree to the last bit.
inline glm::dvec3 localPosition(const Mesh& mesh, const Grid& grid, int i, int j, int k) {
    return mesh.toLocal(grid.position(i, j, k));
}

// The samples' local coordinates per axis: x per i, then y per j, then z per k (dims.x + dims.y +
// dims.z values). localPosition is componentwise, so sample (i, j, k) is (axes[i], axes[dims.x + j],
// axes[dims.x + dims.y + k]) to the bit, without its three divisions per use.
std::vector<double> sampleAxes(const Mesh& mesh, const Grid& grid);

// The grid around `bounds` padded on every side by padding * longest extent, with `res` voxels
// along the longest padded axis. Throws Error for res < 1, negative or non-finite padding, a
// mesh with no extent, or a grid that would not fit in this machine's memory.
Grid makeGrid(const WorldBounds& bounds, int res, double padding);

// Bytes of physical memory on this machine (0 when unknown).
std::uint64_t physicalMemoryBytes();

} // namespace sdfgen
