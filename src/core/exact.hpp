#pragma once
#include "sdfgen/field.hpp"
#include "sdfgen/grid.hpp"
#include "core/parallel.hpp"
#include "core/bvh.hpp"

#include <cstdint>
#include <vector>

namespace sdfgen {

// The exact unsigned distance from every sample to the mesh, and the triangle that attains it.
struct NearestField {
    std::vector<float> distance;
    std::vector<std::uint32_t> triangle;
};

// For each row of samples, eight neighbours at a time search the tree nearest-first, starting
// from the exact distance to the triangles the previous eight found (the field is 1-Lipschitz, so
// a neighbour's triangle is nearly always the answer or close to it and prunes most of the tree).
// The winner is re-measured in double precision. Independent of the thread count.
NearestField computeNearest(const Mesh& mesh, const Bvh& tree, const Grid& grid, const RunControl& control);

class MeshTopology;
// The same search, writing each sample's exact distance straight into values[grid.index(i, j, k)]
// (grid.sampleCount() floats), negated where the closest feature's angle-weighted pseudonormal
// says inside when `pseudonormalSigns` is given (as insideByPseudonormal would): no per-sample
// side arrays, so a bake needs the field's own memory only.
void computeExactField(const Mesh& mesh, const Bvh& tree, const Grid& grid, const MeshTopology* pseudonormalSigns,
                       float* values, const RunControl& control);

// The reference: for every sample, the distance to every triangle and the winding number summed
// over every triangle, all in double (inside where it exceeds 1/2). O(samples x triangles).
Field computeBruteForce(const Mesh& mesh, const Grid& grid, const RunControl& control);

} // namespace sdfgen
