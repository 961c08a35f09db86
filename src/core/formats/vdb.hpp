#pragma once
// The field as an OpenVDB grid, for the .vdb format and `sdfgen surface`.
#include "sdfgen/field.hpp"

#include <openvdb/openvdb.h>

namespace sdfgen::formats {

// A level-set FloatGrid named "surface" whose index (i, j, k) is at sample (i, j, k) (voxel size
// h, translation origin + h/2). band 0: every sample active; band >= 1: only samples with
// |d| < band * h, the rest inactive +-band * h. Initializes OpenVDB.
openvdb::FloatGrid::Ptr fieldToGrid(const Field& field, double band);

} // namespace sdfgen::formats
