// The mesh check's counts on generated broken meshes, and the sign that auto picks from them.
#include "sdfgen/compare.hpp"
#include "core/topology.hpp"
#include "support/broken_meshes.hpp"
#include "support/checks.hpp"
#include "support/reference.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>
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
    EXPECT_EQ(result.field.parameter("sign"), "auto/pseudonormal");
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
        EXPECT_EQ(result.field.parameter("sign"), "auto/winding") << shape.name;
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
    const Field brute = bakeWith(mesh, 16, DistanceMethod::Brute, SignMethod::Auto).field;
    EXPECT_EQ(compareFields(result.field, brute, 1.0).signDifferences, 0u);
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
        const FieldDifference d = compareFields(a.field, b.field, 0.0);
        EXPECT_EQ(d.signDifferences, 0u) << shared.source;
        EXPECT_EQ(d.maxAbs, 0.0) << shared.source;
    }
}

} // namespace
} // namespace sdfgen
