// The sign methods against the brute-force reference and the reference winding number.
#include "sdfgen/compare.hpp"
#include "core/distance/exact.hpp"
#include "core/mesh/sample_positions.hpp"
#include "core/sign/winding_sign.hpp"
#include "core/accel/topology.hpp"
#include "support/broken_meshes.hpp"
#include "support/reference.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <algorithm>
#include <utility>
#include <vector>

namespace sdfgen {
namespace {

using namespace test;

TEST(Signs, PseudonormalAndWindingEqualBruteOnClosedMeshes) {
    for (const Shape& shape : closedShapes()) {
        const Field& brute = bruteField(shape.name, shape.mesh, shape.res);
        for (SignMethod sign : {SignMethod::Pseudonormal, SignMethod::Winding}) {
            const BakeResult result = bakeWith(shape.mesh, shape.res, DistanceMethod::Exact, sign);
            EXPECT_EQ(result.sign, sign);
            EXPECT_FALSE(result.checked);
            const SignCounts c = countSigns(result.field.dense(), brute);
            EXPECT_EQ(c.farWrong, 0u) << shape.name << " " << toString(sign);
            EXPECT_GT(c.referenceInside, 0u) << shape.name;
            EXPECT_EQ(compareFields(result.field.dense(), brute, 1.0).signDifferences, c.farWrong);
        }
    }
}

// An open mesh's vertex normals are built by the first pseudonormal that needs one (the topology
// builds them only when its edges leave the pseudonormal possible): the same normals as the
// closed mesh's where no triangle is missing around the vertex, and the same forced
// pseudonormal field whatever the thread count, which races the first uses against each other.
TEST(Signs, PseudonormalOfAnOpenMeshBuildsItsVertexNormalsOnFirstUse) {
    const Mesh closed = icosphere(1.0f, 2);
    const std::vector<glm::uvec3> kept(closed.triangles.begin(), closed.triangles.end() - 1);
    const glm::uvec3 removed = closed.triangles.back();
    const Mesh open = buildMesh("icosphere less one triangle", closed.worldPositions(), kept);
    const MeshTopology closedTopology(closed), openTopology(open);
    ASSERT_TRUE(closedTopology.edgeCheck().closedAndClean());
    ASSERT_EQ(openTopology.edgeCheck().boundaryEdges, 3u);
    const TriangleFeature corners[3] = {TriangleFeature::VertexA, TriangleFeature::VertexB, TriangleFeature::VertexC};
    std::size_t compared = 0;
    for (std::uint32_t t = 0; t < open.triangleCount(); ++t) {
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t vertex = open.triangles[t][c];
            const TriangleFeature feature = corners[c];
            const glm::dvec3 n = openTopology.pseudonormal(t, feature);
            EXPECT_GT(glm::dot(n, glm::dvec3(open.faceNormals[t])), 0.0) << t;
            if (vertex == removed.x || vertex == removed.y || vertex == removed.z) continue;
            EXPECT_EQ(n, closedTopology.pseudonormal(t, feature)) << t;
            ++compared;
        }
    }
    EXPECT_GT(compared, 3 * open.triangleCount() / 2);
    const BakeResult one = bakeWith(open, 24, DistanceMethod::Exact, SignMethod::Pseudonormal, 1);
    const BakeResult two = bakeWith(open, 24, DistanceMethod::Exact, SignMethod::Pseudonormal, 2);
    EXPECT_EQ(one.sign, SignMethod::Pseudonormal);
    EXPECT_EQ(one.field.dense().values, two.field.dense().values);
    EXPECT_LT(*std::min_element(one.field.dense().values.begin(), one.field.dense().values.end()), 0.0f) << "the inside is signed";
}

TEST(Signs, WindingEqualsBruteOnOpenAndOverlappingMeshes) {
    for (const Shape& shape : openShapes()) {
        const Field& brute = bruteField(shape.name, shape.mesh, shape.res);
        const BakeResult result = bakeWith(shape.mesh, shape.res, DistanceMethod::Exact, SignMethod::Winding);
        const SignCounts c = countSigns(result.field.dense(), brute);
        EXPECT_EQ(c.farWrong, 0u) << shape.name;
        // Not vacuous: the shapes with an inside have one (a flat disk's |w| stays below 1/2; the
        // cup has an inside either way round, |w| > 1/2 within it).
        if (shape.name == "disk") {
            EXPECT_EQ(c.referenceInside, 0u);
        } else {
            EXPECT_GT(c.referenceInside, 0u) << shape.name;
        }
    }
}

// Rows of samples that run exactly through an edge shared by two triangles (here: a cube's face
// diagonals, which its symmetric grid's rows with j == k follow) must cross the surface once.
TEST(Signs, WindingCountsRowsThroughSharedEdgesOnce) {
    const Mesh cube = test::box({1.0f, 1.0f, 1.0f});
    std::vector<glm::uvec3> openTop;
    for (std::size_t t = 0; t < cube.triangleCount(); ++t) {
        const glm::vec3 centroid = (cube.vertex(t, 0) + cube.vertex(t, 1) + cube.vertex(t, 2)) / 3.0f;
        if (centroid.y < 0.9f) openTop.push_back(cube.triangles[t]);
    }
    const Mesh open = buildMesh("open-top cube", cube.worldPositions(), openTop);
    const std::pair<const char*, const Mesh*> meshes[] = {{"cube", &cube}, {"open-top cube", &open}};
    for (const auto& [name, mesh] : meshes) {
        for (int res : {12, 24, 32}) {
            // Sign auto picks the winding number for the open cube by itself.
            const BakeResult result =
                bakeWith(*mesh, res, DistanceMethod::Exact, mesh == &open ? SignMethod::Auto : SignMethod::Winding);
            ASSERT_EQ(result.sign, SignMethod::Winding);
            const Field& brute = bruteField(name, *mesh, res);
            const SignCounts c = countSigns(result.field.dense(), brute);
            EXPECT_EQ(c.farWrong, 0u) << name << " res " << res << ": " << c.farWrong << " of " << c.far
                                      << " samples beyond one voxel have the wrong sign";
        }
    }
}

TEST(Signs, WindingInsideMatchesTheReferenceWindingNumberExactly) {
    // Sample by sample against windingNumber() itself, on the shells with one flipped: there the
    // winding number is -1, 0 and 1 in different regions, and |w| > 1/2 is inside (both shells
    // solid but for their overlap, where the two cancel).
    const Mesh mesh = twoShells(true);
    const Grid grid = makeGrid(mesh.worldBounds(), 20, 0.1f);
    const std::vector<std::uint8_t> inside = insideByWinding(mesh, MeshTopology(mesh), grid, RunControl{});
    const NearestField nearest = computeNearest(mesh, Bvh(mesh), grid, RunControl{});
    std::size_t regions[3] = {0, 0, 0};
    for (int k = 0; k < grid.dims.z; ++k)
        for (int j = 0; j < grid.dims.y; ++j)
            for (int i = 0; i < grid.dims.x; ++i) {
                const std::size_t index = grid.index(i, j, k);
                if (nearest.distance[index] < 1e-3f * grid.voxel) continue;
                const double w = windingNumber(mesh, localPosition(mesh, grid, i, j, k));
                ++regions[w < -0.5 ? 0 : w < 0.5 ? 1 : 2];
                EXPECT_EQ(bool(inside[index]), std::fabs(w) > 0.5) << i << "," << j << "," << k << " w = " << w;
            }
    EXPECT_GT(regions[0], 0u);
    EXPECT_GT(regions[2], 0u);
}

} // namespace
} // namespace sdfgen
