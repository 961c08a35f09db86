// The exact bake's determinism across thread counts and its cancellation from the progress callback.
#include "sdfgen/error.hpp"
#include "core/bake/bake.hpp"
#include "support/checks.hpp"
#include "support/reference.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>
#include <atomic>
#include <cmath>
#include <chrono>
#include <thread>
#include <cstring>

namespace sdfgen {
namespace {

using namespace test;

TEST(ExactBake, BitIdenticalForAnyThreadCount) {
    const Mesh mesh = loadMesh(test::bundledBunnyPath());
    for (SignMethod sign : {SignMethod::Winding, SignMethod::Pseudonormal}) {
        const Field one = bakeWith(mesh, 28, DistanceMethod::Exact, sign, 1).field.dense();
        const Field many = bakeWith(mesh, 28, DistanceMethod::Exact, sign, 5).field.dense();
        ASSERT_EQ(one.values.size(), many.values.size());
        EXPECT_EQ(std::memcmp(one.values.data(), many.values.data(), one.values.size() * sizeof(float)), 0) << toString(sign);
    }
    const Mesh small = test::torus(1.0f, 0.3f, 24, 12);
    const Field one = bakeWith(small, 16, DistanceMethod::Brute, SignMethod::Winding, 1).field.dense();
    const Field many = bakeWith(small, 16, DistanceMethod::Brute, SignMethod::Winding, 5).field.dense();
    EXPECT_EQ(std::memcmp(one.values.data(), many.values.data(), one.values.size() * sizeof(float)), 0) << "brute";
}

// A float distance rounds at the scale of the triangle's vertices, not only of the sample's
// coordinates: the one sample of a res-1 grid lies at the mesh's local origin, exactly on an edge
// of the second triangle (fuzz_bake's find: the search's margin, scaled by the sample's coordinates
// alone, was about 0 there and dropped that triangle, giving the first's 0.5).
TEST(ExactBake, ASampleOnAnEdgeAtTheMeshsCentreIsOnTheSurface) {
    const std::vector<glm::vec3> positions = {{0, 0, 0}, {1, 0.1f, 0}, {0, 1, 0}, {1, 0, 1}};
    const Mesh mesh = buildMesh("edge through the centre", positions, {{0, 1, 2}, {1, 3, 2}});
    for (SignMethod sign : {SignMethod::Winding, SignMethod::Pseudonormal}) {
        const Field field = bakeWith(mesh, 1, DistanceMethod::Exact, sign, 1).field.dense();
        ASSERT_EQ(field.values.size(), 1u);
        EXPECT_LT(std::fabs(field.values[0]), 1e-6f) << toString(sign);
        const Field brute = bakeWith(mesh, 1, DistanceMethod::Brute, SignMethod::Winding, 1).field.dense();
        EXPECT_EQ(std::fabs(brute.values[0]), 0.0f);
    }
}

// The local frame fits the triangles kept: a zero-area triangle out at a stray vertex (dropped)
// once set a unit so large that the quad, far smaller, lost its extent in float, and the exact
// search measured the wrong triangles (fuzz_bake's find: 0.28 where the distance is 0.15).
TEST(ExactBake, ADroppedTriangleAtAStrayVertexLeavesTheFrameToTheRest) {
    for (const double x : {0.0, 1.6e30}) {
        const std::vector<glm::dvec3> positions = {{x, 0, 0}, {x, 5, 6}, {x, 0, 1}, {x, 1, 1}, {1e38, 1, 1}};
        const Mesh mesh = buildMesh("quad and a stray vertex", positions, {{0, 3, 2}, {0, 2, 1}, {0, 4, 4}});
        ASSERT_EQ(mesh.triangleCount(), 2u);
        EXPECT_EQ(mesh.droppedDegenerate, 1u);
        EXPECT_LE(mesh.unit, 4.0) << "the frame fits the quad";
        const Field exact = bakeWith(mesh, 6, DistanceMethod::Exact, SignMethod::Winding, 1).field.dense();
        const Field brute = bakeWith(mesh, 6, DistanceMethod::Brute, SignMethod::Winding, 1).field.dense();
        ASSERT_EQ(exact.values.size(), brute.values.size());
        for (std::size_t n = 0; n < exact.values.size(); ++n) {
            ASSERT_NEAR(exact.values[n], brute.values[n], 1e-5) << "sample " << n << ", quad at x = " << x;
        }
    }
}

TEST(ExactBake, HonoursCancelFromTheProgressCallback) {
    const Mesh mesh = test::icosphere(1.0f, 2);
    const Bvh tree(mesh);
    struct Case {
        DistanceMethod method;
        SignMethod sign;
        double at; // progress fraction at which to cancel
    };
    for (const Case& c : {Case{DistanceMethod::Exact, SignMethod::Auto, 0.2}, Case{DistanceMethod::Exact, SignMethod::Winding, 0.85},
                          Case{DistanceMethod::Exact, SignMethod::Pseudonormal, 0.85}, Case{DistanceMethod::Brute, SignMethod::Winding, 0.2}}) {
        std::atomic<bool> cancel{false};
        RunControl control;
        control.threads = 1;
        control.cancel = &cancel;
        double last = 0;
        control.progress = [&](double f) {
            last = f;
            if (f > c.at) cancel = true;
        };
        BakeSettings settings;
        settings.res = 24;
        settings.method = c.method;
        settings.sign = c.sign;
        EXPECT_THROW(bake(mesh, tree, settings, control), Cancelled) << toString(c.method) << " " << toString(c.sign);
        EXPECT_LT(last, 1.0);
    }
}

// The grid's zero fill before the distances is checked for Cancel in blocks: a cancel raised
// while a large grid is being filled ends the bake within a block, not after the whole fill
// (about 2 s at res 400 on a loaded 2-core machine).
TEST(ExactBake, CancelStopsTheGridsFill) {
    const Mesh mesh = test::icosphere(1.0f, 1);
    const Bvh tree(mesh);
    BakeSettings settings;
    settings.res = 400;
    settings.sign = SignMethod::Winding;
    std::atomic<bool> cancel{false};
    RunControl control;
    control.threads = 1;
    control.cancel = &cancel;
    std::chrono::steady_clock::time_point raised;
    std::thread raiser([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        raised = std::chrono::steady_clock::now();
        cancel = true;
    });
    EXPECT_THROW(bake(mesh, tree, settings, control), Cancelled);
    [[maybe_unused]] const auto ended = std::chrono::steady_clock::now(); // unchecked under ASan (below)
    raiser.join();
#ifndef SDFGEN_TEST_ASAN // whose allocator poisons and unpoisons the grid's 256 MB whole, uncancellably
    EXPECT_LT(std::chrono::duration<double>(ended - raised).count(), 0.3);
#endif
}

} // namespace
} // namespace sdfgen
