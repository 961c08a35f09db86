// The BVH's nearest hit equals brute force over every triangle.
#include "core/bvh.hpp"
#include "core/exact.hpp"
#include "sdfgen/grid.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <limits>
#include <random>

namespace sdfgen {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

bool bruteForce(const Mesh& mesh, const glm::vec3& o, const glm::vec3& d, RayHit& best) {
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
        RayHit expected, actual;
        const bool bruteHit = bruteForce(mesh, o, d, expected);
        const bool treeHit = tree.intersect(o, d, kInf, actual);
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
    const Mesh mesh = loadObj(test::bundledBunnyPath());
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
        RayHit hit;
        ASSERT_TRUE(tree.intersect({0.1f, 0.2f, 0.3f}, d, kInf, hit));
        EXPECT_TRUE(hit.backFace);
        EXPECT_NEAR(hit.t, 1.0f - glm::dot(glm::vec3(0.1f, 0.2f, 0.3f), d), 1e-6f);
        ASSERT_TRUE(tree.intersect(-3.0f * d, d, kInf, hit));
        EXPECT_FALSE(hit.backFace);
        EXPECT_FLOAT_EQ(hit.t, 2.0f);
        EXPECT_FALSE(tree.intersect(-3.0f * d, d, 1.5f, hit)); // tMax stops short of the box
    }
}

TEST(Bvh, BoundedLeavesAndDepth) {
    const Mesh mesh = loadObj(test::bundledBunnyPath());
    const Bvh tree(mesh);
    EXPECT_LE(tree.depth(), Bvh::kMaxDepth);
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
    EXPECT_LE(tree.depth(), Bvh::kMaxDepth);
    RayHit hit;
    ASSERT_TRUE(tree.intersect({0.2f, 0.2f, 1.0f}, {0, 0, -1}, kInf, hit));
    EXPECT_FLOAT_EQ(hit.t, 1.0f);
}


// Every triangle of the mesh that forEachOverlap reports for a box around everything (first copies only).
std::size_t trianglesReached(const Bvh& tree) {
    const float big = std::numeric_limits<float>::max();
    std::size_t count = 0;
    tree.forEachOverlap({glm::vec3(-big), glm::vec3(big)}, [&](std::uint32_t) { ++count; });
    return count;
}

// Regression (fuzzing): centroid spans beyond the float range, or so small that their inverse
// overflows, made the binning index its bins with int(inf or NaN) and crash.
TEST(Bvh, BuildsAtAnyFloatSpan) {
    std::vector<glm::vec3> positions;
    std::vector<glm::uvec3> triangles;
    auto addTetrahedron = [&](glm::vec3 o, float s) {
        const unsigned base = unsigned(positions.size());
        positions.insert(positions.end(), {o, o + glm::vec3(s, 0, 0), o + glm::vec3(0, s, 0), o + glm::vec3(0, 0, s)});
        for (glm::uvec3 f : {glm::uvec3(0, 2, 1), glm::uvec3(0, 1, 3), glm::uvec3(0, 3, 2), glm::uvec3(1, 2, 3)}) triangles.push_back(f + base);
    };
    // Centres 6e38 apart on x (the float span overflows) and on every axis.
    for (float x : {-3e38f, 0.0f, 3e38f}) addTetrahedron({x, -x, x}, 1e37f);
    const Mesh huge = buildMesh("huge", positions, triangles);
    // A cube of side 3e-38 with one corner moved to z = 1e-40: spans whose inverse overflows.
    Mesh tiny = test::box({1.5e-38f, 1.5e-38f, 1.5e-38f});
    tiny.positions[0].z = 1e-40f;
    tiny = buildMesh("tiny", tiny.positions, tiny.triangles);
    for (const Mesh* mesh : std::initializer_list<const Mesh*>{&huge, &tiny}) {
        const Bvh tree(*mesh);
        EXPECT_LE(tree.depth(), Bvh::kMaxDepth) << mesh->source;
        EXPECT_EQ(trianglesReached(tree), mesh->triangleCount()) << mesh->source;
        const glm::vec3 centre = mesh->bounds.min * 0.5f + mesh->bounds.max * 0.5f;
        RayHit hit;
        tree.intersect(centre, {0, 0, 1}, kInf, hit); // must not crash; float overflow may miss
        PointPacket packet;
        packet.px = simd::splat(centre.x);
        packet.py = simd::splat(centre.y);
        packet.pz = simd::splat(centre.z);
        packet.bestSquared = simd::splat(kInf);
        packet.triangle = simd::splat(0);
        tree.nearest(packet);
        EXPECT_LT(std::uint32_t(packet.triangle[0]), mesh->triangleCount()) << mesh->source;
    }
}

// Centroids spaced exponentially make every SAH split peel off one triangle; the build must
// still bound its depth and its leaves, and keep every triangle.
TEST(Bvh, ExponentiallySpacedTrianglesKeepDepthAndLeavesBounded) {
    std::vector<glm::vec3> positions;
    std::vector<glm::uvec3> triangles;
    for (int i = 0; i < 120; ++i) {
        const float x = std::ldexp(1.0f, i - 60);
        const unsigned base = unsigned(positions.size());
        positions.insert(positions.end(), {{x, 0, 0}, {x, 1, 0}, {x, 0, 1}});
        triangles.emplace_back(base, base + 1, base + 2);
    }
    const Mesh mesh = buildMesh("exponential", positions, triangles);
    const Bvh tree(mesh);
    EXPECT_LE(tree.depth(), Bvh::kMaxDepth);
    EXPECT_EQ(trianglesReached(tree), mesh.triangleCount());
    RayHit hit;
    for (int i : {0, 60, 119}) { // a ray along +x from just before triangle i hits it
        const float x = std::ldexp(1.0f, i - 60);
        ASSERT_TRUE(tree.intersect({x * 0.75f, 0.2f, 0.2f}, {1, 0, 0}, kInf, hit)) << i;
        EXPECT_EQ(hit.triangle, std::uint32_t(i));
    }
}

// Regression: a stack of copies made every query that reached it visit each copy (quadratic time
// for 1e5 copies of a tetrahedron). The tree holds one copy and answers as before.
TEST(Bvh, CopiesOfTrianglesAreHeldOnce) {
    const Mesh one = test::box({1.0f, 0.5f, 0.25f});
    std::vector<glm::uvec3> triangles;
    for (int copy = 0; copy < 2000; ++copy) {
        for (std::size_t t = 0; t < one.triangleCount(); ++t) {
            glm::uvec3 f = one.triangles[t];
            if (copy % 3 == 1) f = {f.y, f.z, f.x}; // the same triangle starting at another corner
            triangles.push_back(f);
        }
    }
    const Mesh copies = buildMesh("copies", one.positions, triangles);
    const Bvh tree(copies);
    EXPECT_EQ(tree.triangleCount(), one.triangleCount());
    EXPECT_EQ(trianglesReached(tree), one.triangleCount());
    const Grid grid = makeGrid(copies.bounds, 12, 0.2f);
    const NearestField expected = computeNearest(one, Bvh(one), grid, RunControl{});
    const NearestField actual = computeNearest(copies, tree, grid, RunControl{});
    EXPECT_EQ(actual.distance, expected.distance);
    RayHit hit;
    ASSERT_TRUE(tree.intersect({0.2f, 0.2f, 2.0f}, {0, 0, -1}, kInf, hit));
    EXPECT_FLOAT_EQ(hit.t, 1.75f);
    EXPECT_EQ(copies.triangles[hit.triangle], one.triangles[hit.triangle]); // the first copy
}

} // namespace
} // namespace sdfgen
