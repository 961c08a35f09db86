#pragma once
#include "sdfgen/mesh.hpp"

#include <glm/vec3.hpp>
#include <cstddef>
#include <cstdint>

namespace sdfgen {

// A dense grid of cubic voxels; samples sit at voxel centres origin + (i + 1/2, j + 1/2, k + 1/2) * voxel
// and are stored x fastest, then y, then z.
struct Grid {
    glm::vec3 origin{0.0f};
    float voxel = 1.0f;
    glm::ivec3 dims{0};

    std::size_t sampleCount() const { return std::size_t(dims.x) * std::size_t(dims.y) * std::size_t(dims.z); }
    std::size_t index(int i, int j, int k) const {
        return (std::size_t(k) * std::size_t(dims.y) + std::size_t(j)) * std::size_t(dims.x) + std::size_t(i);
    }
    glm::vec3 sample(int i, int j, int k) const {
        return origin + glm::vec3(float(i) + 0.5f, float(j) + 0.5f, float(k) + 0.5f) * voxel;
    }
};

// The grid around `bounds` padded on every side by padding * longest extent, with `res` voxels
// along the longest padded axis. Throws Error for res < 1, negative or non-finite padding, a
// mesh with no extent, or a grid that would not fit in this machine's memory.
Grid makeGrid(const Bounds& bounds, int res, float padding);

// Bytes of physical memory on this machine (0 when unknown).
std::uint64_t physicalMemoryBytes();

} // namespace sdfgen
