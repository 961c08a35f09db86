#pragma once
#include "core/accel/bvh.hpp"
#include "core/method/methods.hpp"
#include "sdfgen/bake.hpp"
#include "sdfgen/mesh.hpp"

#include <string>

namespace sdfgen {

// The grid's distances by the settings' method, then its signs, then the field's recorded method
// line, e.g. "exact sign=auto/winding res=128 padding=0.1". Throws Error for bad settings.
BakeResult bake(const BakeContext& context, const RunControl& control);

// The same for a mesh and its tree alone (topology and mesh check built when needed); for tests
// and tools. Front ends use sdfgen::Model, which keeps them between bakes.
BakeResult bake(const Mesh& mesh, const Bvh& tree, const BakeSettings& settings, const RunControl& control);

} // namespace sdfgen
