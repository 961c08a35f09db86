#pragma once
#include "core/exact.hpp"
#include "sdfgen/grid.hpp"
#include "sdfgen/mesh.hpp"
#include "core/topology.hpp"

#include <cstdint>
#include <vector>

namespace sdfgen {

// Inside flags (1 = inside) for every sample of a grid, by one of the sign methods.

// What the winding sign did, for tests and benchmarks.
struct WindingStats {
    std::size_t caps = 0;           // fans closing the boundary (equal loops share one, long ones are split)
    std::size_t fanEvaluations = 0; // exact fan solid angles computed, over all samples
};

// The generalized winding number w (Jacobson et al. 2013), inside where w > 1/2, computed exactly.
// The mesh is closed with small fans over its boundary loops; the closed surface's winding number
// is an integer, counted for whole rows at once from the signed crossings of each row's line
// (robust 2D point-in-triangle tests in double with symbolic tie-breaking, so shared edges count
// once; copies of a triangle count once with their number as weight). The fans' own winding number
// is subtracted wherever it could move w across 1/2: a bounding-sphere tree over the fans bounds
// what is far (area / distance²), once per 4³ brick of samples, and a sample whose bounds leave
// doubt opens the loosest node until they do not, down to every fan exactly. So signs are those
// of the exact w, and a sample pays only for the fans near it. Robust to holes,
// self-intersections, overlapping shells and flipped parts.
std::vector<std::uint8_t> insideByWinding(const Mesh& mesh, const MeshTopology& topology, const Grid& grid,
                                          const RunControl& control, WindingStats* stats = nullptr);
// The same signs applied in place: values[i] (unsigned distances, grid order) is negated where
// the sample is inside. No per-sample side array.
void applyWindingSign(const Mesh& mesh, const MeshTopology& topology, const Grid& grid, float* values,
                      const RunControl& control, WindingStats* stats = nullptr);

// The angle-weighted pseudonormal of each sample's closest feature (Bærentzen & Aanæs 2005): right
// for closed, manifold, consistently oriented meshes without self-intersections.
std::vector<std::uint8_t> insideByPseudonormal(const Mesh& mesh, const MeshTopology& topology, const Grid& grid,
                                               const NearestField& nearest, const RunControl& control);

// The generalized winding number at p, summed over every triangle in double (the reference).
double windingNumber(const Mesh& mesh, const glm::dvec3& p);

} // namespace sdfgen
