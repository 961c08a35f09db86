#pragma once
#include "core/geometry.hpp"
#include "core/kdtree.hpp"
#include "core/mesh.hpp"

#include <glm/vec3.hpp>
#include <cstdint>
#include <string>
#include <vector>

namespace sdfgen {

// What a mesh check found. Pseudonormal signs are provably right only when every count is zero.
struct MeshCheck {
    std::size_t boundaryEdges = 0;       // edges with one triangle: the mesh has holes
    std::size_t nonManifoldEdges = 0;    // edges with three or more triangles
    std::size_t inconsistentEdges = 0;   // edges whose two triangles run the same way: flipped faces
    std::size_t nonManifoldVertices = 0; // vertices whose triangles form several fans (pinches)
    std::size_t selfIntersections = 0;   // pairs of triangles that cross each other

    bool closedAndClean() const {
        return boundaryEdges + nonManifoldEdges + inconsistentEdges + nonManifoldVertices + selfIntersections == 0;
    }
    // "12 boundary edges, 0 non-manifold edges, ..." for summaries and the panel.
    std::string describe() const;
};

// Connectivity of a mesh whose coincident vertices are merged (OBJ files often repeat positions).
class MeshTopology {
public:
    explicit MeshTopology(const Mesh& mesh);

    // Counts of the problems above; self-intersections are found with the tree.
    MeshCheck check(const Mesh& mesh, const KdTree& tree) const;

    // The boundary as closed loops of merged vertex indices, oriented like the triangles that own
    // the edges; an edge used twice the same way appears twice. Empty for a closed mesh.
    const std::vector<std::vector<std::uint32_t>>& boundaryLoops() const { return loops_; }
    const glm::dvec3& position(std::uint32_t vertex) const { return positions_[vertex]; }

    // The angle-weighted pseudonormal (Bærentzen & Aanæs 2005) of a feature of a triangle.
    glm::dvec3 pseudonormal(std::uint32_t triangle, TriangleFeature feature) const;

private:
    std::vector<glm::dvec3> positions_;  // merged vertices
    std::vector<glm::uvec3> corners_;    // per triangle, merged vertex indices
    std::vector<glm::dvec3> faceNormals_;
    std::vector<glm::dvec3> vertexNormals_;
    std::vector<glm::dvec3> edgeNormals_; // 3 per triangle: AB, BC, CA
    std::vector<std::vector<std::uint32_t>> loops_;
    MeshCheck edgeCheck_; // everything but self-intersections
};

} // namespace sdfgen
