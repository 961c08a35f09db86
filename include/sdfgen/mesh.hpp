#pragma once
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/ext/vector_double3.hpp>
#include <cstddef>
#include <string>
#include <vector>

namespace sdfgen {

// An axis-aligned box in float (a mesh's local coordinates).
struct Bounds {
    glm::vec3 min{0.0f};
    glm::vec3 max{0.0f};
    glm::vec3 extent() const { return max - min; }
};

// An axis-aligned box in world coordinates (double).
struct WorldBounds {
    glm::dvec3 min{0.0};
    glm::dvec3 max{0.0};
    glm::dvec3 extent() const { return max - min; }
};

// A triangle soup with shared vertices. Triangles wind counter-clockwise seen from outside,
// so faceNormals point out of the solid.
//
// Positions are stored in local coordinates: world = origin + local * unit, with `origin` the
// centre of the bounding box (double) and `unit` a power of two that brings the mesh to about unit
// size. All float work happens in local coordinates, so a mesh far from the world origin or at an
// extreme scale is as exact as one of unit size at the origin; scaling by a power of two is exact.
struct Mesh {
    std::string source;                 // path or name the mesh came from, for messages
    glm::dvec3 origin{0.0};             // world position of local (0, 0, 0)
    double unit = 1.0;                  // world units per local unit (a power of two)
    std::vector<glm::vec3> positions;   // local coordinates
    std::vector<glm::uvec3> triangles;  // indices into positions
    std::vector<glm::vec3> faceNormals; // unit length, one per triangle
    Bounds bounds;                      // local, of the vertices that triangles use
    std::size_t droppedDegenerate = 0;  // zero-area triangles removed while building
    std::vector<std::string> warnings;  // one line each, e.g. precision lost before loading

    std::size_t triangleCount() const { return triangles.size(); }
    glm::vec3 vertex(std::size_t triangle, int corner) const { return positions[triangles[triangle][corner]]; }

    glm::dvec3 toLocal(const glm::dvec3& world) const { return (world - origin) / unit; }
    glm::dvec3 toWorld(const glm::dvec3& local) const { return origin + local * unit; }
    std::vector<glm::dvec3> worldPositions() const {
        std::vector<glm::dvec3> world(positions.size());
        for (std::size_t i = 0; i < positions.size(); ++i) world[i] = toWorld(glm::dvec3(positions[i]));
        return world;
    }
    WorldBounds worldBounds() const {
        return {toWorld(glm::dvec3(bounds.min)), toWorld(glm::dvec3(bounds.max))};
    }
};

// Validates and finishes a mesh from world positions: rejects non-finite coordinates,
// out-of-range indices and meshes with no triangles (Error naming `source`), moves it to local
// coordinates, drops triangles of zero area, computes normals and bounds.
Mesh buildMesh(std::string source, std::vector<glm::dvec3> positions, std::vector<glm::uvec3> triangles);
// The same from positions that were already rounded to float (binary files, float arrays): warns
// in Mesh::warnings when that rounding cannot resolve the mesh (extent below ~1e-5 of its distance
// from the world origin).
Mesh buildMesh(std::string source, const std::vector<glm::vec3>& positions, std::vector<glm::uvec3> triangles);

// One part of a scene: a mesh placed by an affine transform (local to world, column vectors).
struct MeshInstance {
    const Mesh* mesh = nullptr;
    glm::dmat4 transform{1.0};
};

// The scene's parts as one mesh: every part's triangles, transformed (mirroring transforms have
// their triangles' winding reversed, so normals still point out). Baking it gives the union of the
// solids: the generalized winding number of the concatenated soup is >= 1 inside any part, and
// the distance to it is the minimum over all parts. `source` names the result (for the field's
// source line); the parts' warnings and dropped triangles are kept in the result's. Throws Error
// for no parts or a non-finite transform. Defined in mesh_merge.cpp.
Mesh mergeMeshes(const std::vector<MeshInstance>& parts, std::string source);

// Loads a Wavefront OBJ (polygons are triangulated). Throws Error("PATH: problem") on any bad input.
Mesh loadObj(const std::string& path);

// Loads a mesh file in the format its extension names: .obj through loadObj; .stl (ASCII or
// binary), .ply, .off, .gltf, .glb, .fbx and the other formats Assimp reads through Assimp.
// Node transforms are applied and all meshes of the file form one mesh; polygons are
// triangulated, points and lines ignored. Throws Error("PATH: problem") for a file that cannot be
// parsed or holds no triangles.
Mesh loadMesh(const std::string& path);

} // namespace sdfgen
