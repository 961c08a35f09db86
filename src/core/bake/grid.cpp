#include "sdfgen/grid.hpp"
#include "sdfgen/bake.hpp"
#include "sdfgen/error.hpp"
#include "core/runtime/memory.hpp"
#include "core/mesh/sample_positions.hpp"

#include <glm/common.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <unistd.h>

namespace sdfgen {

std::uint64_t physicalMemoryBytes() {
    const long pages = sysconf(_SC_PHYS_PAGES);
    const long pageSize = sysconf(_SC_PAGESIZE);
    return pages > 0 && pageSize > 0 ? std::uint64_t(pages) * std::uint64_t(pageSize) : 0;
}

std::vector<double> sampleAxes(const Mesh& mesh, const Grid& grid) {
    std::vector<double> axes;
    axes.reserve(std::size_t(grid.dims.x) + std::size_t(grid.dims.y) + std::size_t(grid.dims.z));
    for (int i = 0; i < grid.dims.x; ++i) axes.push_back(localPosition(mesh, grid, i, 0, 0).x);
    for (int j = 0; j < grid.dims.y; ++j) axes.push_back(localPosition(mesh, grid, 0, j, 0).y);
    for (int k = 0; k < grid.dims.z; ++k) axes.push_back(localPosition(mesh, grid, 0, 0, k).z);
    return axes;
}

Grid gridAround(const WorldBounds& bounds, int res, double padding) {
    if (res < 1) throw Error("grid resolution must be at least 1 (got " + std::to_string(res) + ")");
    if (!(padding >= 0.0) || !std::isfinite(padding)) {
        throw Error("padding must be a finite number >= 0 (got " + std::to_string(padding) + ")");
    }
    const glm::dvec3 extent = bounds.extent();
    const double longest = std::max(extent.x, std::max(extent.y, extent.z));
    if (!(longest > 0.0)) throw Error("the mesh has no extent: all vertices coincide");
    const glm::dvec3 pad(padding * longest);
    const glm::dvec3 paddedExtent = extent + 2.0 * pad;
    const double paddedLongest = std::max(paddedExtent.x, std::max(paddedExtent.y, paddedExtent.z));
    // Distances are stored as float: a grid beyond float range cannot hold them.
    constexpr double kLargestGrid = 1e37;
    if (!std::isfinite(paddedLongest) || paddedLongest > kLargestGrid) {
        char message[256];
        std::snprintf(message, sizeof(message),
                      "the mesh is %.3g across; with padding %g its grid would be %.3g across, beyond the %.0e that "
                      "single-precision distances can hold: scale the mesh nearer to unit size",
                      longest, padding, paddedLongest, kLargestGrid);
        throw Error(message);
    }

    Grid grid;
    grid.origin = bounds.min - pad;
    const double voxel = paddedLongest / res;
    grid.voxel = voxel;
    for (int a = 0; a < 3; ++a) {
        // The longest axis gets exactly res voxels; the 1e-9 keeps exact multiples from rounding up.
        const double cells = std::ceil(double(paddedExtent[a]) / voxel - 1e-9);
        grid.dims[a] = int(std::clamp(cells, 1.0, double(res)));
    }
    return grid;
}

Grid makeGrid(const WorldBounds& bounds, int res, double padding) {
    const Grid grid = gridAround(bounds, res, padding);
    const double samples = double(grid.dims.x) * double(grid.dims.y) * double(grid.dims.z);
    const double bytes = samples * sizeof(float);
    const std::uint64_t memory = physicalMemoryBytes();
    if (memory > 0 && bytes > double(memory)) {
        throw Error("grid " + std::to_string(grid.dims.x) + "x" + std::to_string(grid.dims.y) + "x" +
                    std::to_string(grid.dims.z) + " needs " + std::to_string(std::llround(std::min(bytes / (1 << 20), 9e18))) +
                    " MiB but this machine has " + std::to_string(memory >> 20) + " MiB");
    }
    return grid;
}

Grid bakeGrid(const WorldBounds& bounds, const BakeSettings& settings) {
    return settings.band > 0 ? gridAround(bounds, settings.res, settings.padding) : makeGrid(bounds, settings.res, settings.padding);
}

} // namespace sdfgen
