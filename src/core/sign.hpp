#pragma once
#include "core/bvh.hpp"
#include "core/exact.hpp"
#include "sdfgen/grid.hpp"
#include "sdfgen/mesh.hpp"
#include "core/topology.hpp"

#include <cstdint>
#include <vector>

namespace sdfgen {

// A fan closing one boundary loop, counted `weight` times, with what bounds its winding number from
// afar. Its triangles are (loop[i + 1], loop[i], centre): the loop reversed, so mesh + fans is closed.
struct Cap {
    std::vector<glm::dvec3> loop;
    glm::dvec3 centre;
    double radius = 0; // every point of the fan is within this of centre
    double area = 0;
    int weight = 1;    // equal loops (copies of open triangles) share one cap
};

// One fan per distinct boundary loop of the mesh, weighted by how often the loop occurs: the mesh
// with its fans is closed.
std::vector<Cap> makeCaps(const MeshTopology& topology);

// Inside flag and exact winding number at p, given `ahead`, the signed count of crossings of the
// mesh and its fans along +x from p (the closed surface's winding number): the fans' own winding
// number is subtracted, in insideFromCrossings only where it could move w across 1/2. Orientation -1
// tells inside by -w > 1/2, for a mesh that is inside out.
bool insideFromCrossings(const std::vector<Cap>& caps, const glm::dvec3& p, int ahead, int orientation = 1);
double windingFromCrossings(const std::vector<Cap>& caps, const glm::dvec3& p, int ahead);

// `ahead` for one point p (local coordinates), from the tree: what insideByWinding's row scan
// finds for a sample at p.
int crossingsAhead(const Mesh& mesh, const Bvh& tree, const std::vector<Cap>& caps, const glm::dvec3& p);

// Inside flags (1 = inside) for every sample of a grid, by one of the sign methods.

// The generalized winding number w (Jacobson et al. 2013), inside where w > 1/2, computed exactly.
// The mesh is closed with a fan over each boundary loop; the closed surface's winding number is an
// integer, counted for whole rows at once from the signed crossings of each row's line (robust 2D
// point-in-triangle tests in double with symbolic tie-breaking, so shared edges count once). The
// fans' own winding number is subtracted wherever it could reach 1/2, bounded by area / distance²,
// exactly in double; elsewhere it cannot change the answer. Robust to holes, self-intersections,
// overlapping shells and flipped parts; exact (no hierarchy error) and linear in samples.
// With `flipped`, inside is where -w > 1/2: the signs of the mesh with every face flipped.
std::vector<std::uint8_t> insideByWinding(const Mesh& mesh, const MeshTopology& topology, const Grid& grid,
                                          const RunControl& control, bool flipped = false);

// The angle-weighted pseudonormal of each sample's closest feature (Bærentzen & Aanæs 2005): right
// for closed, manifold, consistently oriented meshes without self-intersections.
std::vector<std::uint8_t> insideByPseudonormal(const Mesh& mesh, const MeshTopology& topology, const Grid& grid,
                                               const std::vector<std::uint32_t>& nearestTriangle, const RunControl& control);

// The generalized winding number at p, summed over every triangle in double (the reference).
double windingNumber(const Mesh& mesh, const glm::dvec3& p);

} // namespace sdfgen
