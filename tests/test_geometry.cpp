// The geometric primitives against their definitions: the closest point on a triangle, the solid
// angle, the winding number and the 2D point-in-triangle test.
#include "core/mesh/geometry.hpp"
#include "core/sign/winding_sign.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <vector>

namespace sdfgen {
namespace {

constexpr double kPi = 3.14159265358979323846;

double sampledMinDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, int n) {
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= n; ++i) {
        for (int j = 0; i + j <= n; ++j) {
            const glm::dvec3 q = a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n);
            const glm::dvec3 d = p - q;
            best = std::min(best, glm::dot(d, d));
        }
    }
    return std::sqrt(best);
}

// Barycentric coordinates of q (assumed in the plane of a non-degenerate abc).
glm::dvec3 barycentric(const glm::dvec3& q, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const glm::dvec3 v0 = b - a, v1 = c - a, v2 = q - a;
    const double d00 = glm::dot(v0, v0), d01 = glm::dot(v0, v1), d11 = glm::dot(v1, v1);
    const double d20 = glm::dot(v2, v0), d21 = glm::dot(v2, v1);
    const double den = d00 * d11 - d01 * d01;
    const double v = (d11 * d20 - d01 * d21) / den, w = (d00 * d21 - d01 * d20) / den;
    return {1.0 - v - w, v, w};
}

glm::dvec3 randomUnit(std::mt19937& rng) {
    std::normal_distribution<double> gauss;
    return glm::normalize(glm::dvec3(gauss(rng), gauss(rng), gauss(rng)));
}

TEST(ClosestPointOnTriangle, NeverFartherThanADenseSamplingOfTheTriangle) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> uniform(-2.0, 2.0);
    const int n = 120;
    for (int shape = 0; shape < 6; ++shape) {
        // Random triangles: acute, obtuse and thin ones all turn up.
        const glm::dvec3 a(uniform(rng), uniform(rng), uniform(rng));
        const glm::dvec3 b(uniform(rng), uniform(rng), uniform(rng));
        const glm::dvec3 c(uniform(rng), uniform(rng), uniform(rng));
        const double spacing = std::max({glm::length(b - a), glm::length(c - a), glm::length(c - b)}) / n;
        for (int s = 0; s < 60; ++s) {
            const glm::dvec3 p(uniform(rng), uniform(rng), uniform(rng));
            const ClosestPoint closest = closestPointOnTriangle(p, a, b, c);
            const double distance = std::sqrt(closest.distanceSquared);
            const double sampled = sampledMinDistance(p, a, b, c, n);
            EXPECT_LE(distance, sampled + 1e-12);
            EXPECT_GE(distance, sampled - spacing); // and not absurdly close
            EXPECT_NEAR(glm::length(p - closest.point), distance, 1e-12);
            // The point lies on the triangle.
            const glm::dvec3 w = barycentric(closest.point, a, b, c);
            EXPECT_GE(std::min({w.x, w.y, w.z}), -1e-9);
            EXPECT_LT(glm::length(w.x * a + w.y * b + w.z * c - closest.point), 1e-9);
        }
    }
}

TEST(ClosestPointOnTriangle, FeatureMatchesTheVoronoiRegion) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    // An obtuse-ish triangle in a random frame, away from the origin.
    const glm::dvec3 e0 = randomUnit(rng);
    const glm::dvec3 e1 = glm::normalize(glm::cross(e0, randomUnit(rng)));
    const glm::dvec3 e2 = glm::cross(e0, e1);
    const glm::dvec3 origin(0.3, -1.2, 2.5);
    auto place = [&](double x, double y) { return origin + x * e0 + y * e1; };
    const glm::dvec3 corners[3] = {place(0, 0), place(2, 0), place(0.5, 1.5)};
    const glm::dvec3 normal = glm::normalize(glm::cross(corners[1] - corners[0], corners[2] - corners[0]));
    ASSERT_GT(glm::dot(normal, e2), 0.99);
    const glm::dvec3& a = corners[0];
    const glm::dvec3& b = corners[1];
    const glm::dvec3& c = corners[2];

    auto expectClosest = [&](const glm::dvec3& p, const glm::dvec3& point, TriangleFeature feature) {
        const ClosestPoint closest = closestPointOnTriangle(p, a, b, c);
        EXPECT_EQ(int(closest.feature), int(feature)) << "p = " << p.x << "," << p.y << "," << p.z;
        EXPECT_LT(glm::length(closest.point - point), 1e-9);
        EXPECT_NEAR(closest.distanceSquared, glm::dot(p - point, p - point), 1e-9);
    };
    for (int s = 0; s < 200; ++s) {
        // Face: above or below the interior.
        double u, v;
        do {
            u = 0.02 + unit(rng);
            v = 0.02 + unit(rng);
        } while (u + v > 0.98);
        const glm::dvec3 inPlane = a + u * (b - a) + v * (c - a);
        const double h = 2.0 * unit(rng) - 1.0;
        expectClosest(inPlane + h * normal, inPlane, TriangleFeature::Face);

        // Edges: off the edge's outer side, between its ends.
        const TriangleFeature edges[3] = {TriangleFeature::EdgeAB, TriangleFeature::EdgeBC, TriangleFeature::EdgeCA};
        for (int e = 0; e < 3; ++e) {
            const glm::dvec3& from = corners[e];
            const glm::dvec3& to = corners[(e + 1) % 3];
            const glm::dvec3 q = from + (0.02 + 0.96 * unit(rng)) * (to - from);
            const glm::dvec3 out = glm::normalize(glm::cross(to - from, normal));
            const double side = 0.01 + 2.0 * unit(rng), lift = 2.0 * unit(rng) - 1.0;
            expectClosest(q + side * out + lift * normal, q, edges[e]);
        }

        // Vertices: in the cone where both edges from the vertex point away.
        const TriangleFeature vertices[3] = {TriangleFeature::VertexA, TriangleFeature::VertexB, TriangleFeature::VertexC};
        for (int k = 0; k < 3; ++k) {
            const glm::dvec3& corner = corners[k];
            const glm::dvec3 e1v = corners[(k + 1) % 3] - corner, e2v = corners[(k + 2) % 3] - corner;
            glm::dvec3 d;
            do {
                d = randomUnit(rng) * (0.01 + 2.0 * unit(rng));
            } while (glm::dot(d, e1v) > -1e-3 || glm::dot(d, e2v) > -1e-3);
            expectClosest(corner + d, corner, vertices[k]);
        }
    }
}

// The distance from p to the union of the three edges, the definition for a flat triangle.
double segmentsDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const glm::dvec3 corners[3] = {a, b, c};
    double best = std::numeric_limits<double>::infinity();
    for (int e = 0; e < 3; ++e) {
        const glm::dvec3 s = corners[e], d = corners[(e + 1) % 3] - s;
        const double len2 = glm::dot(d, d);
        const double t = len2 > 0 ? std::clamp(glm::dot(p - s, d) / len2, 0.0, 1.0) : 0.0;
        best = std::min(best, glm::length(p - (s + t * d)));
    }
    return best;
}

TEST(ClosestPointOnTriangle, DegenerateTrianglesGiveTheNearestEdge) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> uniform(-3.0, 3.0);
    const glm::dvec3 dir = glm::normalize(glm::dvec3(0.3, -0.7, 0.4));
    const glm::dvec3 o(0.2, 0.1, -0.3);
    struct Degenerate {
        const char* name;
        glm::dvec3 a, b, c;
    };
    const Degenerate cases[] = {
        {"collinear, c beyond b", o, o + dir, o + 2.0 * dir},
        {"collinear, c between", o, o + 2.0 * dir, o + 0.5 * dir},
        {"collinear, a in the middle", o + dir, o - dir, o + 2.0 * dir},
        {"a == b", o, o, o + dir},
        {"b == c", o, o + dir, o + dir},
        {"a == c", o + dir, o, o + dir},
        {"a == b == c", o, o, o},
    };
    for (const Degenerate& d : cases) {
        for (int s = 0; s < 300; ++s) {
            const glm::dvec3 p(uniform(rng), uniform(rng), uniform(rng));
            const ClosestPoint closest = closestPointOnTriangle(p, d.a, d.b, d.c);
            ASSERT_TRUE(std::isfinite(closest.distanceSquared)) << d.name;
            EXPECT_NEAR(std::sqrt(closest.distanceSquared), segmentsDistance(p, d.a, d.b, d.c), 1e-9) << d.name;
            EXPECT_NEAR(glm::length(p - closest.point), std::sqrt(closest.distanceSquared), 1e-9) << d.name;
            EXPECT_NEAR(segmentsDistance(closest.point, d.a, d.b, d.c), 0.0, 1e-9) << d.name; // on the triangle
        }
    }
}

TEST(SolidAngle, ClosedBoxSumsToFourPiInsideAndZeroOutside) {
    const Mesh box = test::box({1.0f, 0.6f, 0.4f});
    ASSERT_EQ(box.triangleCount(), 12u);
    auto total = [&](const glm::dvec3& p, bool flip) {
        double sum = 0;
        for (std::size_t t = 0; t < box.triangleCount(); ++t) {
            const glm::dvec3 a(box.vertex(t, 0)), b(box.vertex(t, 1)), c(box.vertex(t, 2));
            const double omega = flip ? solidAngle(p, a, c, b) : solidAngle(p, a, b, c);
            EXPECT_LE(std::fabs(omega), 2.0 * kPi + 1e-12);
            EXPECT_NEAR(omega, flip ? -solidAngle(p, a, b, c) : -solidAngle(p, a, c, b), 1e-12); // sign flips with winding
            sum += omega;
        }
        return sum;
    };
    EXPECT_NEAR(total({0, 0, 0}, false), 4.0 * kPi, 1e-12);
    EXPECT_NEAR(total({0, 0, 0}, true), -4.0 * kPi, 1e-12);
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (int s = 0; s < 200; ++s) {
        const glm::dvec3 inside(0.99 * uniform(rng), 0.59 * uniform(rng), 0.39 * uniform(rng));
        EXPECT_NEAR(total(inside, false), 4.0 * kPi, 1e-9);
        EXPECT_NEAR(total(inside, true), -4.0 * kPi, 1e-9);
        glm::dvec3 outside(3.0 * uniform(rng), 3.0 * uniform(rng), 3.0 * uniform(rng));
        if (std::fabs(outside.x) < 1.01 && std::fabs(outside.y) < 0.61 && std::fabs(outside.z) < 0.41) outside.x = 1.5;
        EXPECT_NEAR(total(outside, false), 0.0, 1e-9);
        EXPECT_NEAR(total(outside, true), 0.0, 1e-9);
    }
    // A single triangle seen from its back (below, normal +z) is positive; from its front negative.
    const glm::dvec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
    EXPECT_GT(solidAngle({0.2, 0.2, -0.5}, a, b, c), 0.0);
    EXPECT_LT(solidAngle({0.2, 0.2, 0.5}, a, b, c), 0.0);
    // Close to the interior the magnitude approaches 2π.
    EXPECT_NEAR(solidAngle({0.2, 0.2, -1e-9}, a, b, c), 2.0 * kPi, 1e-6);
}

TEST(WindingNumber, IcosphereOneInsideZeroOutsideHalfOnTheSurface) {
    const float r = 1.0f;
    const Mesh sphere = test::icosphere(r, 2);
    const double inner = r - test::icosphereSag(r, 2);
    std::mt19937 rng(13);
    for (int s = 0; s < 100; ++s) {
        const glm::dvec3 d = randomUnit(rng);
        EXPECT_NEAR(windingNumber(sphere, d * (0.999 * inner * (s + 0.5) / 100.0)), 1.0, 1e-9);
        EXPECT_NEAR(windingNumber(sphere, d * (1.001 + 2.0 * s / 100.0)), 0.0, 1e-9);
    }
    // Just inside and just outside a face: 1 and 0.
    for (std::size_t t = 0; t < sphere.triangleCount(); t += 37) {
        const glm::dvec3 centroid = (glm::dvec3(sphere.vertex(t, 0)) + glm::dvec3(sphere.vertex(t, 1)) + glm::dvec3(sphere.vertex(t, 2))) / 3.0;
        const glm::dvec3 n(sphere.faceNormals[t]);
        EXPECT_NEAR(windingNumber(sphere, centroid - 1e-6 * n), 1.0, 1e-6);
        EXPECT_NEAR(windingNumber(sphere, centroid + 1e-6 * n), 0.0, 1e-6);
    }
    // On the surface, at a vertex: the triangles through the vertex subtend nothing and the rest
    // the vertex's interior solid angle, a little under half the sphere. By Girard's theorem that
    // angle is the sum of the dihedral angles at the vertex's edges less (n - 2)π.
    for (std::uint32_t v = 0; v < sphere.positions.size(); v += 11) {
        std::map<std::uint32_t, std::vector<glm::dvec3>> edgeNormals; // ring vertex -> normals of the faces on that edge
        std::size_t faces = 0;
        for (std::size_t t = 0; t < sphere.triangleCount(); ++t) {
            for (int c = 0; c < 3; ++c) {
                if (sphere.triangles[t][c] != v) continue;
                ++faces;
                for (int other : {1, 2}) edgeNormals[sphere.triangles[t][(c + other) % 3]].push_back(glm::dvec3(sphere.faceNormals[t]));
            }
        }
        double omega = -double(faces - 2) * kPi;
        for (const auto& [ring, normals] : edgeNormals) {
            ASSERT_EQ(normals.size(), 2u);
            omega += kPi - std::acos(std::clamp(glm::dot(normals[0], normals[1]), -1.0, 1.0));
        }
        const double w = windingNumber(sphere, glm::dvec3(sphere.positions[v]));
        EXPECT_NEAR(w, omega / (4.0 * kPi), 1e-6) << "vertex " << v;
        EXPECT_NEAR(w, 0.5, 0.1) << "vertex " << v;
    }
    // At a corner of a box: an eighth.
    const Mesh box = test::box({1.0f, 0.6f, 0.4f});
    for (const glm::vec3& corner : box.positions) EXPECT_NEAR(windingNumber(box, glm::dvec3(corner)), 0.125, 1e-12);
}

// How many of the 2D triangles contain q; checks each hit's orientation and weights on the way.
int containingCount(const glm::dvec2& q, const std::vector<glm::dvec2>& points, const std::vector<glm::uvec3>& triangles,
                    int expectedOrientation) {
    int count = 0;
    for (const glm::uvec3& t : triangles) {
        int orientation = 0;
        glm::dvec3 w;
        if (!pointInTriangle2d(q, points[t[0]], points[t[1]], points[t[2]], orientation, w)) continue;
        ++count;
        EXPECT_EQ(orientation, expectedOrientation);
        EXPECT_NEAR(w.x + w.y + w.z, 1.0, 1e-12);
        EXPECT_GE(std::min({w.x, w.y, w.z}), -1e-12);
        const glm::dvec2 back = w.x * points[t[0]] + w.y * points[t[1]] + w.z * points[t[2]];
        EXPECT_NEAR(back.x, q.x, 1e-12);
        EXPECT_NEAR(back.y, q.y, 1e-12);
    }
    return count;
}

std::vector<glm::uvec3> reversed(std::vector<glm::uvec3> triangles) {
    for (glm::uvec3& t : triangles) std::swap(t[1], t[2]);
    return triangles;
}

// pointInTriangle2d's branchless early reject (two edges whose rounded products certainly disagree)
// must answer as the chain of orientation2d signs, ties broken symbolically, that it stands in
// front of: the same hits, orientations and weights, bit for bit, on cases made to be degenerate
// (points on edges and their lines, slivers, repeated vertices, far offsets whose products round
// to ties, double-valued fan centres as the winding sign's caps have).
bool pointInTriangleByOrientations(const glm::dvec2& q, const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c,
                                   int& orientation, glm::dvec3& weights) {
    const glm::dvec2 pa = a - q, pb = b - q, pc = c - q;
    double wa, wb, wc;
    const int sa = orientation2d(pb, pc, wa);
    if (sa == 0 || orientation2d(pc, pa, wb) != sa || orientation2d(pa, pb, wc) != sa) return false;
    const double sum = wa + wb + wc;
    if (sum == 0.0) return false;
    weights = glm::dvec3(wa, wb, wc) / sum;
    orientation = -sa;
    return true;
}

TEST(PointInTriangle2d, TheEarlyRejectAnswersAsTheOrientations) {
    std::mt19937 rng(23);
    std::uniform_int_distribution<int> grid(-4, 4);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::size_t hits = 0, tiedHits = 0, cases = 0;
    auto check = [&](const glm::dvec2& q, const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
        int fastOrientation = 0, orientation = 0;
        glm::dvec3 fastWeights(0.0), weights(0.0);
        const bool fast = pointInTriangle2d(q, a, b, c, fastOrientation, fastWeights);
        const bool reference = pointInTriangleByOrientations(q, a, b, c, orientation, weights);
        ++cases;
        ASSERT_EQ(fast, reference) << "q " << q.x << "," << q.y << " a " << a.x << "," << a.y << " b " << b.x << "," << b.y << " c " << c.x << "," << c.y;
        if (!reference) return;
        ++hits;
        const glm::dvec2 pa = a - q, pb = b - q, pc = c - q;
        tiedHits += pb.y * pc.x == pb.x * pc.y || pc.y * pa.x == pc.x * pa.y || pa.y * pb.x == pa.x * pb.y;
        ASSERT_EQ(fastOrientation, orientation);
        ASSERT_EQ(fastWeights.x, weights.x);
        ASSERT_EQ(fastWeights.y, weights.y);
        ASSERT_EQ(fastWeights.z, weights.z);
    };
    for (int n = 0; n < 20000; ++n) {
        // Small integer points: many exact ties (q on an edge, on an edge's line, at a vertex).
        const glm::dvec2 a(grid(rng), grid(rng)), b(grid(rng), grid(rng)), c(grid(rng), grid(rng)), q(grid(rng), grid(rng));
        check(q, a, b, c);
        // Slivers: c on (or a rounding error off) the line ab, q on that line too.
        const double t = unit(rng), s = unit(rng) * 3.0 - 1.0;
        const glm::dvec2 onLine = a + (b - a) * t, qLine = a + (b - a) * s;
        check(qLine, a, b, onLine);
        check(onLine, a, b, qLine);
        // Far from the origin (large products that round) and with double-valued centres.
        const glm::dvec2 far(1e6 + grid(rng), -3e5 + grid(rng));
        const glm::dvec2 centre = (a + b + c) / 3.0;
        check(far + q * 1e-3, far + a * 1e-3, far + b * 1e-3, far + centre * 1e-3);
        check(centre, b, a, c);
        check(a + (centre - a) * s, a, b, centre);
    }
    EXPECT_GT(hits, cases / 20) << cases << " cases";
    EXPECT_GT(tiedHits, 100u) << "hits whose signs needed a tie broken";
}

TEST(PointInTriangle2d, PointsOnASharedDiagonalAreCountedOnce) {
    const std::vector<glm::dvec2> square = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    // Split along either diagonal, wound counter-clockwise and then clockwise.
    const std::vector<glm::uvec3> splits[2] = {{{0, 1, 2}, {0, 2, 3}}, {{0, 1, 3}, {1, 2, 3}}};
    for (int split = 0; split < 2; ++split) {
        for (int orientation : {1, -1}) {
            const std::vector<glm::uvec3> triangles = orientation > 0 ? splits[split] : reversed(splits[split]);
            for (int k = 1; k < 64; ++k) {
                const double t = k / 64.0;
                const glm::dvec2 q = split == 0 ? glm::dvec2(t, t) : glm::dvec2(t, 1.0 - t);
                EXPECT_EQ(containingCount(q, square, triangles, orientation), 1)
                    << "split " << split << " orientation " << orientation << " t " << t;
            }
            // Interior points elsewhere, and the shared edge of a square in general position.
            std::mt19937 rng(17);
            std::uniform_real_distribution<double> uniform(1e-6, 1.0 - 1e-6);
            for (int s = 0; s < 200; ++s) {
                EXPECT_EQ(containingCount({uniform(rng), uniform(rng)}, square, triangles, orientation), 1);
            }
        }
    }
    // A tilted square whose diagonal points are exactly representable: (0,0), (3,1), (2,4), (-1,3).
    const std::vector<glm::dvec2> tilted = {{0, 0}, {3, 1}, {2, 4}, {-1, 3}};
    for (int orientation : {1, -1}) {
        const std::vector<glm::uvec3> split = {{0, 1, 2}, {0, 2, 3}};
        const std::vector<glm::uvec3> triangles = orientation > 0 ? split : reversed(split);
        for (int k = 1; k < 32; ++k) {
            const glm::dvec2 q = glm::dvec2(2, 4) * (k / 32.0);
            EXPECT_EQ(containingCount(q, tilted, triangles, orientation), 1) << "k " << k;
        }
    }
}

TEST(PointInTriangle2d, TheSharedVertexOfAFanIsCountedOnce) {
    // Closed fans about a centre (axis-aligned spokes included, where the symbolic tie-breaking
    // decides), queried at the centre and on the spokes, wound both ways.
    for (const glm::dvec2 centre : {glm::dvec2(0, 0), glm::dvec2(0.25, -0.5), glm::dvec2(3, 7)}) {
        for (int n : {3, 4, 5, 6, 8, 12}) {
            std::vector<glm::dvec2> points = {centre};
            std::vector<glm::uvec3> fanTriangles;
            for (int k = 0; k < n; ++k) {
                const double angle = 2.0 * kPi * k / n;
                // Exact axis directions where the angle is a multiple of π/2.
                static const glm::dvec2 axes[4] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
                const glm::dvec2 dir = (4 * k) % n == 0 ? axes[4 * k / n] : glm::dvec2(std::cos(angle), std::sin(angle));
                points.push_back(centre + dir * 2.0);
                fanTriangles.emplace_back(0u, unsigned(1 + k), unsigned(1 + (k + 1) % n));
            }
            for (int orientation : {1, -1}) {
                const std::vector<glm::uvec3> triangles = orientation > 0 ? fanTriangles : reversed(fanTriangles);
                EXPECT_EQ(containingCount(centre, points, triangles, orientation), 1)
                    << "centre " << centre.x << "," << centre.y << " n " << n << " orientation " << orientation;
                for (int k = 0; k < n; ++k) {
                    const glm::dvec2 q = centre + (points[std::size_t(1 + k)] - centre) * 0.5;
                    EXPECT_EQ(containingCount(q, points, triangles, orientation), 1) << "spoke " << k << " n " << n;
                }
            }
        }
    }
}

} // namespace
} // namespace sdfgen
