#pragma once
#include "core/method/methods.hpp"
#include "sdfgen/bake.hpp"

namespace sdfgen {

// The narrow-band bake of context.settings.band voxels (see SparseField), named after the mesh
// (the caller adds the method line); the phases' times go into `result`. The bricks whose samples
// may lie within the band get the values the dense bake gives them, bit for bit (measured by the
// method's `bricks`, signed as it measured them, by the sign's own `bricks`, or by the band's
// sides: see BandSigning); every other sample gets its side as the dense field has it and the
// magnitude band * voxel. context.sign is settled (decideSign) to one that can
// side a band. Cost and memory follow the band's bricks, not the grid.
SparseField bakeBand(const BakeContext& context, BakeResult& result, const RunControl& control);

} // namespace sdfgen
