// Möller–Trumbore: hits, misses, edges and corners, parallel rays, faces, packet vs single ray.
#include "core/accel/ray.hpp"

#include <gtest/gtest.h>
#include <cmath>
#include <limits>
#include <random>

namespace sdfgen {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
// Counter-clockwise seen from +z, so the face normal is +z.
const PreparedTriangle kTri = prepareTriangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0});

struct Hit {
    bool hit;
    float t;
    bool back;
};
Hit trace(glm::vec3 o, glm::vec3 d, float tMax = kInf) {
    float t = 0;
    bool back = false;
    const bool hit = intersectTriangle(o.x, o.y, o.z, d, kTri, tMax, t, back);
    return {hit, t, back};
}

TEST(MollerTrumbore, HitsInteriorAtTheRightDistance) {
    const Hit h = trace({0.25f, 0.25f, 2.0f}, {0, 0, -1});
    ASSERT_TRUE(h.hit);
    EXPECT_FLOAT_EQ(h.t, 2.0f);
    const Hit oblique = trace({0.0f, 0.0f, 1.0f}, glm::normalize(glm::vec3(0.2f, 0.2f, -1.0f)));
    ASSERT_TRUE(oblique.hit);
    EXPECT_NEAR(oblique.t, std::sqrt(0.08f + 1.0f), 1e-6f);
}

TEST(MollerTrumbore, MissesOutsideTheTriangle) {
    EXPECT_FALSE(trace({0.6f, 0.6f, 1.0f}, {0, 0, -1}).hit);  // beyond the hypotenuse
    EXPECT_FALSE(trace({-0.1f, 0.5f, 1.0f}, {0, 0, -1}).hit); // left of the y edge
    EXPECT_FALSE(trace({0.5f, -0.1f, 1.0f}, {0, 0, -1}).hit); // below the x edge
    EXPECT_FALSE(trace({2.0f, 2.0f, 1.0f}, {0, 0, -1}).hit);
}

TEST(MollerTrumbore, EdgesAndCornersCountAsHits) {
    EXPECT_TRUE(trace({0.5f, 0.0f, 1.0f}, {0, 0, -1}).hit);  // on edge v0-v1
    EXPECT_TRUE(trace({0.0f, 0.5f, 1.0f}, {0, 0, -1}).hit);  // on edge v0-v2
    EXPECT_TRUE(trace({0.5f, 0.5f, 1.0f}, {0, 0, -1}).hit);  // on the hypotenuse
    EXPECT_TRUE(trace({0.0f, 0.0f, 1.0f}, {0, 0, -1}).hit);  // corner v0
    EXPECT_TRUE(trace({1.0f, 0.0f, 1.0f}, {0, 0, -1}).hit);  // corner v1
    EXPECT_TRUE(trace({0.0f, 1.0f, 1.0f}, {0, 0, -1}).hit);  // corner v2
}

TEST(MollerTrumbore, ParallelRaysNeverHit) {
    EXPECT_FALSE(trace({0.25f, 0.25f, 1.0f}, {1, 0, 0}).hit);  // above the plane
    EXPECT_FALSE(trace({-1.0f, 0.25f, 0.0f}, {1, 0, 0}).hit);  // in the plane
    EXPECT_FALSE(trace({0.25f, 0.25f, 0.0f}, {0, 1, 0}).hit);  // in the plane, starting inside
}

TEST(MollerTrumbore, FrontAndBackFaces) {
    const Hit front = trace({0.2f, 0.2f, 1.0f}, {0, 0, -1}); // against the normal: entering the solid
    ASSERT_TRUE(front.hit);
    EXPECT_FALSE(front.back);
    const Hit back = trace({0.2f, 0.2f, -1.0f}, {0, 0, 1}); // along the normal: leaving it
    ASSERT_TRUE(back.hit);
    EXPECT_TRUE(back.back);
}

TEST(MollerTrumbore, RespectsTheRayInterval) {
    EXPECT_FALSE(trace({0.2f, 0.2f, -1.0f}, {0, 0, -1}).hit);    // triangle behind the origin
    EXPECT_FALSE(trace({0.2f, 0.2f, 2.0f}, {0, 0, -1}, 1.5f).hit); // beyond tMax
    EXPECT_FALSE(trace({0.2f, 0.2f, 2.0f}, {0, 0, -1}, 2.0f).hit); // tMax is exclusive
    const Hit onSurface = trace({0.2f, 0.2f, 0.0f}, {0, 0, 1});   // origin on the triangle: t = 0
    ASSERT_TRUE(onSurface.hit);
    EXPECT_EQ(onSurface.t, 0.0f);
}

TEST(MollerTrumbore, PacketLanesMatchSingleRays) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> coord(-0.5f, 1.5f);
    for (int trial = 0; trial < 200; ++trial) {
        const glm::vec3 d = glm::normalize(glm::vec3(coord(rng) - 0.5f, coord(rng) - 0.5f, -1.0f));
        simd::f8 ox, oy, oz, tMax = simd::splat(kInf), t;
        for (int lane = 0; lane < 8; ++lane) {
            ox[lane] = coord(rng);
            oy[lane] = coord(rng);
            oz[lane] = 1.0f;
        }
        bool back = false;
        const simd::i8 mask = intersectTriangle(ox, oy, oz, d, kTri, tMax, t, back);
        for (int lane = 0; lane < 8; ++lane) {
            const Hit single = trace({ox[lane], oy[lane], oz[lane]}, d);
            ASSERT_EQ(mask[lane] != 0, single.hit);
            if (single.hit) {
                EXPECT_EQ(t[lane], single.t);
            }
        }
    }
}

} // namespace
} // namespace sdfgen
