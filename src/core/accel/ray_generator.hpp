#pragma once
#include "core/accel/bvh.hpp"
#include "core/runtime/parallel.hpp"
#include "sdfgen/field.hpp"
#include "sdfgen/mesh.hpp"

namespace sdfgen {

// The ray-sampling generator. For each sample, `rays` rays leave in the directions of
// sphereDirections(rays); the distance is the nearest hit of any ray (an upper bound of the true
// distance), and the sample is inside (negative) when more than half of the rays that hit anything
// first hit a back face. A sample whose rays all miss lies outside, and gets the distance to the
// farthest corner of the mesh's bounding box: finite, positive and still an upper bound.
// The result does not depend on the thread count.
Field generateRayField(const Mesh& mesh, const Bvh& tree, const Grid& grid, int rays, const RunControl& control);

} // namespace sdfgen
