// The mesh check's orientation predicates against exact rational arithmetic (GMP), on
// configurations built so close to degenerate that plain double precision gets the sign wrong.
#include "core/mesh/predicates.hpp"
#include "support/reference.hpp"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <gmpxx.h>
#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

namespace sdfgen {
namespace {

// The sign of (b - a) × (c - a) · (d - a) in rationals: every float converts to one exactly.
int rationalOrient3d(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& d) {
    const auto difference = [](const glm::vec3& p, const glm::vec3& o) {
        return std::vector<mpq_class>{mpq_class(double(p.x)) - mpq_class(double(o.x)),
                                      mpq_class(double(p.y)) - mpq_class(double(o.y)),
                                      mpq_class(double(p.z)) - mpq_class(double(o.z))};
    };
    const std::vector<mpq_class> u = difference(b, a), v = difference(c, a), w = difference(d, a);
    const mpq_class volume = w[0] * (u[1] * v[2] - u[2] * v[1]) + w[1] * (u[2] * v[0] - u[0] * v[2]) +
                             w[2] * (u[0] * v[1] - u[1] * v[0]);
    return sgn(volume);
}

// Whether the closed segment pq meets the closed triangle abc, for a segment not in abc's plane.
bool rationalSegmentMeetsTriangle(const glm::vec3& p, const glm::vec3& q, const glm::vec3& a, const glm::vec3& b,
                                  const glm::vec3& c) {
    const int sp = rationalOrient3d(a, b, c, p), sq = rationalOrient3d(a, b, c, q);
    EXPECT_FALSE(sp == 0 && sq == 0) << "a segment in the triangle's plane is not modelled here";
    if (sp == sq && sp != 0) return false;
    const int s1 = rationalOrient3d(p, q, a, b), s2 = rationalOrient3d(p, q, b, c), s3 = rationalOrient3d(p, q, c, a);
    return !((s1 > 0 || s2 > 0 || s3 > 0) && (s1 < 0 || s2 < 0 || s3 < 0));
}

// What the mesh check used before: proper crossings only, in plain double precision.
int plainOrient3d(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
    const double v = glm::dot(glm::cross(b - a, c - a), d - a);
    return (v > 0.0) - (v < 0.0);
}

bool plainSegmentCrossesTriangle(const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& a, const glm::dvec3& b,
                                 const glm::dvec3& c) {
    const int sp = plainOrient3d(a, b, c, p), sq = plainOrient3d(a, b, c, q);
    if (sp == 0 || sq == 0 || sp == sq) return false;
    const int s1 = plainOrient3d(p, q, a, b), s2 = plainOrient3d(p, q, b, c), s3 = plainOrient3d(p, q, c, a);
    return s1 != 0 && s1 == s2 && s2 == s3;
}

// An exact symmetry of space for floats: a permutation of the axes and a sign per axis.
struct AxisMap {
    int axis[3];
    float sign[3];
    glm::vec3 operator()(const glm::vec3& p) const {
        return {sign[0] * p[axis[0]], sign[1] * p[axis[1]], sign[2] * p[axis[2]]};
    }
};

AxisMap randomAxisMap(std::mt19937& rng) {
    AxisMap map{{0, 1, 2}, {1, 1, 1}};
    std::shuffle(std::begin(map.axis), std::end(map.axis), rng);
    for (float& s : map.sign) s = rng() % 2 ? 1.0f : -1.0f;
    return map;
}

// A float with 24 random significant bits and magnitude in [2^lo, 2^hi), either sign.
float randomFloat(std::mt19937& rng, int lo, int hi) {
    const float mantissa = 1.0f + float(rng() >> 9) * 0x1p-23f;
    const int exponent = lo + int(rng() % unsigned(hi - lo));
    return (rng() % 2 ? 1.0f : -1.0f) * std::ldexp(mantissa, exponent);
}

// a, b and c on the plane x = y, d within a few float steps of it near the origin, then mapped by
// a random axis map. The differences d - a need about 60 bits: double rounds them by ~2^-47 while
// d lies 0 to 3 steps of 2^-52 off the plane, so the rounding decides the plain double's sign.
struct Quad {
    glm::vec3 a, b, c, d;
};
Quad nearlyCoplanar(std::mt19937& rng) {
    const auto onPlane = [&] {
        const float s = randomFloat(rng, -2, 6);
        return glm::vec3(s, s, randomFloat(rng, -2, 6));
    };
    Quad q{onPlane(), onPlane(), onPlane(), {}};
    const float t = std::ldexp(1.0f + float(rng() >> 9) * 0x1p-23f, -29);
    float y = t;
    for (int step = int(rng() % 7) - 3; step != 0; step += step > 0 ? -1 : 1) y = std::nextafter(y, step > 0 ? 1.0f : -1.0f);
    q.d = {t, y, randomFloat(rng, -32, -26)};
    const AxisMap map = randomAxisMap(rng);
    return {map(q.a), map(q.b), map(q.c), map(q.d)};
}

TEST(Orient3d, ExactWherePlainDoubleGetsTheSignWrong) {
    std::mt19937 rng(21);
    const int n = 20000;
    int plainWrong = 0, coplanar = 0;
    for (int s = 0; s < n; ++s) {
        const Quad q = nearlyCoplanar(rng);
        const int truth = rationalOrient3d(q.a, q.b, q.c, q.d);
        coplanar += truth == 0;
        plainWrong += plainOrient3d(q.a, q.b, q.c, q.d) != truth;
        ASSERT_EQ(orient3d(q.a, q.b, q.c, q.d), truth) << s;
        ASSERT_EQ(orient3dExact(q.a, q.b, q.c, q.d), truth) << s;
        // Swapping two points flips the sign, a cyclic shift of the last three keeps it.
        ASSERT_EQ(orient3d(q.b, q.a, q.c, q.d), -truth) << s;
        ASSERT_EQ(orient3d(q.a, q.c, q.d, q.b), truth) << s;
    }
    // Not vacuous: the configurations defeat plain double often, and some are exactly coplanar.
    EXPECT_GT(plainWrong, n / 5) << "plain double wrong on " << plainWrong << " of " << n;
    EXPECT_GT(coplanar, n / 20);
}

TEST(Orient3d, ExactOnGenericDegenerateAndExtremeInputs) {
    std::mt19937 rng(22);
    for (int s = 0; s < 5000; ++s) {
        // Every coordinate from its own binade anywhere in float's range, subnormals included; then
        // repeated, collinear and zero points.
        const auto point = [&] {
            return glm::vec3(randomFloat(rng, -149, 127), randomFloat(rng, -149, 127), randomFloat(rng, -149, 127));
        };
        glm::vec3 p[4] = {point(), point(), point(), point()};
        if (s % 5 == 1) p[3] = p[int(rng() % 3)];
        if (s % 5 == 2) {
            p[1] = glm::vec3(p[0].x, p[0].y, p[1].z);
            p[2] = glm::vec3(p[0].x, p[0].y, p[2].z);
        }
        if (s % 5 == 3) p[3] = glm::vec3(0.0f);
        const int truth = rationalOrient3d(p[0], p[1], p[2], p[3]);
        ASSERT_EQ(orient3d(p[0], p[1], p[2], p[3]), truth) << s;
        ASSERT_EQ(orient3dExact(p[0], p[1], p[2], p[3]), truth) << s;
        ASSERT_EQ(orient3d(p[1], p[0], p[2], p[3]), -truth) << s;
    }
    // Moderate, unit-scale inputs: the filter decides almost all of them and agrees too.
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    for (int s = 0; s < 5000; ++s) {
        const glm::vec3 a(unit(rng), unit(rng), unit(rng)), b(unit(rng), unit(rng), unit(rng));
        const glm::vec3 c(unit(rng), unit(rng), unit(rng)), d(unit(rng), unit(rng), unit(rng));
        ASSERT_EQ(orient3d(a, b, c, d), rationalOrient3d(a, b, c, d)) << s;
    }
    // Four points of a cube face and a point off it, at a scale where the differences are exact.
    EXPECT_EQ(orient3d({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}), 1);
    EXPECT_EQ(orient3d({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, -1}), -1);
    EXPECT_EQ(orient3d({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}), 0);
}

// Two triangles: T on the plane x = y around the origin, and a thin U whose vertex p lies within a
// few float steps of T's plane near the origin and whose other vertices are far on one side. U's
// edges from p meet T exactly when p is on T's plane or beyond it, which plain double often gets
// wrong; every other pair of edge and triangle is far from touching. Mapped by a random axis map.
std::vector<glm::vec3> nearlyTouchingPair(std::mt19937& rng) {
    const float t = std::ldexp(1.0f + float(rng() >> 9) * 0x1p-23f, -29);
    float y = t;
    for (int step = int(rng() % 7) - 3; step != 0; step += step > 0 ? -1 : 1) y = std::nextafter(y, step > 0 ? 1.0f : -1.0f);
    const float side = rng() % 2 ? 1.0f : -1.0f;
    std::vector<glm::vec3> points = {{-40.0f, -40.0f, -30.0f}, {40.0f, 40.0f, -30.0f}, {0.0f, 0.0f, 50.0f},
                                     {t, y, randomFloat(rng, -32, -26)},
                                     {-8.0f * side, 8.0f * side, 0.3f}, {-8.0f * side, 8.0f * side, 3.7f}};
    const AxisMap map = randomAxisMap(rng);
    for (glm::vec3& p : points) p = map(p);
    return points;
}

TEST(MeshCheck, SelfIntersectionsAreCountedWithExactOrientations) {
    std::mt19937 rng(23);
    int found = 0, plainMissed = 0;
    for (int attempt = 0; attempt < 400 && found < 40; ++attempt) {
        const Mesh mesh = buildMesh("nearly touching", nearlyTouchingPair(rng), {{0, 1, 2}, {3, 4, 5}});
        // The mesh's own (local) floats, as the check sees them.
        const glm::vec3 a = mesh.vertex(0, 0), b = mesh.vertex(0, 1), c = mesh.vertex(0, 2);
        const glm::vec3 p = mesh.vertex(1, 0), q = mesh.vertex(1, 1), r = mesh.vertex(1, 2);
        const bool truth = rationalSegmentMeetsTriangle(p, q, a, b, c) || rationalSegmentMeetsTriangle(r, p, a, b, c);
        ASSERT_FALSE(rationalSegmentMeetsTriangle(q, r, a, b, c));
        for (int e = 0; e < 3; ++e) {
            const glm::vec3 u[3] = {a, b, c};
            ASSERT_FALSE(rationalSegmentMeetsTriangle(u[e], u[(e + 1) % 3], p, q, r));
        }
        const bool plain = plainSegmentCrossesTriangle(p, q, a, b, c) || plainSegmentCrossesTriangle(r, p, a, b, c);
        EXPECT_EQ(segmentMeetsTriangle(p, q, a, b, c), rationalSegmentMeetsTriangle(p, q, a, b, c)) << attempt;
        const MeshCheck check = test::checkMesh(mesh);
        EXPECT_EQ(check.selfIntersections, truth ? 1u : 0u) << attempt;
        if (plain == truth) continue;
        // A pair where the plain-double check would have counted wrongly.
        ++found;
        if (!plain) ++plainMissed;
    }
    EXPECT_EQ(found, 40);
    // Plain double misses pairs that do meet. (It counts pairs that do not meet only where
    // multiply-adds are fused, which our build never does: see CMakeLists.txt.)
    EXPECT_GT(plainMissed, 0);
}

TEST(SegmentMeetsTriangle, TouchingCountsInAndOutOfThePlane) {
    const glm::vec3 a(0, 0, 0), b(4, 0, 0), c(0, 4, 0);
    // Across the plane: through the interior, an edge, a vertex; stopping on the triangle; missing.
    EXPECT_TRUE(segmentMeetsTriangle({1, 1, -1}, {1, 1, 1}, a, b, c));
    EXPECT_TRUE(segmentMeetsTriangle({2, 0, -1}, {2, 0, 1}, a, b, c));
    EXPECT_TRUE(segmentMeetsTriangle({0, 4, -1}, {0, 4, 1}, a, b, c));
    EXPECT_TRUE(segmentMeetsTriangle({1, 1, 0}, {1, 1, 1}, a, b, c));
    EXPECT_FALSE(segmentMeetsTriangle({3, 3, -1}, {3, 3, 1}, a, b, c));
    EXPECT_FALSE(segmentMeetsTriangle({1, 1, 0.5f}, {1, 1, 1}, a, b, c));
    // In the plane: inside, crossing an edge, ending on an edge, along an edge, beside it.
    EXPECT_TRUE(segmentMeetsTriangle({1, 1, 0}, {1, 2, 0}, a, b, c));
    EXPECT_TRUE(segmentMeetsTriangle({-1, 1, 0}, {1, 1, 0}, a, b, c));
    EXPECT_TRUE(segmentMeetsTriangle({-1, 1, 0}, {0, 1, 0}, a, b, c));
    EXPECT_TRUE(segmentMeetsTriangle({4, 0, 0}, {6, 0, 0}, a, b, c));
    EXPECT_FALSE(segmentMeetsTriangle({5, 0, 0}, {6, 0, 0}, a, b, c));
    EXPECT_FALSE(segmentMeetsTriangle({3, 3, 0}, {5, 1, 0}, a, b, c));
    // A triangle without area meets nothing.
    EXPECT_FALSE(segmentMeetsTriangle({1, 0, -1}, {1, 0, 1}, a, b, {2, 0, 0}));
}

TEST(MeshCheck, TouchingAndCoplanarOverlappingTrianglesCount) {
    const auto pairCount = [](std::vector<glm::vec3> positions) {
        return test::checkMesh(buildMesh("pair", std::move(positions), {{0, 1, 2}, {3, 4, 5}})).selfIntersections;
    };
    // A vertex on the other triangle's face, an edge through its edge, a coplanar overlap, a
    // coplanar triangle inside the other, and the same pairs moved apart.
    EXPECT_EQ(pairCount({{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {1, 1, 0}, {1, 1, 2}, {2, 1, 2}}), 1u);
    EXPECT_EQ(pairCount({{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {2, -1, 1}, {2, 1, -1}, {2, 3, 3}}), 1u);
    EXPECT_EQ(pairCount({{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {1, 1, 0}, {5, 1, 0}, {1, 5, 0}}), 1u);
    EXPECT_EQ(pairCount({{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {1, 1, 0}, {2, 1, 0}, {1, 2, 0}}), 1u);
    EXPECT_EQ(pairCount({{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {1, 1, 0.5f}, {1, 1, 2}, {2, 1, 2}}), 0u);
    EXPECT_EQ(pairCount({{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {3, 3, 0}, {5, 3, 0}, {3, 5, 0}}), 0u);
}

} // namespace
} // namespace sdfgen
