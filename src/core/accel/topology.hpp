#pragma once
#include "core/mesh/geometry.hpp"
#include "core/accel/bvh.hpp"
#include "core/mesh/vertex_groups.hpp"
#include "sdfgen/mesh.hpp"
#include "sdfgen/mesh_check.hpp"
#include "sdfgen/run_control.hpp"

#include <glm/vec3.hpp>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace sdfgen {

// Connectivity of a mesh whose coincident vertices are merged (OBJ files often repeat positions).
class MeshTopology {
public:
    // Reports progress and throws Cancelled (between its stages) when control.cancel is raised.
    explicit MeshTopology(const Mesh& mesh, const RunControl& control = {});
    // The same, taking the exact copies of triangles from the mesh's tree, which has found them
    // already (Bvh::copies), instead of finding them again.
    MeshTopology(const Mesh& mesh, const Bvh& tree, const RunControl& control = {});
    // The topology of `mesh`, which is `previous`'s mesh with its vertices moved (the same
    // triangles) where previous.groups().holdFor(mesh.positions): the connectivity is shared, and
    // only what depends on positions is measured again, equal to a fresh build's.
    MeshTopology(const MeshTopology& previous, const Mesh& mesh, const RunControl& control = {});

    // The mesh's vertices grouped by position: group g is merged vertex g.
    const std::shared_ptr<const VertexGroups>& groups() const { return groups_; }

    // The counts MeshCheck lists; self-intersections are found with the tree, a crossing pair of
    // repeated triangles counted once per pair of copies (as triangle by triangle).
    // In parallel; the same counts for any thread count. Throws Cancelled when control.cancel is raised.
    MeshCheck check(const Mesh& mesh, const Bvh& tree, const RunControl& control = {}) const;
    // The counts found by the topology alone: everything but self-intersections (not searched).
    const MeshCheck& edgeCheck() const { return edgeCheck_; }

    // The boundary as closed loops of merged vertex indices, oriented like the triangles that own
    // the edges; an edge used twice the same way appears twice. Empty for a closed mesh.
    const std::vector<std::vector<std::uint32_t>>& boundaryLoops() const { return links_->loops; }
    const glm::dvec3& position(std::uint32_t vertex) const { return positions_[vertex]; }
    std::size_t triangleCount() const { return links_->corners.size(); }
    // Triangle t's corners as merged vertex indices.
    const glm::uvec3& corners(std::uint32_t triangle) const { return links_->corners[triangle]; }
    // How often triangle t occurs in the mesh if it is the first of its exact copies, else 0 (see
    // TriangleCopies): passes that stack triangles weigh the first copy and skip the others.
    std::uint32_t copies(std::uint32_t triangle) const { return links_->copies[triangle]; }
    // Closed and consistently oriented with negative volume (see MeshCheck::insideOut).
    bool insideOut() const { return edgeCheck_.insideOut; }

    // The angle-weighted pseudonormal (Bærentzen & Aanæs 2005) of a feature of a triangle. Safe
    // from any thread; the vertex normals of a mesh whose edges rule the pseudonormal out are
    // built by the first call that needs one.
    glm::dvec3 pseudonormal(std::uint32_t triangle, TriangleFeature feature) const;
    // glm::dot(offset, pseudonormal(triangle, feature)) < 0.0, bit for bit: whether `offset` (a
    // point less its closest point on the feature) points against the pseudonormal. A refit's
    // vertex normal not yet measured is measured only where the faces around the vertex leave the
    // side in doubt (vertexSide).
    bool facesAway(std::uint32_t triangle, TriangleFeature feature, const glm::dvec3& offset) const;

    // 3 per triangle (AB, BC, CA): the other triangle of an edge used by exactly two, else kNoNeighbour.
    static constexpr std::uint32_t kNoNeighbour = 0xffffffffu;
    // What depends on the triangles and the vertex groups alone, shared by the topologies of a mesh
    // whose vertices move (the refit constructor).
    struct Links {
        std::vector<glm::uvec3> corners;           // per triangle, merged vertex indices
        std::vector<std::uint32_t> edgeNeighbours; // 3 per triangle, see kNoNeighbour
        std::vector<std::vector<std::uint32_t>> loops;
        std::vector<std::uint32_t> copies;
        MeshCheck edgeCounts; // boundary, non-manifold and inconsistent edges, non-manifold vertices
        // fansCloseMesh's answer (core/sign/winding_sign.hpp), which depends on these alone: found
        // once for a whole chain of refits (it sorts every edge: a large part of a refit step).
        mutable std::once_flag fansCloseOnce;
        mutable bool fansClose = false;
    };
    const Links& links() const { return *links_; }

private:
    MeshTopology(const Mesh& mesh, std::vector<std::uint32_t> copies, const RunControl& control);
    // The merged positions (double, exact) and the face normals, from the mesh.
    void takePositions(const Mesh& mesh);
    // The signed volume, insideOut and (for a clean mesh, `eagerNormals`) the vertex normals, from positions_.
    void measurePositions(const RunControl& control, bool eagerNormals);
    glm::dvec3 edgeNormal(std::uint32_t triangle, int edge) const;
    // The angle at corner c of triangle t (merged positions), or -1 for a collapsed corner.
    double cornerAngle(std::size_t t, std::uint32_t c) const;
    // The cosine cornerAngle takes the arc cosine of, or nothing for a collapsed corner.
    std::optional<double> cornerCosine(std::size_t t, std::uint32_t c) const;
    // The angle-weighted vertex normals, built once: in parallel with a control, else serially.
    void buildVertexNormals(const RunControl* control) const;
    // A vertex normal: all of them built, or (a refit's) this one alone, measured on first use.
    glm::dvec3 vertexNormal(std::uint32_t vertex) const;
    glm::dvec3 measureVertexNormal(std::uint32_t vertex) const;
    // The sign of glm::dot(offset, measureVertexNormal(vertex)) where the vertex's faces settle
    // it without the corners' angles, else 0.
    int vertexSide(std::uint32_t vertex, const glm::dvec3& offset) const;
    // Whether triangles t and u have a point in common other than the vertices they share (exact).
    bool trianglesCross(std::uint32_t t, std::uint32_t u) const;
    // MeshCheck::misorientedShells of a mesh whose other counts are all zero; `outward` is -1 for
    // a mesh inside out as a whole, else 1.
    std::size_t countMisorientedShells(const Mesh& mesh, const Bvh& tree, int outward, const RunControl& control) const;

    std::shared_ptr<const VertexGroups> groups_;
    std::shared_ptr<const Links> links_;
    std::vector<glm::dvec3> positions_;  // merged vertices
    std::vector<glm::vec3> faceNormals_;  // the mesh's (float, exact in double)
    mutable std::once_flag vertexNormalsOnce_;
    // Set once they are built: the per-sample check is one load, where std::call_once's own fast
    // path writes thread-locals on every call.
    mutable std::atomic<bool> vertexNormalsBuilt_{false};
    mutable std::vector<glm::dvec3> vertexNormals_; // empty until buildVertexNormals
    // A refit's vertex normals are measured one by one as the queries ask for them (a query
    // usually meets a few vertices of a large mesh, and each refit would measure every one
    // again): each vertex's corners (3 t + c, in triangle order, the order buildVertexNormals sums
    // them in, so the same value bit for bit), shared along the refit chain, and per vertex its
    // state: 0 not measured, 1 being stored by the thread that claimed it, 2 stored.
    struct VertexCorners {
        std::vector<std::uint32_t> start; // vertex v's corners are corner[start[v]] .. corner[start[v + 1]]
        std::vector<std::uint32_t> corner;
    };
    std::shared_ptr<const VertexCorners> vertexCorners_; // null: all normals are built at once
    mutable std::unique_ptr<std::atomic<std::uint8_t>[]> vertexNormalState_;
    MeshCheck edgeCheck_; // everything but self-intersections: links_->edgeCounts and the volume
};

} // namespace sdfgen
