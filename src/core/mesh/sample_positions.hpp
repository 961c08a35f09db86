#pragma once
// Where a grid's samples lie in a mesh's local coordinates, the frame every distance and sign is
// computed in (Mesh::toLocal).
#include "sdfgen/grid.hpp"
#include "sdfgen/mesh.hpp"

#include <glm/vec3.hpp>
#include <vector>

namespace sdfgen {

// Sample (i, j, k) of `grid` in `mesh`'s local coordinates: the one expression every generator and
// point query uses, so that they agree to the last bit.
inline glm::dvec3 localPosition(const Mesh& mesh, const Grid& grid, int i, int j, int k) {
    return mesh.toLocal(grid.position(i, j, k));
}

// makeGrid without its check that the dense grid fits in memory: for the narrow-band bake, which
// never allocates it.
Grid gridAround(const WorldBounds& bounds, int res, double padding);

// The samples' local coordinates per axis: x per i, then y per j, then z per k (dims.x + dims.y +
// dims.z values). localPosition is componentwise, so sample (i, j, k) is (axes[i], axes[dims.x + j],
// axes[dims.x + dims.y + k]) to the bit, without its three divisions per use.
std::vector<double> sampleAxes(const Mesh& mesh, const Grid& grid);

} // namespace sdfgen
