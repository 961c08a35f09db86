#pragma once
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

// Loads a Wavefront OBJ (polygons are triangulated). Throws Error("PATH: problem") on any bad input.
Mesh loadObj(const std::string& path);

// Loads a mesh file in the format its extension names: .obj through loadObj; .stl (ASCII or
// binary), .ply, .off, .gltf, .glb, .fbx and the other formats Assimp reads through Assimp.
// Node transforms are applied and all meshes of the file form one mesh; polygons are
// triangulated, points and lines ignored. Throws Error("PATH: problem") for a file that cannot be
// parsed or holds no triangles.
Mesh loadMesh(const std::string& path);

} // namespace sdfgen
