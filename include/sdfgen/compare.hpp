#pragma once
#include "sdfgen/field.hpp"

#include <cstddef>

namespace sdfgen {

// How two fields on the same grid differ.
struct FieldDifference {
    double maxAbs = 0, meanAbs = 0, rmsAbs = 0; // over the samples compared, in the fields' units
    double voxel = 0;                           // to express the above in voxels
    std::size_t compared = 0;                   // samples outside the band
    std::size_t signDifferences = 0;            // of those, samples whose signs differ
    double signFraction() const { return compared ? double(signDifferences) / double(compared) : 0.0; }
};

// Compares a and b sample by sample, skipping samples within `bandVoxels` voxels of the surface in
// either field (0 compares all). Throws Error when the grids differ.
FieldDifference compareFields(const Field& a, const Field& b, double bandVoxels);

} // namespace sdfgen
