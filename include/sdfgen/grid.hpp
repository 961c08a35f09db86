#pragma once
#include "sdfgen/mesh.hpp"

#include <glm/vec3.hpp>
#include <cstddef>
#include <cstdint>

namespace sdfgen {

// A dense grid of cubic voxels in world coordinates; samples sit at voxel centres
// origin + (i + 1/2, j + 1/2, k + 1/2) * voxel and are stored x fastest, then y, then z.
struct Grid {
    glm::dvec3 origin{0.0}; // the grid's minimum corner
    double voxel = 1.0;     // edge of the cubic voxels
    glm::ivec3 dims{0};

    // The most samples a grid may have (2^58): the bytes of its values and of every channel (32 per
    // sample) stay far from 64 bits, so no count or size computed from a valid grid wraps.
    static constexpr std::uint64_t kMaxSamples = std::uint64_t(1) << 58;
    // dims.x * dims.y * dims.z computed without overflow; 0 when a dimension is below 1 or the
    // count exceeds kMaxSamples (what every reader, writer and front end checks, through checkGrid
    // and SparseField's constructor, before counting samples or bytes).
    static std::uint64_t checkedSampleCount(const glm::ivec3& dims) {
        if (dims.x < 1 || dims.y < 1 || dims.z < 1) return 0;
        const std::uint64_t xy = std::uint64_t(dims.x) * std::uint64_t(dims.y); // < 2^62
        if (xy > kMaxSamples / std::uint64_t(dims.z)) return 0;
        return xy * std::uint64_t(dims.z);
    }
    // The sample count of a valid grid (see checkedSampleCount).
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

// The grid around `bounds` padded on every side by padding * longest extent, with `res` voxels
// along the longest padded axis. Throws Error for res < 1, negative or non-finite padding, a
// mesh with no extent, or a grid that would not fit in this machine's memory.
Grid makeGrid(const WorldBounds& bounds, int res, double padding);

} // namespace sdfgen
