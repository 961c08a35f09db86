#pragma once
#include "core/exact.hpp"
#include "sdfgen/grid.hpp"
#include "sdfgen/mesh.hpp"
#include "core/topology.hpp"
#include "sdfgen/device.hpp"

#include <cstdint>
#include <vector>

namespace sdfgen {

// Inside flags (1 = inside) for every sample of a grid, by one of the sign methods.

// The generalized winding number w (Jacobson et al. 2013), inside where w > 1/2, computed exactly.
// The mesh is closed with a fan over each boundary loop; the closed surface's winding number is an
// integer, counted for whole rows at once from the signed crossings of each row's line (robust 2D
// point-in-triangle tests in double with symbolic tie-breaking, so shared edges count once). The
// fans' own winding number is subtracted wherever it could reach 1/2, bounded by area / distance²,
// exactly in double; elsewhere it cannot change the answer. Robust to holes, self-intersections,
// overlapping shells and flipped parts; exact (no hierarchy error) and linear in samples.
// With a device, the closed surface's winding numbers come from it (the same integers) and only
// the fans' part near the holes is computed here.
std::vector<std::uint8_t> insideByWinding(const Mesh& mesh, const MeshTopology& topology, const Grid& grid,
                                          const RunControl& control, ComputeDevice* device = nullptr);

// The angle-weighted pseudonormal of each sample's closest feature (Bærentzen & Aanæs 2005): right
// for closed, manifold, consistently oriented meshes without self-intersections.
std::vector<std::uint8_t> insideByPseudonormal(const Mesh& mesh, const MeshTopology& topology, const Grid& grid,
                                               const NearestField& nearest, const RunControl& control);

// The generalized winding number at p, summed over every triangle in double (the reference).
double windingNumber(const Mesh& mesh, const glm::dvec3& p);

} // namespace sdfgen
