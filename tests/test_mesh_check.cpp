// The mesh check's counts on generated broken meshes, and the sign that auto picks from them.
#include "sdfgen/compare.hpp"
#include "core/mesh/predicates.hpp"
#include "core/accel/topology.hpp"
#include "core/mesh/vertex_groups.hpp"
#include "core/runtime/parallel.hpp"
#include "support/broken_meshes.hpp"
#include "support/checks.hpp"
#include "support/reference.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace sdfgen {
namespace {

using namespace test;

// The check's five counts in describe()'s order (boundary, non-manifold and inconsistent edges,
// non-manifold vertices, self-intersecting pairs), to compare in one expectation.
std::vector<std::size_t> counts(const MeshCheck& c) {
    return {c.boundaryEdges, c.nonManifoldEdges, c.inconsistentEdges, c.nonManifoldVertices, c.selfIntersections};
}

TEST(MeshCheck, ClosedMeshesAreCleanAndAutoPicksPseudonormal) {
    const BakeResult result = bakeWith(test::icosphere(1.0f, 2), 12, DistanceMethod::Exact, SignMethod::Auto);
    EXPECT_TRUE(result.checked);
    EXPECT_TRUE(result.check.closedAndClean()) << result.check.describe();
    EXPECT_EQ(result.sign, SignMethod::Pseudonormal);
    EXPECT_EQ(result.field.dense().parameter("sign"), "auto/pseudonormal");
    for (const Shape& shape : closedShapes()) {
        const MeshCheck check = checkMesh(shape.mesh);
        EXPECT_TRUE(check.closedAndClean()) << shape.name << ": " << check.describe();
    }
}

TEST(MeshCheck, OpenAndOverlappingMeshesMakeAutoPickWinding) {
    for (const Shape& shape : openShapes()) {
        const BakeResult result = bakeWith(shape.mesh, 12, DistanceMethod::Exact, SignMethod::Auto);
        EXPECT_TRUE(result.checked) << shape.name;
        EXPECT_FALSE(result.check.closedAndClean()) << shape.name;
        EXPECT_EQ(result.sign, SignMethod::Winding) << shape.name;
        EXPECT_EQ(result.field.dense().parameter("sign"), "auto/winding") << shape.name;
        EXPECT_FALSE(result.signReason.empty());
        // The costly search runs only when the edges leave the choice open: closed shells that overlap.
        const MeshCheck edges = MeshTopology(shape.mesh).edgeCheck();
        EXPECT_EQ(result.check.selfIntersectionsSearched, edges.closedAndClean()) << shape.name;
        if (edges.closedAndClean()) {
            EXPECT_GT(result.check.selfIntersections, 0u) << shape.name;
        } else {
            EXPECT_CONTAINS(result.check.describe(), "self-intersections not searched");
        }
        EXPECT_TRUE(checkMesh(shape.mesh).selfIntersectionsSearched) << shape.name;
    }
}

TEST(MeshCheck, HoleCountsBoundaryEdges) {
    const Mesh mesh = holedSphere(1.0f);
    const MeshCheck check = checkMesh(mesh);
    EXPECT_GT(check.boundaryEdges, 0u);
    EXPECT_EQ(check.nonManifoldEdges, 0u);
    EXPECT_EQ(check.inconsistentEdges, 0u);
    EXPECT_EQ(check.nonManifoldVertices, 0u);
    EXPECT_EQ(check.selfIntersections, 0u);
    // One loop, as long as the boundary.
    const MeshTopology topology(mesh);
    ASSERT_EQ(topology.boundaryLoops().size(), 1u);
    EXPECT_EQ(topology.boundaryLoops()[0].size(), check.boundaryEdges);
    const BakeResult result = bakeWith(mesh, 12, DistanceMethod::Exact, SignMethod::Auto);
    EXPECT_EQ(result.sign, SignMethod::Winding);
    EXPECT_NE(result.signReason.find("holes"), std::string::npos) << result.signReason;
}

TEST(MeshCheck, OverlappingShellsCountSelfIntersections) {
    for (bool flip : {false, true}) {
        const MeshCheck check = checkMesh(twoShells(flip));
        EXPECT_GT(check.selfIntersections, 0u);
        EXPECT_EQ(check.boundaryEdges, 0u);
        EXPECT_EQ(check.nonManifoldEdges, 0u);
        EXPECT_EQ(check.inconsistentEdges, 0u);
        EXPECT_EQ(check.nonManifoldVertices, 0u);
    }
    // Apart, the same two shells are clean.
    const Mesh sphere = test::icosphere(1.0f, 2);
    EXPECT_TRUE(checkMesh(combined("apart", translated(sphere, {-1.5f, 0, 0}, false), translated(sphere, {1.5f, 0, 0}, false)))
                    .closedAndClean());
}

TEST(MeshCheck, TwoTetrahedraSharingOneVertexArePinched) {
    std::vector<glm::vec3> positions;
    std::vector<glm::uvec3> triangles;
    addTetrahedron(positions, triangles, {0, 0, 0}, 1.0f);
    addTetrahedron(positions, triangles, {0, 0, 0}, -1.0f);
    const Mesh mesh = buildMesh("pinched", positions, triangles);
    EXPECT_GT(signedVolume(mesh), 0.0);
    const MeshCheck check = checkMesh(mesh);
    EXPECT_EQ(counts(check), (std::vector<std::size_t>{0, 0, 0, 1, 0})) << check.describe();
    const BakeResult result = bakeWith(mesh, 12, DistanceMethod::Exact, SignMethod::Auto);
    EXPECT_EQ(result.sign, SignMethod::Winding);
    // Either tetrahedron alone is clean.
    std::vector<glm::vec3> one;
    std::vector<glm::uvec3> oneTriangles;
    addTetrahedron(one, oneTriangles, {0, 0, 0}, -1.0f);
    EXPECT_TRUE(checkMesh(buildMesh("tetrahedron", one, oneTriangles)).closedAndClean());
}

TEST(MeshCheck, OneFlippedTriangleGivesThreeInconsistentEdges) {
    Mesh sphere = test::icosphere(1.0f, 2);
    std::vector<glm::uvec3> triangles = sphere.triangles;
    std::swap(triangles[17][1], triangles[17][2]);
    const Mesh mesh = buildMesh("one flipped", sphere.worldPositions(), triangles);
    const MeshCheck check = checkMesh(mesh);
    EXPECT_EQ(counts(check), (std::vector<std::size_t>{0, 0, 3, 0, 0})) << check.describe();
    const BakeResult result = bakeWith(mesh, 16, DistanceMethod::Exact, SignMethod::Auto);
    EXPECT_EQ(result.sign, SignMethod::Winding);
    EXPECT_NE(result.signReason.find("flipped faces"), std::string::npos) << result.signReason;
    // The winding sign still matches the reference away from the surface.
    const Field brute = bakeWith(mesh, 16, DistanceMethod::Brute, SignMethod::Auto).field.dense();
    EXPECT_EQ(compareFields(result.field.dense(), brute, 1.0).signDifferences, 0u);
}

TEST(MeshCheck, ThreeTrianglesOnOneEdgeAreANonManifoldEdge) {
    std::vector<glm::vec3> positions;
    std::vector<glm::uvec3> triangles;
    addTetrahedron(positions, triangles, {0, 0, 0}, 1.0f);
    // A fin on edge (1,0,0)-(0,1,0), outside the tetrahedron.
    positions.emplace_back(1.0f, 1.0f, -0.3f);
    triangles.emplace_back(1u, 4u, 2u);
    const Mesh mesh = buildMesh("fin", positions, triangles);
    const MeshCheck check = checkMesh(mesh);
    EXPECT_EQ(check.nonManifoldEdges, 1u) << check.describe();
    EXPECT_EQ(check.boundaryEdges, 2u) << check.describe(); // the fin's own two edges
    EXPECT_EQ(check.selfIntersections, 0u) << check.describe();
    const BakeResult result = bakeWith(mesh, 12, DistanceMethod::Exact, SignMethod::Auto);
    EXPECT_EQ(result.sign, SignMethod::Winding);
}

// Every pair of triangles tested with the exact predicates alone: the definition that the check's
// tree-against-tree traversal and its cheap rejections must reproduce exactly. Vertices merge by
// position; a pair sharing an edge never counts, any other pair counts when an edge of one away
// from their shared vertices meets the other.
std::size_t bruteForceCrossings(const Mesh& mesh) {
    std::map<std::array<float, 3>, std::uint32_t> merged;
    std::vector<glm::uvec3> corners(mesh.triangleCount());
    for (std::uint32_t t = 0; t < mesh.triangleCount(); ++t) {
        for (int c = 0; c < 3; ++c) {
            const glm::vec3 p = mesh.vertex(t, c) + glm::vec3(0.0f);
            corners[t][c] = merged.emplace(std::array<float, 3>{p.x, p.y, p.z}, std::uint32_t(merged.size())).first->second;
        }
    }
    std::size_t count = 0;
    for (std::uint32_t t = 0; t < mesh.triangleCount(); ++t) {
        for (std::uint32_t u = t + 1; u < mesh.triangleCount(); ++u) {
            const glm::uvec3 a = corners[t], b = corners[u];
            int shared = 0;
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) shared += a[i] == b[j];
            if (shared >= 2) continue;
            const auto touches = [](const glm::uvec3& x, std::uint32_t v) { return x[0] == v || x[1] == v || x[2] == v; };
            bool meet = false;
            for (int e = 0; e < 3 && !meet; ++e) {
                const int f = (e + 1) % 3;
                if (!touches(b, a[e]) && !touches(b, a[f]))
                    meet = segmentMeetsTriangle(mesh.vertex(t, e), mesh.vertex(t, f), mesh.vertex(u, 0), mesh.vertex(u, 1), mesh.vertex(u, 2));
                if (!meet && !touches(a, b[e]) && !touches(a, b[f]))
                    meet = segmentMeetsTriangle(mesh.vertex(u, e), mesh.vertex(u, f), mesh.vertex(t, 0), mesh.vertex(t, 1), mesh.vertex(t, 2));
            }
            count += meet ? 1 : 0;
        }
    }
    return count;
}

// Meshes made of the cases the check's shortcuts must get right: triangles on a small integer
// lattice (shared vertices and edges, coplanar overlaps, collinear triangles, touching corners),
// the same lattice moved far off the origin (rounded: nearly coplanar and nearly touching), fans
// wound more than once around a vertex (flat: overlapping coplanar sectors; lifted: sectors
// apart by a hair), and a finely tessellated tilted plane (nearly coplanar neighbours only), each
// at tiny and huge scales.
TEST(MeshCheck, SelfIntersectionsMatchEveryPairTestedExactly) {
    std::mt19937 rng(11);
    std::vector<std::pair<std::string, Mesh>> meshes;
    for (double scale : {0x1p-60, 1.0, 0x1p60}) {
        for (double offset : {0.0, 1000.1}) {
            std::vector<glm::dvec3> positions;
            for (int i = 0; i < 64; ++i) positions.push_back((glm::dvec3(i % 4, i / 4 % 4, i / 16) * 0.1 + offset) * scale);
            std::vector<glm::uvec3> triangles;
            while (triangles.size() < 240) {
                const glm::uvec3 t(rng() % 64, rng() % 64, rng() % 64);
                if (t.x != t.y && t.y != t.z && t.z != t.x) triangles.push_back(t);
            }
            meshes.emplace_back("lattice", buildMesh("lattice", positions, triangles));
        }
        for (double lift : {0.0, 1e-6}) {
            std::vector<glm::dvec3> positions{{0, 0, 0}};
            std::vector<glm::uvec3> triangles;
            for (int i = 0; i <= 24; ++i) {
                const double angle = 0.5 * i; // 12 radians: nearly two turns
                positions.push_back(glm::dvec3(std::cos(angle), std::sin(angle), lift * i) * scale);
                if (i > 0) triangles.push_back({0u, unsigned(i), unsigned(i + 1)});
            }
            meshes.emplace_back("fan", buildMesh("fan", positions, triangles));
        }
        std::vector<glm::dvec3> positions;
        std::vector<glm::uvec3> triangles;
        constexpr int kSide = 12;
        for (int i = 0; i <= kSide; ++i)
            for (int j = 0; j <= kSide; ++j) positions.push_back(glm::dvec3(i, j, 0.3 * i + 0.7 * j) * (scale / 7.0));
        for (unsigned i = 0; i < kSide; ++i) {
            for (unsigned j = 0; j < kSide; ++j) {
                const unsigned v = i * (kSide + 1) + j;
                triangles.push_back({v, v + kSide + 1, v + 1});
                triangles.push_back({v + 1, v + kSide + 1, v + kSide + 2});
            }
        }
        meshes.emplace_back("tilted plane", buildMesh("tilted plane", positions, triangles));
    }
    std::size_t total = 0;
    for (const auto& [name, mesh] : meshes) {
        const std::size_t expected = bruteForceCrossings(mesh);
        EXPECT_EQ(checkMesh(mesh).selfIntersections, expected) << name;
        total += expected;
        if (name == "tilted plane") {
            EXPECT_EQ(expected, 0u);
        }
    }
    EXPECT_GT(total, 1000u); // the lattices and the flat fans cross many times
}

TEST(MeshCheck, VerticesDuplicatedPerTriangleAreMerged) {
    for (const Mesh& shared : {test::icosphere(1.0f, 2), test::torus(1.0f, 0.3f, 24, 12), test::box({1.0f, 0.6f, 0.4f})}) {
        const Mesh soup = unshared(shared);
        ASSERT_EQ(soup.positions.size(), 3 * soup.triangleCount());
        const MeshCheck check = checkMesh(soup);
        EXPECT_TRUE(check.closedAndClean()) << shared.source << ": " << check.describe();
        EXPECT_TRUE(MeshTopology(soup).boundaryLoops().empty()) << shared.source;
        const BakeResult a = bakeWith(shared, 20, DistanceMethod::Exact, SignMethod::Auto);
        const BakeResult b = bakeWith(soup, 20, DistanceMethod::Exact, SignMethod::Auto);
        EXPECT_EQ(b.sign, SignMethod::Pseudonormal) << shared.source;
        const FieldDifference d = compareFields(a.field.dense(), b.field.dense(), 0.0);
        EXPECT_EQ(d.signDifferences, 0u) << shared.source;
        EXPECT_EQ(d.maxAbs, 0.0) << shared.source;
    }
}

} // namespace
} // namespace sdfgen

namespace sdfgen {
namespace {

// A refit topology (vertices moved, the same merges) equals a fresh build: loops, positions, the
// edge counts, the volume and the pseudonormals; merges that change are seen.
TEST(MeshTopologyRefit, EqualsAFreshBuildWhileTheMergesHold) {
    // Every triangle with its own three vertices (an unwelded OBJ), and a hole: merges decide everything.
    const Mesh welded = test::icosphere(1.0f, 2);
    std::vector<glm::dvec3> positions;
    std::vector<glm::uvec3> triangles;
    const std::vector<glm::dvec3> weldedPositions = welded.worldPositions();
    for (std::size_t t = 1; t < welded.triangleCount(); ++t) {
        const unsigned o = unsigned(positions.size());
        for (int c = 0; c < 3; ++c) positions.push_back(weldedPositions[welded.triangles[t][c]]);
        triangles.push_back({o, o + 1, o + 2});
    }
    const Mesh start = buildMesh("unwelded", positions, triangles);
    const MeshTopology topology(start);
    std::vector<glm::dvec3> moved = positions;
    for (glm::dvec3& p : moved) p += 0.1 * glm::dvec3(std::sin(3.0 * p.y), std::cos(2.0 * p.z), p.x * p.y);
    const Mesh movedMesh = buildMesh("moved", moved, triangles);
    ASSERT_TRUE(topology.groups()->holdFor(movedMesh.positions));
    const MeshTopology refit(topology, movedMesh), fresh(movedMesh);
    EXPECT_EQ(refit.boundaryLoops(), fresh.boundaryLoops());
    ASSERT_FALSE(fresh.boundaryLoops().empty());
    for (const std::vector<std::uint32_t>& loop : fresh.boundaryLoops()) {
        for (std::uint32_t v : loop) EXPECT_EQ(refit.position(v), fresh.position(v));
    }
    EXPECT_EQ(refit.edgeCheck().describe(), fresh.edgeCheck().describe());
    EXPECT_EQ(refit.edgeCheck().signedVolume, fresh.edgeCheck().signedVolume);
    EXPECT_NE(refit.edgeCheck().signedVolume, topology.edgeCheck().signedVolume);
    for (std::uint32_t t = 0; t < movedMesh.triangleCount(); t += 7) {
        for (const TriangleFeature f : {TriangleFeature::Face, TriangleFeature::EdgeAB, TriangleFeature::VertexC}) {
            EXPECT_EQ(refit.pseudonormal(t, f), fresh.pseudonormal(t, f)) << t;
        }
    }
    // A seam opened (one copy of a vertex moved alone), and two vertices brought together.
    std::vector<glm::dvec3> opened = moved;
    opened[0] += glm::dvec3(1e-3, 0.0, 0.0);
    EXPECT_FALSE(topology.groups()->holdFor(buildMesh("opened", opened, triangles).positions));
    std::vector<glm::dvec3> joined = moved;
    const glm::dvec3 target = moved[0];
    std::size_t farthest = 0;
    for (std::size_t i = 0; i < moved.size(); ++i) {
        if (glm::length(moved[i] - target) > glm::length(moved[farthest] - target)) farthest = i;
    }
    const glm::dvec3 away = moved[farthest];
    for (glm::dvec3& p : joined) {
        if (p == away) p = target; // the far vertex's group onto vertex 0's: no triangle collapses
    }
    const Mesh joinedMesh = buildMesh("joined", joined, triangles);
    ASSERT_EQ(joinedMesh.triangleCount(), movedMesh.triangleCount());
    EXPECT_FALSE(topology.groups()->holdFor(joinedMesh.positions));
}

// A closed mesh's fresh topology builds every vertex normal at once (in parallel blocks); a refit's
// measures each when first asked, from every thread at once: the same pseudonormals, bit for bit,
// along a chain of refits.
TEST(MeshTopologyRefit, VertexNormalsMeasuredOnUseEqualAFreshBuild) {
    const Mesh sphere = test::icosphere(1.0f, 3);
    const std::vector<glm::dvec3> start = sphere.worldPositions();
    std::unique_ptr<MeshTopology> previous = std::make_unique<MeshTopology>(sphere);
    for (int step = 1; step <= 2; ++step) {
        std::vector<glm::dvec3> moved = start;
        for (glm::dvec3& p : moved) p += 0.05 * step * glm::dvec3(std::sin(3.0 * p.y), std::cos(2.0 * p.z), p.x * p.y);
        const Mesh movedMesh = buildMesh("moved", moved, sphere.triangles);
        ASSERT_TRUE(previous->groups()->holdFor(movedMesh.positions));
        auto refit = std::make_unique<MeshTopology>(*previous, movedMesh);
        const MeshTopology fresh(movedMesh);
        ASSERT_TRUE(fresh.edgeCheck().closedAndClean());
        const std::size_t count = movedMesh.triangleCount();
        std::vector<glm::dvec3> asked(3 * count);
        RunControl control;
        control.threads = 2;
        parallelFor(count, control, [&](std::size_t t) { // the triangles' vertices asked for concurrently
            for (int c = 0; c < 3; ++c) {
                const TriangleFeature vertex[3] = {TriangleFeature::VertexA, TriangleFeature::VertexB, TriangleFeature::VertexC};
                asked[3 * t + std::size_t(c)] = refit->pseudonormal(std::uint32_t(t), vertex[c]);
            }
        });
        for (std::uint32_t t = 0; t < count; ++t) {
            EXPECT_EQ(asked[3 * t], fresh.pseudonormal(t, TriangleFeature::VertexA)) << t;
            EXPECT_EQ(asked[3 * t + 1], fresh.pseudonormal(t, TriangleFeature::VertexB)) << t;
            EXPECT_EQ(asked[3 * t + 2], fresh.pseudonormal(t, TriangleFeature::VertexC)) << t;
            EXPECT_EQ(refit->pseudonormal(t, TriangleFeature::VertexB), asked[3 * t + 1]) << t; // stored, then read
        }
        previous = std::move(refit);
    }
}

// A refit's side of a vertex's pseudonormal is settled by the faces around the vertex where they
// agree, without measuring the normal: the same answer as the fresh build's normal, bit for bit,
// for offsets anywhere, along a face's plane up to rounding, tiny and zero, at every vertex of a
// sphere and of the bunny (concave vertices, holes).
TEST(MeshTopologyRefit, FacesAwayEqualsTheMeasuredPseudonormalsSide) {
    std::mt19937 rng(31);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (const Mesh& mesh : {test::icosphere(1.0f, 3), loadObj(test::bundledBunnyPath())}) {
        SCOPED_TRACE(mesh.source);
        const std::vector<glm::dvec3> start = mesh.worldPositions();
        std::vector<glm::dvec3> moved = start;
        for (glm::dvec3& p : moved) p += 0.01 * glm::dvec3(std::sin(3.0 * p.y), std::cos(2.0 * p.z), p.x * p.y);
        const Mesh movedMesh = buildMesh("moved", moved, mesh.triangles);
        ASSERT_EQ(movedMesh.triangleCount(), mesh.triangleCount());
        const MeshTopology topology(mesh);
        ASSERT_TRUE(topology.groups()->holdFor(movedMesh.positions));
        const MeshTopology refit(topology, movedMesh), fresh(movedMesh);
        for (std::uint32_t t = 0; t < movedMesh.triangleCount(); ++t) {
            for (const TriangleFeature f : {TriangleFeature::VertexA, TriangleFeature::VertexB, TriangleFeature::VertexC}) {
                const glm::dvec3 n = fresh.pseudonormal(t, f), face(movedMesh.faceNormals[t]);
                const glm::dvec3 side = glm::cross(face, glm::dvec3(u(rng), u(rng), u(rng)));
                for (const glm::dvec3& d : {glm::dvec3(u(rng), u(rng), u(rng)), n, -n, side, side + 1e-17 * face, side - 1e-17 * face,
                                            1e-300 * n, glm::dvec3(0.0)}) {
                    EXPECT_EQ(refit.facesAway(t, f, d), glm::dot(d, n) < 0.0) << t;
                }
            }
        }
        // Then every normal measured (as a query would, where the faces disagree): still equal.
        for (std::uint32_t t = 0; t < movedMesh.triangleCount(); ++t) {
            EXPECT_EQ(refit.pseudonormal(t, TriangleFeature::VertexA), fresh.pseudonormal(t, TriangleFeature::VertexA));
            const glm::dvec3 d(u(rng), u(rng), u(rng));
            EXPECT_EQ(refit.facesAway(t, TriangleFeature::VertexA, d), glm::dot(d, fresh.pseudonormal(t, TriangleFeature::VertexA)) < 0.0);
            EXPECT_EQ(refit.facesAway(t, TriangleFeature::Face, d), glm::dot(d, glm::dvec3(movedMesh.faceNormals[t])) < 0.0);
        }
    }
}

} // namespace
} // namespace sdfgen

namespace sdfgen {
namespace {

// Vertex groups (coincident vertices merged) and the linear test of whether moved vertices keep
// them, which decides whether a model is refit or built afresh.
TEST(VertexGroups, HoldWhileEveryGroupMovesTogetherAndNoTwoMeet) {
    // Vertices 0 and 2 coincide, as do 1 and 4 (-0 and +0 alike); 3 is alone.
    const std::vector<glm::vec3> start{{0, 0, 0}, {1, -0.0f, 2}, {0, 0, 0}, {5, 5, 5}, {1, 0, 2}};
    const VertexGroups groups(start);
    ASSERT_EQ(groups.count(), 3u);
    EXPECT_EQ(groups.groupOf(0), 0u);
    EXPECT_EQ(groups.groupOf(2), 0u);
    EXPECT_EQ(groups.groupOf(1), 1u);
    EXPECT_EQ(groups.groupOf(4), 1u);
    EXPECT_EQ(groups.groupOf(3), 2u);
    EXPECT_EQ(groups.firstVertex(1), 1u);
    EXPECT_TRUE(groups.holdFor(start));
    std::vector<glm::vec3> moved{{0.5f, 0, 0}, {1, 1, 2}, {0.5f, 0, 0}, {5, 6, 5}, {1, 1, 2}};
    EXPECT_TRUE(groups.holdFor(moved));
    std::vector<glm::vec3> split = moved;
    split[2].x = 0.25f; // vertex 2 leaves vertex 0
    EXPECT_FALSE(groups.holdFor(split));
    std::vector<glm::vec3> joined = moved;
    joined[3] = joined[1]; // vertex 3 lands on group 1
    EXPECT_FALSE(groups.holdFor(joined));
    std::vector<glm::vec3> signedZero = {{0, 0, 0}, {1, 1, 2}, {0, 0, 0}, {-0.0f, 0, -0.0f}, {1, 1, 2}};
    EXPECT_FALSE(groups.holdFor(signedZero)); // -0 lands on +0: one position
    EXPECT_FALSE(groups.holdFor(std::vector<glm::vec3>(moved.begin(), moved.end() - 1)));
    // Many groups (the hash table's probes): every vertex of a grid moved, then one pair made to meet.
    std::vector<glm::vec3> grid;
    for (int i = 0; i < 40; ++i)
        for (int j = 0; j < 40; ++j)
            for (int k = 0; k < 10; ++k) grid.emplace_back(float(i), float(j), float(k)); // integers: equal low mantissa bits
    const VertexGroups gridGroups(grid);
    ASSERT_EQ(gridGroups.count(), grid.size());
    for (glm::vec3& p : grid) p *= 2.0f;
    EXPECT_TRUE(gridGroups.holdFor(grid));
    grid[12345] = grid[777];
    EXPECT_FALSE(gridGroups.holdFor(grid));
}

} // namespace
} // namespace sdfgen
