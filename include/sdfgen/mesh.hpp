#pragma once
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <cstddef>
#include <string>
#include <vector>

namespace sdfgen {

struct Bounds {
    glm::vec3 min{0.0f};
    glm::vec3 max{0.0f};
    glm::vec3 extent() const { return max - min; }
};

// A triangle soup with shared vertices. Triangles wind counter-clockwise seen from outside,
// so faceNormals point out of the solid.
struct Mesh {
    std::string source;                 // path or name the mesh came from, for messages
    std::vector<glm::vec3> positions;
    std::vector<glm::uvec3> triangles;  // indices into positions
    std::vector<glm::vec3> faceNormals; // unit length, one per triangle
    Bounds bounds;                      // of the vertices that triangles use
    std::size_t droppedDegenerate = 0;  // zero-area triangles removed while building

    std::size_t triangleCount() const { return triangles.size(); }
    glm::vec3 vertex(std::size_t triangle, int corner) const { return positions[triangles[triangle][corner]]; }
};

// Validates and finishes a mesh: rejects non-finite coordinates, out-of-range indices and meshes
// with no triangles (Error naming `source`), drops zero-area triangles, computes normals and bounds.
Mesh buildMesh(std::string source, std::vector<glm::vec3> positions, std::vector<glm::uvec3> triangles);

// One part of a scene: a mesh placed by an affine transform (local to world, column vectors).
struct MeshInstance {
    const Mesh* mesh = nullptr;
    glm::dmat4 transform{1.0};
};

// The scene's parts as one mesh: every part's triangles, transformed (mirroring transforms have
// their triangles' winding reversed, so normals still point out). Baking it gives the union of the
// solids: the generalized winding number of the concatenated soup is >= 1 inside any part, and
// the distance to it is the minimum over all parts. `source` names the result (for the field's
// source line). Throws Error for no parts or a non-finite transform. Defined in mesh_merge.cpp.
Mesh mergeMeshes(const std::vector<MeshInstance>& parts, std::string source);

// Loads a Wavefront OBJ (polygons are triangulated). Throws Error("PATH: problem") on any bad input.
Mesh loadObj(const std::string& path);

} // namespace sdfgen
