#pragma once
#include "core/bvh.hpp"
#include "core/parallel.hpp"
#include "sdfgen/bake.hpp"
#include "sdfgen/mesh.hpp"

namespace sdfgen {

// Grid + distances + signs + the field's recorded method line, in one call; the method line reads
// e.g. "exact sign=auto/winding res=128 padding=0.1". Throws Error for bad settings.
BakeResult bake(const Mesh& mesh, const Bvh& tree, const BakeSettings& settings, const RunControl& control);

} // namespace sdfgen
