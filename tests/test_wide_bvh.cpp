// The closest-point kernel: the 8-wide tree with triangle packets (core/accel/wide_bvh.hpp) and the
// brick candidate lists of the exact distance (core/distance/exact.hpp), against linear scans and brute
// force in double: random points and grid samples near and far, slivers and needles, copies of a
// triangle (ties to the lower index), huge and tiny scales, thread counts.
#include "core/distance/exact.hpp"
#include "core/mesh/geometry.hpp"
#include "core/distance/kernel.hpp"
#include "core/mesh/sample_positions.hpp"
#include "core/accel/topology.hpp"
#include "core/accel/wide_bvh.hpp"
#include "sdfgen/grid.hpp"
#include "sdfgen/model.hpp"
#include "support/checks.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

namespace sdfgen {
namespace {

// The kernel's answer by definition: the lowest (float squared distance, index) over every packet.
NearestSoFar linearScan(const WideBvh& tree, const glm::vec3& p) {
    NearestSoFar best{FLT_MAX, 0};
    for (const TrianglePacket& packet : tree.packets()) scanPacket(packet, p.x, p.y, p.z, best);
    return best;
}

double bruteDistance(const Mesh& mesh, const glm::dvec3& p) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        best = std::min(best, closestPointOnTriangle(p, glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)),
                                                     glm::dvec3(mesh.vertex(t, 2)))
                                  .distanceSquared);
    }
    return std::sqrt(best);
}

// A soup of random triangles, a fifth of them slivers (a corner on the opposite edge, up to
// rounding) or needles (two corners nearly coincident), with some exact copies of earlier ones.
Mesh soup(int count, double scale, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<glm::dvec3> positions;
    std::vector<glm::uvec3> triangles;
    for (int t = 0; t < count; ++t) {
        const glm::dvec3 centre(u(rng), u(rng), u(rng));
        glm::dvec3 a = centre + 0.1 * glm::dvec3(u(rng), u(rng), u(rng));
        glm::dvec3 b = centre + 0.1 * glm::dvec3(u(rng), u(rng), u(rng));
        glm::dvec3 c = centre + 0.1 * glm::dvec3(u(rng), u(rng), u(rng));
        if (t % 10 == 3) c = 0.3 * a + 0.7 * b + 1e-6 * glm::dvec3(u(rng), u(rng), u(rng)); // sliver
        if (t % 10 == 7) b = a + 1e-6 * glm::dvec3(u(rng), u(rng), u(rng));                 // needle
        const std::uint32_t first = std::uint32_t(positions.size());
        for (const glm::dvec3& v : {a, b, c}) positions.push_back(v * scale);
        triangles.push_back({first, first + 1, first + 2});
        if (t % 13 == 5) triangles.push_back(triangles[std::size_t(t) / 2]); // an exact copy of an earlier triangle
    }
    return buildMesh("soup", positions, triangles);
}

std::vector<glm::vec3> randomPoints(const Mesh& mesh, int count, float spread, unsigned seed) {
    std::mt19937 rng(seed);
    const glm::vec3 lo = mesh.bounds.min, size = mesh.bounds.extent();
    std::uniform_real_distribution<float> u(-spread, 1.0f + spread);
    std::vector<glm::vec3> points;
    for (int i = 0; i < count; ++i) points.push_back(lo + size * glm::vec3(u(rng), u(rng), u(rng)));
    return points;
}

void expectTreeEqualsLinearScan(const Mesh& mesh, const std::vector<glm::vec3>& points) {
    SCOPED_TRACE(mesh.source);
    const Bvh binary(mesh);
    const WideBvh tree(mesh, binary);
    std::size_t differing = 0;
    std::uint32_t hint = WideBvh::kEmpty;
    for (const glm::vec3& p : points) {
        const NearestSoFar expected = linearScan(tree, p);
        NearestSoFar fromTree{FLT_MAX, 0};
        tree.nearest(p.x, p.y, p.z, fromTree);
        const std::uint32_t seeded = nearestTriangle(tree, p, hint);
        differing += fromTree.triangle != expected.triangle || fromTree.distanceSquared != expected.distanceSquared ||
                     seeded != expected.triangle;
    }
    EXPECT_EQ(differing, 0u) << "of " << points.size();
}

// Each triangle is in exactly one packet (padding lanes repeat a triangle of their own packet),
// except later copies of a triangle, which the binary tree holds once, as its first copy.
void expectEveryTriangleOnce(const Mesh& mesh, const Bvh& binary, const WideBvh& tree) {
    std::vector<int> seen(mesh.triangleCount());
    for (const TrianglePacket& packet : tree.packets()) {
        std::vector<std::int32_t> ids;
        for (int lane = 0; lane < 8; ++lane) {
            if (std::find(ids.begin(), ids.end(), packet.id[lane]) == ids.end()) ids.push_back(packet.id[lane]);
        }
        for (std::int32_t id : ids) ++seen[std::size_t(id)];
    }
    for (std::size_t t = 0; t < seen.size(); ++t) EXPECT_EQ(seen[t], binary.copies(std::uint32_t(t)) > 0 ? 1 : 0) << "triangle " << t;
}

TEST(WideBvh, EveryTriangleIsInExactlyOnePacketLane) {
    const Mesh mesh = soup(500, 1.0, 1);
    const Bvh binary(mesh);
    const WideBvh tree(mesh, binary);
    expectEveryTriangleOnce(mesh, binary, tree);
}

// A packet lane's frame as plain scalar glm code in double (the vector fill's definition,
// core/accel/wide_fill.inc), each value rounded once to float.
void referenceLane(const Mesh& mesh, std::uint32_t id, TrianglePacket& p, int lane) {
    const glm::dvec3 corner[3] = {glm::dvec3(mesh.vertex(id, 0)), glm::dvec3(mesh.vertex(id, 1)), glm::dvec3(mesh.vertex(id, 2))};
    int base = 0;
    double longest = -1.0;
    for (int e = 0; e < 3; ++e) {
        const glm::dvec3 edge = corner[(e + 1) % 3] - corner[e];
        const double length2 = glm::dot(edge, edge);
        if (length2 > longest) longest = length2, base = e;
    }
    const glm::dvec3 a = corner[base], b = corner[(base + 1) % 3], c = corner[(base + 2) % 3];
    const double length = std::sqrt(longest);
    const glm::dvec3 e1 = (b - a) / length;
    const glm::dvec3 cross = glm::cross(b - a, c - a);
    const double area = glm::length(cross);
    glm::dvec3 n = area > 0.0 ? cross / area : glm::dvec3(mesh.faceNormals[id]);
    n = glm::normalize(n - glm::dot(n, e1) * e1);
    const glm::dvec3 e2 = glm::cross(n, e1);
    const double cu = glm::dot(c - a, e1), cv = glm::dot(c - a, e2), bcu = cu - length;
    auto inverse = [](double length2) {
        const float inv = float(1.0 / length2);
        return length2 > 0.0 && std::isfinite(inv) ? inv : 0.0f;
    };
    p.ax[lane] = float(a.x), p.ay[lane] = float(a.y), p.az[lane] = float(a.z);
    p.e1x[lane] = float(e1.x), p.e1y[lane] = float(e1.y), p.e1z[lane] = float(e1.z);
    p.e2x[lane] = float(e2.x), p.e2y[lane] = float(e2.y), p.e2z[lane] = float(e2.z);
    p.nx[lane] = float(n.x), p.ny[lane] = float(n.y), p.nz[lane] = float(n.z);
    p.length[lane] = float(length), p.cu[lane] = float(cu), p.cv[lane] = float(cv), p.bcu[lane] = float(bcu);
    p.invAC[lane] = inverse(cu * cu + cv * cv), p.invBC[lane] = inverse(bcu * bcu + cv * cv);
    p.id[lane] = std::int32_t(id);
}

// Every lane of the tree's packets equals referenceLane's frame of its triangle, bit for bit.
void expectScalarFrames(const Mesh& mesh, const WideBvh& tree) {
    for (std::size_t i = 0; i < tree.packets().size(); ++i) {
        TrianglePacket reference = tree.packets()[i];
        for (int lane = 0; lane < 8; ++lane) referenceLane(mesh, std::uint32_t(reference.id[lane]), reference, lane);
        EXPECT_EQ(std::memcmp(&tree.packets()[i], &reference, sizeof(TrianglePacket)), 0) << "packet " << i;
    }
}

TEST(WideBvh, PacketsEqualTheScalarFramesOnBothPathsBuiltOrRefit) {
    // The packets' frames are filled four lanes at a time in double vectors: the same bits as the
    // scalar glm code on every path, for slivers, needles, copies, huge and tiny scales, built
    // and refit to moved vertices.
    const SimdPath chosen = simdPath();
    const Mesh bunny = loadObj(test::bundledBunnyPath());
    for (const Mesh& mesh : {soup(500, 1.0, 21), soup(300, 1e30, 22), soup(300, 1e-30, 23), bunny}) {
        SCOPED_TRACE(mesh.source);
        std::vector<glm::dvec3> moved(mesh.positions.begin(), mesh.positions.end());
        for (std::size_t v = 0; v < moved.size(); ++v) moved[v] += 1e-3 * glm::dvec3(mesh.positions[(v * 7) % moved.size()]);
        const Mesh movedMesh = buildMesh("moved", moved, mesh.triangles);
        ASSERT_EQ(movedMesh.triangleCount(), mesh.triangleCount());
        for (SimdPath path : kSimdPaths) {
            if (!simdPathAvailable(path)) continue;
            setSimdPath(path);
            const Bvh binary(mesh);
            const WideBvh tree(mesh, binary);
            expectScalarFrames(mesh, tree);
            expectScalarFrames(movedMesh, WideBvh(tree, movedMesh));
        }
    }
    setSimdPath(chosen);
}

TEST(WideBvh, NearestEqualsALinearScanNearAndFar) {
    const Mesh bunny = loadObj(test::bundledBunnyPath());
    expectTreeEqualsLinearScan(bunny, randomPoints(bunny, 3000, 0.05f, 2));  // near and inside
    expectTreeEqualsLinearScan(bunny, randomPoints(bunny, 1000, 20.0f, 3));  // far away
    const Mesh sphere = test::icosphere(1.0f, 3);
    expectTreeEqualsLinearScan(sphere, randomPoints(sphere, 2000, 0.2f, 4));
    expectTreeEqualsLinearScan(sphere, {glm::vec3(0.0f)}); // the centre: every triangle nearly ties
    expectTreeEqualsLinearScan(soup(700, 1.0, 5), randomPoints(soup(700, 1.0, 5), 3000, 0.5f, 6));
}

TEST(WideBvh, TiesGoToTheLowerTriangleIndex) {
    // One triangle copied three times at scattered indices, among others far from it.
    std::vector<glm::dvec3> positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    std::vector<glm::uvec3> triangles;
    for (int t = 0; t < 40; ++t) {
        const std::uint32_t first = std::uint32_t(positions.size());
        const glm::dvec3 o(5.0 + t, 5.0, 5.0);
        positions.insert(positions.end(), {o, o + glm::dvec3(1, 0, 0), o + glm::dvec3(0, 0, 1)});
        triangles.push_back({first, first + 1, first + 2});
        if (t == 7 || t == 19 || t == 33) triangles.push_back({0, 1, 2});
    }
    const Mesh mesh = buildMesh("copies", positions, triangles);
    const WideBvh tree(mesh, Bvh(mesh));
    const std::uint32_t lowest = 8; // the first copy: after triangles 0..7
    ASSERT_EQ(mesh.triangles[lowest], glm::uvec3(0, 1, 2));
    for (const glm::dvec3& world : {glm::dvec3(0.2, 0.2, 0.5), glm::dvec3(-1.0, -1.0, -1.0), glm::dvec3(0.3, 0.3, -0.01)}) {
        const glm::vec3 p(mesh.toLocal(world));
        NearestSoFar best{FLT_MAX, 0};
        tree.nearest(p.x, p.y, p.z, best);
        EXPECT_EQ(best.triangle, lowest);
        std::uint32_t hint = WideBvh::kEmpty;
        EXPECT_EQ(nearestTriangle(tree, p, hint), lowest);
    }
    // The grid's samples near the copies find the lowest one too.
    const Grid grid = makeGrid(mesh.worldBounds(), 24, 0.1);
    const NearestField nearest = computeNearest(mesh, Bvh(mesh), grid, RunControl{});
    for (std::size_t i = 0; i < nearest.triangle.size(); ++i) {
        const std::uint32_t t = nearest.triangle[i];
        if (mesh.triangles[t] == glm::uvec3(0, 1, 2)) {
            ASSERT_EQ(t, lowest) << "sample " << i;
        }
    }
}

TEST(WideBvh, ExponentiallySpacedChain) {
    // Triangles at exponentially growing distances (2^0 .. 2^119): lopsided splits, boxes of
    // every scale in one tree, local coordinates down to the smallest normal floats.
    std::vector<glm::dvec3> positions;
    std::vector<glm::uvec3> triangles;
    for (int t = 0; t < 120; ++t) {
        const double x = std::ldexp(1.0, t);
        const std::uint32_t first = std::uint32_t(positions.size());
        positions.insert(positions.end(), {{x, 0, 0}, {x, 1, 0}, {x, 0, 1}});
        triangles.push_back({first, first + 1, first + 2});
    }
    const Mesh mesh = buildMesh("chain", positions, triangles);
    const Bvh binary(mesh);
    expectTreeEqualsLinearScan(mesh, randomPoints(mesh, 2000, 0.1f, 7));
    const WideBvh tree(mesh, binary);
    expectEveryTriangleOnce(mesh, binary, tree);
}

// Every sample's triangle from the brick lists equals the tree's answer for its position, and its
// distance equals brute force in double within 1e-5 of the grid's diagonal.
void expectGridMatches(const Mesh& mesh, int res, double padding) {
    SCOPED_TRACE(mesh.source + " res " + std::to_string(res) + " padding " + std::to_string(padding));
    const Bvh binary(mesh);
    const WideBvh tree(mesh, binary);
    const Grid grid = makeGrid(mesh.worldBounds(), res, padding);
    const NearestField nearest = computeNearest(mesh, tree, grid, RunControl{});
    const double diagonal = grid.voxel * glm::length(glm::dvec3(grid.dims));
    std::size_t wrongTriangle = 0, wrongDistance = 0;
    for (int k = 0; k < grid.dims.z; ++k) {
        for (int j = 0; j < grid.dims.y; ++j) {
            for (int i = 0; i < grid.dims.x; ++i) {
                const std::size_t index = grid.index(i, j, k);
                const glm::dvec3 p = localPosition(mesh, grid, i, j, k);
                NearestSoFar best{FLT_MAX, 0};
                tree.nearest(float(p.x), float(p.y), float(p.z), best);
                wrongTriangle += best.triangle != nearest.triangle[index];
                const double truth = bruteDistance(mesh, p) * mesh.unit;
                wrongDistance += !(std::fabs(double(nearest.distance[index]) - truth) <= 1e-5 * diagonal);
            }
        }
    }
    EXPECT_EQ(wrongTriangle, 0u) << "of " << grid.sampleCount();
    EXPECT_EQ(wrongDistance, 0u) << "of " << grid.sampleCount();
}

TEST(ExactBricks, GridSamplesMatchTheTreeAndBruteForce) {
    const Mesh bunny = loadObj(test::bundledBunnyPath());
    expectGridMatches(bunny, 28, 0.1);  // bricks cut by the grid's end on every axis
    expectGridMatches(bunny, 20, 3.0);  // mostly far field
    expectGridMatches(test::torus(1.0f, 0.3f, 24, 12), 33, 0.05);
    expectGridMatches(soup(300, 1.0, 8), 26, 0.2);
}

TEST(ExactBricks, DenseMeshesSearchPerSample) {
    // 81,920 triangles on a coarse grid: a quarter's candidate list would hold thousands of packets,
    // so its samples are searched one by one in the tree instead (kMaxCandidates); same answers.
    const Mesh dense = test::icosphere(1.0f, 6);
    expectGridMatches(dense, 6, 0.1);
    expectGridMatches(dense, 10, 0.5);
}

TEST(ExactBricks, HugeAndTinyScales) {
    for (double scale : {1e-30, 1e-9, 1e9, 1e30}) {
        expectGridMatches(soup(120, scale, 9), 18, 0.3);
        const Mesh mesh = soup(120, scale, 10);
        expectTreeEqualsLinearScan(mesh, randomPoints(mesh, 500, 0.5f, 11));
    }
}

TEST(ExactBricks, IndependentOfTheThreadCount) {
    const Mesh bunny = loadObj(test::bundledBunnyPath());
    const Bvh binary(bunny);
    const WideBvh tree(bunny, binary);
    const Grid grid = makeGrid(bunny.worldBounds(), 40, 0.1);
    std::vector<float> one(grid.sampleCount()), two(grid.sampleCount()), four(grid.sampleCount());
    RunControl control;
    control.threads = 1;
    computeExactField(bunny, tree, grid, nullptr, false, one.data(), control);
    control.threads = 2;
    computeExactField(bunny, tree, grid, nullptr, false, two.data(), control);
    control.threads = 4;
    computeExactField(bunny, tree, grid, nullptr, false, four.data(), control);
    EXPECT_EQ(std::memcmp(one.data(), two.data(), one.size() * sizeof(float)), 0);
    EXPECT_EQ(std::memcmp(one.data(), four.data(), one.size() * sizeof(float)), 0);
}

TEST(ExactBricks, BaselinePathEqualsTheAvx2Path) {
    // The kernel's two compiled copies (core/distance/kernel.hpp): the same fields, nearest triangles and
    // point queries bit for bit, near and far, and on a soup of slivers and copies.
    if (!simdPathAvailable(SimdPath::Avx2)) GTEST_SKIP() << "this CPU has no AVX2: only the baseline path runs";
    const SimdPath chosen = simdPath();
    for (const Mesh& mesh : {loadObj(test::bundledBunnyPath()), soup(300, 1.0, 12)}) {
        SCOPED_TRACE(mesh.source);
        const Bvh binary(mesh);
        const WideBvh tree(mesh, binary);
        const Grid grid = makeGrid(mesh.worldBounds(), 36, 0.5);
        const std::vector<glm::vec3> points = randomPoints(mesh, 2000, 1.0f, 13);
        struct Run {
            std::vector<float> field;
            std::vector<std::uint32_t> triangles, queried;
        };
        auto run = [&](SimdPath path) {
            setSimdPath(path);
            EXPECT_EQ(simdPath(), path);
            Run r;
            r.field.resize(grid.sampleCount());
            computeExactField(mesh, tree, grid, nullptr, false, r.field.data(), RunControl{});
            r.triangles = computeNearest(mesh, tree, grid, RunControl{}).triangle;
            std::uint32_t hint = WideBvh::kEmpty;
            for (const glm::vec3& p : points) r.queried.push_back(nearestTriangle(tree, p, hint));
            return r;
        };
        const Run avx2 = run(SimdPath::Avx2), baseline = run(SimdPath::Baseline);
        EXPECT_EQ(std::memcmp(avx2.field.data(), baseline.field.data(), avx2.field.size() * sizeof(float)), 0);
        EXPECT_EQ(avx2.triangles, baseline.triangles);
        EXPECT_EQ(avx2.queried, baseline.queried);
    }
    setSimdPath(chosen);
}

TEST(ExactBricks, RowMeasureEqualsTheScalarClosestPoint) {
    // The field measures four samples of a row at once (each lane in its own Voronoi region);
    // computeNearest and sampleValue measure each sample alone with closestPointOnTriangle: the
    // same bits on both paths, near and far, unsigned and signed by the closest feature's
    // pseudonormal, on slivers, needles and copies (every region of a triangle is some sample's)
    // and on the bundled bunny (closed, with concave edges and vertices whose pseudonormals differ
    // from their faces' normals).
    const SimdPath chosen = simdPath();
    for (const Mesh& mesh : {soup(300, 1.0, 14), loadObj(test::bundledBunnyPath())}) {
        SCOPED_TRACE(mesh.source);
        const MeshTopology topology(mesh);
        const Bvh binary(mesh);
        const WideBvh tree(mesh, binary);
        for (SimdPath path : kSimdPaths) {
            if (!simdPathAvailable(path)) continue;
            setSimdPath(path);
            for (int res : {27, 45}) {
                const Grid grid = makeGrid(mesh.worldBounds(), res, 0.3);
                std::vector<float> field(grid.sampleCount());
                computeExactField(mesh, tree, grid, nullptr, false, field.data(), RunControl{});
                const NearestField nearest = computeNearest(mesh, tree, grid, RunControl{});
                EXPECT_EQ(std::memcmp(field.data(), nearest.distance.data(), field.size() * sizeof(float)), 0) << toString(path) << " res " << res;
                computeExactField(mesh, tree, grid, &topology, true, field.data(), RunControl{});
                std::size_t differing = 0, negative = 0;
                for (int k = 0; k < grid.dims.z; ++k) {
                    for (int j = 0; j < grid.dims.y; ++j) {
                        for (int i = 0; i < grid.dims.x; ++i) {
                            const std::size_t index = grid.index(i, j, k);
                            const float expected =
                                sampleValue(mesh, &topology, true, localPosition(mesh, grid, i, j, k), nearest.triangle[index]);
                            differing += std::memcmp(&expected, &field[index], sizeof(float)) != 0;
                            negative += field[index] < 0.0f;
                        }
                    }
                }
                EXPECT_EQ(differing, 0u) << toString(path) << " res " << res;
                EXPECT_GT(negative, 0u); // both signs occur
                EXPECT_LT(negative, field.size());
            }
        }
    }
    setSimdPath(chosen);
}

TEST(ExactBricks, PseudonormalSignWrittenInlineEqualsTheClosestFeatureSign) {
    // A closed mesh: the bake's inline signs are those of the sign method's own pass (which signs
    // the ray-sampled distances), and the analytic signs of the sphere away from its surface.
    const Model model{test::icosphere(1.0f, 3)};
    BakeSettings settings;
    settings.res = 30;
    const BakeResult baked = model.bake(settings);
    ASSERT_EQ(baked.sign, SignMethod::Pseudonormal);
    settings.method = DistanceMethod::Rays;
    settings.sign = SignMethod::Pseudonormal;
    const BakeResult separate = model.bake(settings);
    const Grid& grid = baked.field.dense().grid;
    std::size_t disagree = 0, wrong = 0;
    for (int k = 0; k < grid.dims.z; ++k) {
        for (int j = 0; j < grid.dims.y; ++j) {
            for (int i = 0; i < grid.dims.x; ++i) {
                const std::size_t index = grid.index(i, j, k);
                disagree += std::signbit(baked.field.dense().values[index]) != std::signbit(separate.field.dense().values[index]);
                const double r = glm::length(grid.position(i, j, k));
                if (std::fabs(r - 1.0) > 0.05) wrong += (baked.field.dense().values[index] < 0.0f) != (r < 1.0);
            }
        }
    }
    EXPECT_EQ(disagree, 0u);
    EXPECT_EQ(wrong, 0u);
}

} // namespace
} // namespace sdfgen
