#pragma once
#include "sdfgen/field.hpp"
#include "sdfgen/run_control.hpp"
#include "sdfgen/sparse_field.hpp"

#include <cstddef>
#include <vector>

namespace sdfgen {

// How two fields on the same grid differ.
struct FieldDifference {
    double maxAbs = 0, meanAbs = 0, rmsAbs = 0; // over the samples compared, in the fields' units
    double voxel = 0;                           // to express the above in voxels
    std::size_t compared = 0;                   // samples compared by value (outside the band skipped)
    // Samples compared by sign only: outside a band field's band (Field::background), where it
    // knows the side and not the distance.
    std::size_t signOnly = 0;
    std::size_t signDifferences = 0; // of both, samples whose signs differ
    double signFraction() const { return compared + signOnly ? double(signDifferences) / double(compared + signOnly) : 0.0; }
};

// Compares a and b sample by sample, skipping samples within `bandVoxels` voxels of the surface in
// either field (0 compares all). A band field (Field::background > 0) is compared by value where
// |value| < background and by sign elsewhere. Throws Error when the grids differ. With
// `signDifferences`, it gets the indices (into Field::values) of the samples counted in
// FieldDifference::signDifferences, in increasing order. `control` reports progress and is
// checked for Cancel every million samples (its threads are not used: the sums run in order).
FieldDifference compareFields(const Field& a, const Field& b, double bandVoxels, std::vector<std::size_t>* signDifferences = nullptr,
                              const RunControl& control = {});

// compareFields for two band fields, without their dense forms: sample by sample where either
// stores a brick, by counting elsewhere (time and memory grow with the bricks and inside boxes,
// not the grid). The same result as compareFields on their toDense().
FieldDifference compareSparseFields(const SparseField& a, const SparseField& b, double bandVoxels);

// Throws Error when two grids differ in dimensions, or in origin or voxel size by more than a
// thousandth of a voxel: what the comparisons check first.
void checkSameGrid(const Grid& a, const Grid& b);

} // namespace sdfgen
