#pragma once
// sdfgen::Model: signed distance fields and point queries for a triangle mesh.
//
// What is computed. The `exact` method's distance of a sample is the distance to the nearest
// triangle: the triangle is found by a float search (ties going to the lower triangle index,
// whatever the traversal order), then its closest point is measured again in double in the mesh's
// local coordinates (centred and scaled by a power of two, see Mesh::toLocal) and the result,
// scaled to world units, is rounded once to float. Fields are stored as float. `brute` measures
// every triangle in double (the reference); `rays` is an upper bound from ray hits.
//
// Which meshes. Any triangle soup: open, with holes, non-manifold, self-intersecting, with
// overlapping shells, copies of triangles, inverted (inside-out) parts. Zero-area triangles are
// dropped (Mesh::droppedDegenerate). Distances are defined for all of them; only signs depend on
// the shape.
//
// Signs. Negative inside. The winding sign takes the generalized winding number w (Jacobson et
// al. 2013), computed exactly (robust crossing counts, the holes closed by small fans): inside
// where |w| > 1/2, so a closed part is solid whichever way its faces point, and a cavity bounded
// by a reversed inner shell is empty. The pseudonormal sign (the angle-weighted pseudonormal of the
// closest feature, Baerentzen and Aanaes 2005) is right on closed, consistently oriented,
// non-self-intersecting meshes; auto takes it only where the mesh check proves it so, the winding
// sign otherwise (BakeResult::signReason says why).
//
// Threads. RunControl::threads sets the threads of every phase; fields and query answers are
// bit-identical whatever the count (fixed work partitions, no order-dependent reductions), and
// whether the AVX2 or the baseline kernel runs. Point queries at a grid's sample positions
// (Grid::position) return exactly the baked values.
//
// What is refused, and how. Every failure is an Error (sdfgen/error.hpp) whose message is one
// line naming the file, when there is one, and the problem; nothing is written or left half done.
// Refused: unreadable or malformed mesh files, faces that refer to missing vertices, non-finite
// coordinates, meshes without a triangle of non-zero area or without extent, a resolution below 1,
// negative or non-finite padding, grids (and bakes: BakeSettings' memory estimate) that do not fit
// in the memory available, distances beyond float range, non-finite query points, and settings
// that do not go together (e.g. a sign the method does not support). A raised
// RunControl::cancel ends any long call with Cancelled (an Error) soon after.
#include "sdfgen/bake.hpp"
#include "sdfgen/mesh.hpp"
#include "sdfgen/mesh_check.hpp"
#include "sdfgen/run_control.hpp"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace sdfgen {

// Where point queries write. Every pointer may be null (that output is not computed); each
// non-null one holds `count` entries (closestPoint: 3 * count, x y z interleaved).
struct PointQueryOutputs {
    float* signedDistance = nullptr;   // negative inside, by the query's sign method
    float* unsignedDistance = nullptr; // distance to the nearest triangle
    double* closestPoint = nullptr;    // world coordinates of the nearest surface point
    std::int64_t* triangle = nullptr;  // index of the nearest triangle in mesh().triangles
    double* windingNumber = nullptr;   // generalized winding number, computed exactly
    // The unit gradient of the signed distance (3 * count, by the query's sign), as a bake's
    // gradient channel (see Channels): sign * (p - c) / |p - c|; at distance 0 (where it has none)
    // the nearest triangle's unit face normal, reversed where auto finds the mesh inside out.
    double* gradient = nullptr;
    // The closest point's barycentric weights (3 * count) on the nearest triangle's corners
    // mesh().triangles[triangle][0..2], in double: they sum to 1, and only the corners spanning the
    // closest point's feature (face, edge or vertex) carry weight.
    double* barycentric = nullptr;
    // Channels besides these (sdfgen/channels.hpp), from the same closest hits and signed by the
    // query's sign, as a bake's: each of `channels` is appended to *channelValues (which must then
    // be given), in the registry's order, interleaved (ChannelInfo::width values per point, as
    // Samples holds them).
    Channels channels = {};
    std::vector<ChannelValues>* channelValues = nullptr;
};

// What a query found at one point (Model::closest): fcpw's Interaction, Warp's mesh query.
struct ClosestHit {
    std::int64_t triangle = -1; // the nearest triangle, an index into mesh().triangles
    glm::dvec3 point{0.0};      // the closest surface point, world coordinates
    glm::dvec3 barycentric{0.0}; // point's weights on the triangle's corners (PointQueryOutputs::barycentric)
    float distance = 0.0f;      // signed distance, negative inside (-0 on the surface of an inside point)
    int sign = 1;               // -1 inside, 1 outside: distance's sign, also where distance is 0
    glm::dvec3 gradient{0.0};   // the signed distance's unit gradient (PointQueryOutputs::gradient)
};

// A mesh made ready for baking and point queries: the mesh, its bounding volume hierarchy (built
// once), and its closest-point tree, topology and mesh check (built on first use, the first two
// at once when a bake or query needs both). Const member functions may be called from several
// threads at once. Moving is cheap; copies are not allowed.
class Model {
public:
    // Loads a mesh file (format from the extension, see loadMesh) and builds the tree.
    static Model load(const std::string& path, const RunControl& control = {});
    // Builds the tree of `mesh`. `control` is the one the caller's later calls use, made before
    // this: the tree is built on its threads (Error for a count outside 0..kMaxThreads), its cancel
    // flag is read before the load and during the build (Cancelled), its progress reports the
    // build, and its warn receives the mesh's warnings (Mesh::warnings, dropped zero-area triangles).
    explicit Model(Mesh mesh, const RunControl& control = {});
    // A model of `mesh`, this model's mesh with its vertices moved (an optimisation step): the same
    // triangles in the same order. While the vertices group by position as before (the vertices
    // that coincided still coincide, and no others have met: so the same connectivity and the
    // same exact copies of triangles), this model's trees and topology are refit to the new
    // positions in linear time instead of built again, and its mesh check is kept, its search for
    // self-intersections not run again, while the orientation holds: auto then decides the sign as
    // it did. Queries and bakes give exactly what a Model built from `mesh` gives when that
    // decision is the same. Anything else (other triangles, a zero-area triangle dropped, vertices
    // parted or met) is built afresh, and decides as a new model does. `control` as the constructor's.
    Model refit(Mesh mesh, const RunControl& control = {}) const;
    ~Model();
    Model(Model&&) noexcept;
    Model& operator=(Model&&) noexcept;

    const Mesh& mesh() const;

    // The mesh check (holes, non-manifold edges and vertices, flipped faces, self-intersections,
    // orientation), computed once and cached.
    const MeshCheck& check(const RunControl& control = {}) const;

    // A field on the grid that `settings` describes (see makeGrid). Throws Error for bad settings
    // or a grid that does not fit in memory (naming the mesh), Cancelled when control.cancel is
    // raised. BakeResult::warnings also go to control.warn, each prefixed with the mesh's source.
    BakeResult bake(const BakeSettings& settings, const RunControl& control = {}) const;

    // Exact queries at `count` points (world coordinates, x y z interleaved), in parallel. At a
    // baked grid's sample positions (Field::position) they give exactly the baked values.
    // `sign` is Auto, Winding or Pseudonormal (Auto decides as bake does). Winding: inside where
    // |w| > 1/2, w the exact generalized winding number, as libigl's fast-winding-number sign has
    // it: a closed part is solid whichever way its faces point, a hollow part whose inner shell
    // faces into its cavity stays hollow, a mesh inside out as a whole needs no special case, and
    // where copies facing opposite ways overlap they cancel (w = 0: outside).
    // Throws Error for a non-finite point, or one farther than 10^4 mesh sizes (the bounding box's
    // longest side) from the bounding box: the single-precision search cannot tell its nearest
    // triangle and sign.
    void query(const double* points, std::size_t count, const PointQueryOutputs& outputs,
               SignMethod sign = SignMethod::Auto, const RunControl& control = {}) const;

    // Conveniences over query().
    std::vector<float> signedDistance(const std::vector<glm::dvec3>& points, const RunControl& control = {}) const;
    std::vector<float> unsignedDistance(const std::vector<glm::dvec3>& points, const RunControl& control = {}) const;
    std::vector<ClosestHit> closest(const std::vector<glm::dvec3>& points, SignMethod sign = SignMethod::Auto,
                                    const RunControl& control = {}) const;

private:
    Model(); // for refit, which sets impl_
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace sdfgen
