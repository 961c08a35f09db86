// Exact copies of triangles: held once in the tree, counted per pair of copies by the mesh check,
// crossed once with a weight by the winding sign, and boundary loops of stacked open triangles
// walked in linear time. The field must be the one the triangle-by-triangle definition gives.
#include "core/accel/bvh.hpp"
#include "core/mesh/triangle_copies.hpp"
#include "core/distance/exact.hpp"
#include "core/bake/memory_estimate.hpp"
#include "core/runtime/memory.hpp"
#include "core/mesh/sample_positions.hpp"
#include "core/sign/winding_sign.hpp"
#include "core/accel/topology.hpp"
#include "sdfgen/model.hpp"
#include "support/checks.hpp"
#include "support/binary_rays.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>
#include <cmath>
#include <limits>

namespace sdfgen {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// `copies` copies of each triangle of `mesh`, every other one starting at another corner.
Mesh repeated(const Mesh& mesh, int copies) {
    std::vector<glm::uvec3> triangles;
    for (int copy = 0; copy < copies; ++copy) {
        for (const glm::uvec3& f : mesh.triangles) triangles.push_back(copy % 2 ? glm::uvec3(f.z, f.x, f.y) : f);
    }
    return buildMesh(mesh.source + " x" + std::to_string(copies), mesh.worldPositions(), triangles);
}

Mesh tetrahedron() {
    return buildMesh("tetrahedron", std::vector<glm::vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
                     {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}});
}

// Every triangle the tree reports for a box around everything.
std::size_t trianglesReached(const Bvh& tree) {
    const float big = std::numeric_limits<float>::max();
    std::size_t count = 0;
    tree.forEachOverlap({glm::vec3(-big), glm::vec3(big)}, [&](std::uint32_t) { ++count; });
    return count;
}

TEST(TriangleCopies, SameCornersInTheSameCyclicOrderAreCopies) {
    std::vector<glm::vec3> positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-0.0f, 0, 0}};
    // 0: a triangle; 1: it rotated; 2: it flipped (not a copy); 3: it with -0 for +0 (a copy);
    // 4: another triangle; 5: a copy of it.
    const Mesh mesh = buildMesh("copies", positions, {{0, 1, 2}, {1, 2, 0}, {0, 2, 1}, {4, 1, 2}, {0, 1, 3}, {3, 0, 1}});
    const TriangleCopies copies = findTriangleCopies(mesh);
    EXPECT_EQ(copies.unique, (std::vector<std::uint32_t>{0, 2, 4}));
    EXPECT_EQ(copies.count, (std::vector<std::uint32_t>{3, 1, 2}));
    EXPECT_EQ(copies.first, (std::vector<std::uint32_t>{0, 0, 2, 0, 4, 4}));
    EXPECT_FALSE(copies.none());
    EXPECT_TRUE(findTriangleCopies(test::icosphere(1.0f, 2)).none());
}

// Regression: a stack of copies made every query that reached it visit each copy. The tree holds
// one copy, reports the first (the lowest index, as brute force would) and answers as before.
TEST(Bvh, CopiesOfTrianglesAreHeldOnce) {
    const Mesh one = test::box({1.0f, 0.5f, 0.25f});
    const Mesh copies = repeated(one, 2000);
    const Bvh tree(copies);
    EXPECT_EQ(tree.triangleCount(), one.triangleCount());
    EXPECT_EQ(trianglesReached(tree), one.triangleCount());
    for (std::uint32_t t = 0; t < copies.triangleCount(); ++t) {
        ASSERT_EQ(tree.copies(t), t < one.triangleCount() ? 2000u : 0u) << t;
    }
    const Grid grid = makeGrid(copies.worldBounds(), 12, 0.2);
    const NearestField expected = computeNearest(one, Bvh(one), grid, RunControl{});
    const NearestField actual = computeNearest(copies, tree, grid, RunControl{});
    EXPECT_EQ(actual.distance, expected.distance);
    EXPECT_EQ(actual.triangle, expected.triangle); // the first copies carry the single mesh's indices
    test::RayHit hit;
    ASSERT_TRUE(test::intersect(copies, tree, glm::vec3(copies.toLocal({0.2, 0.2, 2.0})), {0, 0, -1}, kInf, hit));
    EXPECT_FLOAT_EQ(float(hit.t * copies.unit), 1.75f);
    EXPECT_LT(hit.triangle, one.triangleCount());
}

// Centroids spaced exponentially make every SAH split peel off one triangle; the build must fall
// back to median splits and keep depth, leaves and every triangle.
TEST(Bvh, ExponentiallySpacedTrianglesKeepDepthAndLeavesBounded) {
    std::vector<glm::dvec3> positions;
    std::vector<glm::uvec3> triangles;
    // x = ±2^-30 .. ±2^29, symmetric so that the mesh's local origin stays at 0 and each is exact.
    auto xOf = [](int i) { return (i % 2 ? 1.0 : -1.0) * std::ldexp(1.0, i / 2 - 30); };
    for (int i = 0; i < 120; ++i) {
        const double x = xOf(i);
        const unsigned base = unsigned(positions.size());
        positions.insert(positions.end(), {{x, 0, 0}, {x, 1, 0}, {x, 0, 1}});
        triangles.emplace_back(base, base + 1, base + 2);
    }
    const Mesh mesh = buildMesh("exponential", positions, triangles);
    const Bvh tree(mesh);
    EXPECT_LT(test::treeDepth(tree), Bvh::kMaxDepth);
    EXPECT_EQ(trianglesReached(tree), mesh.triangleCount());
    test::RayHit hit;
    for (int i : {1, 61, 119}) { // a ray along +x from just before triangle i (x > 0) hits it
        const double x = xOf(i);
        ASSERT_TRUE(test::intersect(mesh, tree, glm::vec3(mesh.toLocal({x * 0.75, 0.2, 0.2})), {1, 0, 0}, kInf, hit)) << i;
        EXPECT_EQ(hit.triangle, std::uint32_t(i));
    }
}

// The memory check counts a set of copies' row crossings once, as the scan makes them: 100000
// copies of a tetrahedron at res 256 need the single tetrahedron's bytes plus the topology of the
// copies (they were refused as ~68 GiB).
TEST(BakeMemory, CopiesCrossTheRowsOnceInTheEstimate) {
    const Mesh one = tetrahedron(), many = repeated(one, 100000);
    const Bvh oneTree(one), manyTree(many);
    const Grid grid = makeGrid(many.worldBounds(), 256, 0.1f);
    BakeSettings winding;
    winding.sign = SignMethod::Winding;
    const double single = double(estimateBakeBytes(one, grid, winding, false, &oneTree));
    const double copies = double(estimateBakeBytes(many, grid, winding, false, &manyTree));
    EXPECT_GT(copies, single);
    EXPECT_LT(copies - single, 200.0 * double(many.triangleCount()));
    EXPECT_NO_THROW(checkBakeMemory(many, manyTree, grid, winding, false));
}

// The mesh check counts copies as the triangle-by-triangle definition would, without pairing them.
TEST(MeshCheck, CopiesCountAsOftenAsTheyOccur) {
    // Two triangles crossing each other, each three times: 9 crossing pairs.
    std::vector<glm::vec3> positions = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}, {0, -0.5f, -1}, {0, -0.5f, 1}, {0, 0.5f, 0}};
    const Mesh pair = buildMesh("crossing pair", positions, {{0, 1, 2}, {3, 4, 5}});
    EXPECT_EQ(MeshTopology(pair).check(pair, Bvh(pair)).selfIntersections, 1u);
    const Mesh tripled = repeated(pair, 3);
    EXPECT_EQ(MeshTopology(tripled).check(tripled, Bvh(tripled)).selfIntersections, 9u);
}

// Regression (issue 8, item 5): 1e5 copies of a tetrahedron took 56 s at res 16 (every triangle
// paired with every copy in the mesh check, every copy crossed every row). Now the tree, the check
// and the crossing scan each see four triangles with a count, and the field is the one the
// definition gives: the tetrahedron's distances, inside where its winding number (1e5) is.
TEST(TriangleCopies, AHundredThousandCopiesOfATetrahedronBakeAsOne) {
    const Mesh one = tetrahedron();
    const Mesh many = repeated(one, 100000);
    ASSERT_EQ(many.triangleCount(), 400000u);
    const Model model(many);
    const MeshCheck& check = model.check();
    EXPECT_EQ(check.nonManifoldEdges, 6u) << check.describe(); // every edge shared by 200000 triangles
    EXPECT_EQ(check.boundaryEdges, 0u);
    EXPECT_EQ(check.inconsistentEdges, 0u);
    EXPECT_EQ(check.selfIntersections, 0u);
    const MeshTopology topology(many);
    EXPECT_TRUE(topology.boundaryLoops().empty());
    for (std::uint32_t t = 0; t < 8; ++t) EXPECT_EQ(topology.copies(t), t < 4 ? 100000u : 0u) << t;
    EXPECT_EQ(Bvh(many).triangleCount(), 4u);

    BakeSettings settings;
    settings.res = 16;
    const BakeResult result = model.bake(settings);
    EXPECT_EQ(result.sign, SignMethod::Winding) << result.signReason;
    BakeSettings winding = settings;
    winding.sign = SignMethod::Winding;
    const BakeResult single = Model(one).bake(winding);
    EXPECT_EQ(result.field.dense().values, single.field.dense().values);
    std::size_t inside = 0;
    for (float v : single.field.dense().values) inside += v < 0.0f;
    EXPECT_GT(inside, 0u);
}

// Copies of an open triangle: one boundary loop per copy, all equal. They are walked in linear
// time and closed by one fan with a weight, and the signs are those of the weighted reference.
TEST(TriangleCopies, StackedOpenTrianglesShareOneFan) {
    const Mesh open = buildMesh("open tetrahedron", std::vector<glm::vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
                                {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}});
    constexpr int kCopies = 20000;
    const Mesh many = repeated(open, kCopies);
    const MeshTopology topology(many);
    EXPECT_EQ(topology.boundaryLoops().size(), std::size_t(kCopies));
    const WindingCaps caps(topology);
    ASSERT_EQ(caps.caps().size(), 1u);
    EXPECT_EQ(caps.caps()[0].weight, kCopies);

    const Grid grid = makeGrid(many.worldBounds(), 12, 0.15);
    const std::vector<std::uint8_t> inside = insideByWinding(many, topology, grid, RunControl{});
    std::size_t compared = 0, in = 0, inOnce = 0;
    for (int k = 0; k < grid.dims.z; ++k)
        for (int j = 0; j < grid.dims.y; ++j)
            for (int i = 0; i < grid.dims.x; ++i) {
                const double w = kCopies * windingNumber(open, localPosition(open, grid, i, j, k));
                if (std::fabs(std::fabs(w) - 0.5) < 1e-6) continue;
                ++compared;
                in += std::fabs(w) > 0.5;
                inOnce += std::fabs(w / kCopies) > 0.5;
                ASSERT_EQ(bool(inside[grid.index(i, j, k)]), std::fabs(w) > 0.5) << i << "," << j << "," << k << ": w = " << w;
            }
    EXPECT_GT(compared, grid.sampleCount() * 9 / 10);
    // |w| > 1/2 nearly everywhere around so many copies; one copy alone would have few samples
    // inside: the fan's weight decides.
    EXPECT_GT(in, compared * 9 / 10);
    EXPECT_LT(inOnce, in / 2);

    // Point queries count the same weighted crossings as the bake's rows.
    const Model model(many);
    BakeSettings settings;
    settings.res = 12;
    settings.padding = 0.15;
    settings.sign = SignMethod::Winding;
    const Field field = model.bake(settings).field.dense();
    std::vector<glm::dvec3> points;
    for (int k = 0; k < grid.dims.z; k += 3)
        for (int j = 0; j < grid.dims.y; ++j)
            for (int i = 0; i < grid.dims.x; ++i) points.push_back(grid.position(i, j, k));
    std::vector<float> signedDistance(points.size());
    std::vector<double> xyz;
    for (const glm::dvec3& p : points) xyz.insert(xyz.end(), {p.x, p.y, p.z});
    PointQueryOutputs out;
    out.signedDistance = signedDistance.data();
    model.query(xyz.data(), points.size(), out, SignMethod::Winding);
    std::size_t n = 0;
    for (int k = 0; k < grid.dims.z; k += 3)
        for (int j = 0; j < grid.dims.y; ++j)
            for (int i = 0; i < grid.dims.x; ++i, ++n) ASSERT_EQ(signedDistance[n], field.at(i, j, k)) << i << "," << j << "," << k;
}

} // namespace
} // namespace sdfgen
