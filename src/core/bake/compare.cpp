#include "sdfgen/compare.hpp"
#include "sdfgen/error.hpp"

#include <glm/common.hpp>
#include <algorithm>
#include <cmath>

namespace sdfgen {

FieldDifference compareFields(const Field& a, const Field& b, double bandVoxels) {
    const Grid& ga = a.grid;
    const Grid& gb = b.grid;
    if (ga.dims != gb.dims) {
        throw Error("the fields have different grids: " + std::to_string(ga.dims.x) + "x" + std::to_string(ga.dims.y) + "x" +
                    std::to_string(ga.dims.z) + " and " + std::to_string(gb.dims.x) + "x" + std::to_string(gb.dims.y) + "x" +
                    std::to_string(gb.dims.z));
    }
    // Same sample positions to within a thousandth of a voxel (text round trips are exact anyway).
    const double tolerance = 1e-3 * ga.voxel;
    const glm::dvec3 offset = glm::abs(ga.origin - gb.origin);
    if (std::max({offset.x, offset.y, offset.z}) > tolerance || std::fabs(ga.voxel - gb.voxel) > tolerance) {
        throw Error("the fields' grids have the same dimensions but different origins or voxel sizes");
    }
    FieldDifference d;
    d.voxel = ga.voxel;
    const double band = bandVoxels * ga.voxel;
    double sum = 0, sumSquares = 0;
    for (std::size_t i = 0; i < a.values.size(); ++i) {
        const double va = a.values[i], vb = b.values[i];
        if (std::min(std::fabs(va), std::fabs(vb)) < band) continue;
        d.signDifferences += (va < 0) != (vb < 0);
        if ((a.background > 0 && std::fabs(va) >= a.background) || (b.background > 0 && std::fabs(vb) >= b.background)) {
            ++d.signOnly;
            continue;
        }
        const double diff = std::fabs(va - vb);
        d.maxAbs = std::max(d.maxAbs, diff);
        sum += diff;
        sumSquares += diff * diff;
        ++d.compared;
    }
    if (d.compared) {
        d.meanAbs = sum / double(d.compared);
        d.rmsAbs = std::sqrt(sumSquares / double(d.compared));
    }
    return d;
}

} // namespace sdfgen
