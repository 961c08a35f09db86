#pragma once
#include "core/method/methods.hpp"
#include "sdfgen/bake.hpp"

#include <cstdint>

namespace sdfgen {

// The narrow-band bake of context.settings.band voxels into result.sparse (see SparseField): the
// bricks whose samples may lie within the band get the values the dense bake gives them (exact
// distances, signed by the winding sign, or by the pseudonormal as the distances are measured when
// `signBricks` is false), bit for bit; every other sample gets its side as the dense field has it
// and the magnitude band * voxel. Cost and memory follow the band's bricks, not the grid.
void bakeBand(const BakeContext& context, bool signBricks, BakeResult& result, const RunControl& control);

// The peak bytes bakeBand allocates, estimated from the mesh's area: an upper bound, within twice
// the bake's peak on closed and open meshes (tests/test_band_bake.cpp).
std::uint64_t estimateBandBakeBytes(const Mesh& mesh, const Grid& grid, double band);

} // namespace sdfgen
