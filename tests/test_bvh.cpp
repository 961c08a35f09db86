// The BVH's nearest hit equals brute force over every triangle.
#include "core/accel/bvh.hpp"
#include "support/shapes.hpp"
#include "support/binary_rays.hpp"

#include "support/checks.hpp"
#include <gtest/gtest.h>
#include <tuple>
#include <glm/geometric.hpp>
#include <limits>
#include <random>

namespace sdfgen {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

bool bruteForce(const Mesh& mesh, const glm::vec3& o, const glm::vec3& d, test::RayHit& best) {
    bool found = false;
    for (std::size_t i = 0; i < mesh.triangleCount(); ++i) {
        const PreparedTriangle tri = prepareTriangle(mesh.vertex(i, 0), mesh.vertex(i, 1), mesh.vertex(i, 2));
        float t = 0;
        bool back = false;
        if (intersectTriangle(o.x, o.y, o.z, d, tri, found ? best.t : kInf, t, back)) {
            best = {t, std::uint32_t(i), back};
            found = true;
        }
    }
    return found;
}

float hitDistance(const Mesh& mesh, std::uint32_t triangle, const glm::vec3& o, const glm::vec3& d) {
    const PreparedTriangle tri = prepareTriangle(mesh.vertex(triangle, 0), mesh.vertex(triangle, 1), mesh.vertex(triangle, 2));
    float t = kInf;
    bool back = false;
    intersectTriangle(o.x, o.y, o.z, d, tri, kInf * 1.0f, t, back);
    return t;
}

void expectTreeMatchesBruteForce(const Mesh& mesh, int rays, unsigned seed) {
    const Bvh tree(mesh);
    std::mt19937 rng(seed);
    std::normal_distribution<float> gauss;
    const glm::vec3 lo = mesh.bounds.min - 0.2f * mesh.bounds.extent();
    const glm::vec3 hi = mesh.bounds.max + 0.2f * mesh.bounds.extent();
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    int hits = 0;
    for (int r = 0; r < rays; ++r) {
        const glm::vec3 o = lo + glm::vec3(unit(rng), unit(rng), unit(rng)) * (hi - lo);
        const glm::vec3 d = glm::normalize(glm::vec3(gauss(rng), gauss(rng), gauss(rng)));
        test::RayHit expected, actual;
        const bool bruteHit = bruteForce(mesh, o, d, expected);
        const bool treeHit = test::intersect(mesh, tree, o, d, kInf, actual);
        ASSERT_EQ(treeHit, bruteHit) << "ray " << r;
        if (!bruteHit) continue;
        ++hits;
        if (actual.triangle == expected.triangle) {
            EXPECT_EQ(actual.t, expected.t) << "ray " << r;
            EXPECT_EQ(actual.backFace, expected.backFace) << "ray " << r;
        } else {
            // Only a tie may pick another triangle: a ray through a shared edge or vertex.
            EXPECT_NEAR(actual.t, expected.t, 1e-6f * expected.t) << "ray " << r;
            EXPECT_NEAR(hitDistance(mesh, actual.triangle, o, d), expected.t, 1e-6f * expected.t) << "ray " << r;
        }
    }
    EXPECT_GT(hits, rays / 10) << "too few hits to test anything";
}

TEST(Bvh, NearestHitMatchesBruteForceOnTheBunny) {
    const Mesh mesh = loadMesh(test::bundledBunnyPath());
    expectTreeMatchesBruteForce(mesh, 3000, 1);
}

TEST(Bvh, NearestHitMatchesBruteForceOnGeneratedShapes) {
    expectTreeMatchesBruteForce(test::icosphere(1.0f, 3), 2000, 2);
    expectTreeMatchesBruteForce(test::torus(1.0f, 0.3f, 48, 24), 2000, 3);
    expectTreeMatchesBruteForce(test::box({1.0f, 0.5f, 0.25f}), 2000, 4);
}

TEST(Bvh, AxisAlignedRaysAndRaysFromInside) {
    // Zero direction components take the slab test's special path.
    const Mesh mesh = test::box({1.0f, 1.0f, 1.0f});
    const Bvh tree(mesh);
    const glm::vec3 axes[] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const glm::vec3& d : axes) {
        test::RayHit hit;
        ASSERT_TRUE(test::intersect(mesh, tree, {0.1f, 0.2f, 0.3f}, d, kInf, hit));
        EXPECT_TRUE(hit.backFace);
        EXPECT_NEAR(hit.t, 1.0f - glm::dot(glm::vec3(0.1f, 0.2f, 0.3f), d), 1e-6f);
        ASSERT_TRUE(test::intersect(mesh, tree, -3.0f * d, d, kInf, hit));
        EXPECT_FALSE(hit.backFace);
        EXPECT_FLOAT_EQ(hit.t, 2.0f);
        EXPECT_FALSE(test::intersect(mesh, tree, -3.0f * d, d, 1.5f, hit)); // tMax stops short of the box
    }
}

TEST(Bvh, BoundedLeavesAndDepth) {
    const Mesh mesh = loadMesh(test::bundledBunnyPath());
    const Bvh tree(mesh);
    // Well short of the build's hard limit (kMaxDepth), which a balanced SAH tree never reaches.
    EXPECT_LE(test::treeDepth(tree), 32) << "limit " << Bvh::kMaxDepth;
    EXPECT_LT(tree.nodeCount(), 2 * mesh.triangleCount());
    EXPECT_EQ(tree.bounds().min, mesh.bounds.min);
    EXPECT_EQ(tree.bounds().max, mesh.bounds.max);
}

TEST(Bvh, CoincidentTrianglesStillSplit) {
    // 1000 copies of one triangle: no plane separates them, yet leaves stay bounded and rays still hit.
    std::vector<glm::vec3> positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    std::vector<glm::uvec3> triangles(1000, glm::uvec3(0, 1, 2));
    const Mesh mesh = buildMesh("stack", positions, triangles);
    const Bvh tree(mesh);
    // Halving 1000 copies down to leaves of at most kMaxLeafSize takes about log2(1000 / 8) levels.
    EXPECT_LE(test::treeDepth(tree), 10);
    test::RayHit hit;
    ASSERT_TRUE(test::intersect(mesh, tree, glm::vec3(mesh.toLocal({0.2, 0.2, 1.0})), {0, 0, -1}, kInf, hit));
    EXPECT_FLOAT_EQ(float(hit.t * mesh.unit), 1.0f);
}

TEST(Bvh, BuildsAndBakesAtExtremeCoordinateSpans) {
    // The audit's crashes: centres spanning beyond float range on an axis, and a cube of side 3e-38
    // with one vertex at z = 1e-40 (differences below the smallest normal float).
    const Mesh cube = test::box(glm::vec3(0.5f));
    std::vector<glm::dvec3> huge = cube.worldPositions(), tiny = cube.worldPositions(), mixed;
    std::vector<glm::uvec3> triangles = cube.triangles, twoCubes = cube.triangles;
    for (glm::dvec3& p : huge) p *= 1e36;
    for (glm::dvec3& p : tiny) p *= 3e-38;
    tiny[0].z = 1e-40;
    // Two cubes far apart: deep nodes of the tree hold spans 1e-30 of the whole.
    mixed = cube.worldPositions();
    for (const glm::dvec3& p : cube.worldPositions()) mixed.push_back(p * 1e-30 + glm::dvec3(1e-3, 0, 0));
    for (const glm::uvec3& t : cube.triangles) twoCubes.push_back(t + glm::uvec3(unsigned(cube.positions.size())));
    for (const auto& [name, positions, faces] : {std::tuple{"huge", huge, triangles}, {"tiny", tiny, triangles}, {"mixed", mixed, twoCubes}}) {
        SCOPED_TRACE(name);
        const Mesh mesh = buildMesh(name, positions, faces);
        const Bvh tree(mesh);
        EXPECT_GT(tree.nodeCount(), 0u);
        BakeSettings settings;
        settings.res = 8;
        const Field field = test::bakeMesh(mesh, settings).field.dense();
        for (float v : field.values) ASSERT_TRUE(std::isfinite(v));
    }
    // Beyond what float distances can hold: the tree builds, and the bake is a clear refusal.
    std::vector<glm::dvec3> beyond = cube.worldPositions();
    for (glm::dvec3& p : beyond) p *= 3e38;
    const Mesh mesh = buildMesh("beyond", beyond, triangles);
    const Bvh tree(mesh);
    BakeSettings settings;
    settings.res = 8;
    EXPECT_CONTAINS(test::errorFrom([&] { test::bakeMesh(mesh, settings); }),
                    "the mesh is 3e+38 across; with padding 0.1 its grid would be 3.6e+38 across, beyond the 1e+37");
}

} // namespace
} // namespace sdfgen
