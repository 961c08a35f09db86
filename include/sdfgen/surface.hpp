#pragma once
// Iso-surfaces of a field as triangle meshes (`sdfgen surface`): OpenVDB's volumeToMesh on the
// field's level set, quads split into triangles, saved as OBJ or PLY.
#include "sdfgen/field.hpp"
#include "sdfgen/sparse_field.hpp"

#include <glm/vec3.hpp>
#include <string>
#include <vector>

namespace sdfgen {

struct SurfaceMesh {
    std::vector<glm::vec3> positions;  // world coordinates
    std::vector<glm::uvec3> triangles; // counter-clockwise seen from outside (where d > iso)
};

// The surface where the field equals `iso` (0: the mesh's surface; > 0 an offset outwards).
// `adaptivity` in [0, 1] merges flat regions into fewer, larger polygons (0: uniform). The
// surface is closed when it stays inside the grid: Error when a sample on the grid's boundary is
// at or below `iso` (the field needs more padding). Error for an empty result.
SurfaceMesh extractSurface(const Field& field, double iso, double adaptivity);
// The same for a band field, meshed as the level set it is (never made dense): `iso` must lie
// within the band (|iso| < background), where the field holds distances.
SurfaceMesh extractSurface(const SparseField& field, double iso, double adaptivity);

// Writes `mesh` as Wavefront OBJ (.obj) or binary little-endian PLY (.ply), by the extension of
// `path`, atomically. Error naming `path` for another extension or a failed write.
void saveSurface(const SurfaceMesh& mesh, const std::string& path);

} // namespace sdfgen
