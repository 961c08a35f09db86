// Exact distances, the sign methods, the mesh check and the brute-force reference: the geometric
// primitives against their definitions, the fast paths against the reference, and the ray mode's
// error measured against the exact field.
#include "sdfgen/compare.hpp"
#include "sdfgen/error.hpp"
#include "core/exact.hpp"
#include "core/bake.hpp"
#include "core/geometry.hpp"
#include "core/sign.hpp"
#include "core/topology.hpp"
#include "support/checks.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace sdfgen {
namespace {

constexpr double kPi = 3.14159265358979323846;

// ---------------------------------------------------------------------------------------------
// Helpers: meshes built from the test shapes, bakes, and sign comparisons.

Mesh translated(const Mesh& mesh, const glm::vec3& offset, bool flip) {
    std::vector<glm::dvec3> positions = mesh.worldPositions();
    for (glm::dvec3& p : positions) p += glm::dvec3(offset);
    std::vector<glm::uvec3> triangles = mesh.triangles;
    if (flip) {
        for (glm::uvec3& t : triangles) std::swap(t[1], t[2]);
    }
    return buildMesh(mesh.source, std::move(positions), std::move(triangles));
}

// Both meshes in one, b's indices shifted past a's vertices.
Mesh combined(const std::string& name, const Mesh& a, const Mesh& b) {
    std::vector<glm::dvec3> positions = a.worldPositions();
    const std::vector<glm::dvec3> more = b.worldPositions();
    positions.insert(positions.end(), more.begin(), more.end());
    std::vector<glm::uvec3> triangles = a.triangles;
    const unsigned shift = unsigned(a.positions.size());
    for (const glm::uvec3& t : b.triangles) triangles.push_back(t + glm::uvec3(shift));
    return buildMesh(name, std::move(positions), std::move(triangles));
}

// The icosphere of radius r without the triangles whose centroid has y > 0.8 r: a hole at the top.
Mesh holedSphere(float r) {
    const Mesh sphere = test::icosphere(r, 2);
    std::vector<glm::uvec3> kept;
    for (std::size_t t = 0; t < sphere.triangleCount(); ++t) {
        const glm::vec3 centroid = (sphere.vertex(t, 0) + sphere.vertex(t, 1) + sphere.vertex(t, 2)) / 3.0f;
        if (centroid.y <= 0.8f * r) kept.push_back(sphere.triangles[t]);
    }
    return buildMesh("holed sphere", sphere.worldPositions(), std::move(kept));
}

Mesh twoShells(bool flipSecond) {
    const Mesh sphere = test::icosphere(1.0f, 2);
    return combined(flipSecond ? "two shells, one flipped" : "two shells", translated(sphere, {-0.5f, 0, 0}, false),
                    translated(sphere, {0.5f, 0, 0}, flipSecond));
}

// A fan of `n` triangles about `apex`, its rim a circle of radius R about `centre` in the plane
// spanned by u and v. apex == centre gives a flat disk; an apex off the plane a cone-shaped cup.
Mesh fan(const std::string& name, glm::vec3 centre, glm::vec3 apex, glm::vec3 u, glm::vec3 v, float R, int n, bool flip) {
    std::vector<glm::vec3> positions = {apex};
    std::vector<glm::uvec3> triangles;
    for (int k = 0; k < n; ++k) {
        const float angle = 2.0f * float(kPi) * float(k) / float(n);
        positions.push_back(centre + R * (std::cos(angle) * u + std::sin(angle) * v));
        const unsigned b = unsigned(1 + k), c = unsigned(1 + (k + 1) % n);
        triangles.push_back(flip ? glm::uvec3(0, c, b) : glm::uvec3(0, b, c));
    }
    return buildMesh(name, std::move(positions), std::move(triangles));
}

// A generic tilted frame for the disks, so that no edge lines up with a grid axis.
void tiltedFrame(glm::vec3& u, glm::vec3& v) {
    u = glm::normalize(glm::vec3(0.8f, 0.3f, -0.5f));
    v = glm::normalize(glm::cross(glm::vec3(0.2f, 1.0f, 0.1f), u));
}

Mesh flatDisk() {
    glm::vec3 u, v;
    tiltedFrame(u, v);
    return fan("disk", {0.1f, 0.05f, -0.02f}, {0.1f, 0.05f, -0.02f}, u, v, 1.0f, 16, false);
}

Mesh cup(bool flip) {
    glm::vec3 u, v;
    tiltedFrame(u, v);
    const glm::vec3 centre(0.1f, 0.05f, -0.02f);
    const glm::vec3 axis = glm::normalize(glm::cross(u, v));
    return fan(flip ? "cup, flipped" : "cup", centre, centre + 1.5f * axis, u, v, 1.0f, 16, flip);
}

// Tetrahedron o, o+x, o+y, o+z (scaled by s, which may be negative: a mirror image), outward.
void addTetrahedron(std::vector<glm::vec3>& positions, std::vector<glm::uvec3>& triangles, glm::vec3 o, float s) {
    const unsigned base = unsigned(positions.size());
    positions.insert(positions.end(), {o, o + glm::vec3(s, 0, 0), o + glm::vec3(0, s, 0), o + glm::vec3(0, 0, s)});
    std::vector<glm::uvec3> faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    for (glm::uvec3 f : faces) {
        if (s < 0) std::swap(f[1], f[2]); // a mirror image reverses the orientation
        triangles.push_back(f + glm::uvec3(base));
    }
}

// Every triangle with three vertices of its own, at the same positions (as OBJ exports often do).
Mesh unshared(const Mesh& mesh) {
    std::vector<glm::dvec3> positions;
    std::vector<glm::uvec3> triangles;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const unsigned base = unsigned(positions.size());
        for (int c = 0; c < 3; ++c) positions.push_back(mesh.toWorld(glm::dvec3(mesh.vertex(t, c))));
        triangles.emplace_back(base, base + 1, base + 2);
    }
    return buildMesh(mesh.source + " (unshared)", std::move(positions), std::move(triangles));
}

double signedVolume(const Mesh& mesh) {
    double volume = 0;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        volume += glm::dot(glm::dvec3(mesh.vertex(t, 0)), glm::cross(glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2))));
    }
    return volume / 6.0;
}

MeshCheck checkMesh(const Mesh& mesh) {
    const Bvh tree(mesh);
    return MeshTopology(mesh).check(mesh, tree);
}

BakeResult bakeWith(const Mesh& mesh, int res, DistanceMethod method, SignMethod sign, int threads = 0, int rays = 64) {
    BakeSettings settings;
    settings.res = res;
    settings.method = method;
    settings.sign = sign;
    settings.rays = rays;
    return test::bakeMesh(mesh, settings, threads);
}

// The brute-force field of a named mesh at a resolution, computed once per test run (the bunny's
// is the slowest thing here and several tests compare against it).
const Field& bruteField(const std::string& name, const Mesh& mesh, int res) {
    static std::map<std::string, Field> cache;
    const std::string key = name + "@" + std::to_string(res);
    auto it = cache.find(key);
    if (it == cache.end()) {
        it = cache.emplace(key, bakeWith(mesh, res, DistanceMethod::Brute, SignMethod::Winding).field).first;
    }
    return it->second;
}

struct Shape {
    std::string name;
    Mesh mesh;
    int res;
};

std::vector<Shape> closedShapes() {
    return {{"icosphere", test::icosphere(1.0f, 2), 24},
            {"box", test::box({1.0f, 0.6f, 0.4f}), 24},
            {"torus", test::torus(1.0f, 0.3f, 24, 12), 24},
            {"bunny", loadMesh(test::bundledBunnyPath()), 16}};
}

std::vector<Shape> openShapes() {
    return {{"holed sphere", holedSphere(1.0f), 24}, {"two shells", twoShells(false), 24},
            {"two shells, one flipped", twoShells(true), 24}, {"disk", flatDisk(), 24},
            {"cup", cup(false), 24}, {"cup, flipped", cup(true), 24}};
}

// Sign disagreements of `test` with `reference`, split by whether the sample lies within one voxel
// of the surface (in either field).
struct SignCounts {
    std::size_t near = 0, nearWrong = 0, far = 0, farWrong = 0, referenceInside = 0;
};
SignCounts countSigns(const Field& test, const Field& reference) {
    SignCounts c;
    const double voxel = reference.grid.voxel;
    for (std::size_t i = 0; i < reference.values.size(); ++i) {
        const float a = test.values[i], b = reference.values[i];
        const bool wrong = (a < 0) != (b < 0);
        c.referenceInside += b < 0;
        if (std::min(std::fabs(a), std::fabs(b)) < voxel) {
            ++c.near;
            c.nearWrong += wrong;
        } else {
            ++c.far;
            c.farWrong += wrong;
        }
    }
    return c;
}

// ---------------------------------------------------------------------------------------------
// 1. Geometric primitives.

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

// ---------------------------------------------------------------------------------------------
// 2. Exact distances against the brute-force reference.

TEST(ExactDistance, EqualsBruteForceOnClosedMeshes) {
    for (const Shape& shape : closedShapes()) {
        const Field& brute = bruteField(shape.name, shape.mesh, shape.res);
        const BakeResult exact = bakeWith(shape.mesh, shape.res, DistanceMethod::Exact, SignMethod::Auto);
        const Grid& g = exact.field.grid;
        const double tolerance = 1e-5 * g.voxel * glm::length(glm::vec3(g.dims));
        const FieldDifference d = compareFields(exact.field, brute, 1.0);
        EXPECT_LT(d.maxAbs, tolerance) << shape.name;
        EXPECT_EQ(d.signDifferences, 0u) << shape.name;
        EXPECT_GT(d.compared, g.sampleCount() / 2) << shape.name;
        // Unsigned distances agree everywhere, the near-surface band included.
        double worst = 0;
        for (std::size_t i = 0; i < brute.values.size(); ++i) {
            worst = std::max(worst, double(std::fabs(std::fabs(exact.field.values[i]) - std::fabs(brute.values[i]))));
        }
        EXPECT_LT(worst, tolerance) << shape.name;
    }
}

TEST(ExactDistance, EqualsBruteForceOnOpenMeshes) {
    for (const Shape& shape : openShapes()) {
        const Field& brute = bruteField(shape.name, shape.mesh, shape.res);
        const NearestField nearest = computeNearest(shape.mesh, Bvh(shape.mesh), brute.grid, RunControl{});
        const double tolerance = 1e-5 * brute.grid.voxel * glm::length(glm::vec3(brute.grid.dims));
        double worst = 0;
        for (std::size_t i = 0; i < brute.values.size(); ++i) {
            worst = std::max(worst, double(std::fabs(nearest.distance[i] - std::fabs(brute.values[i]))));
            // The triangle reported is a real one.
            const std::uint32_t t = nearest.triangle[i];
            ASSERT_LT(t, shape.mesh.triangleCount());
        }
        EXPECT_LT(worst, tolerance) << shape.name;
    }
}

// ---------------------------------------------------------------------------------------------
// 3. Signs.

TEST(Signs, PseudonormalAndWindingEqualBruteOnClosedMeshes) {
    for (const Shape& shape : closedShapes()) {
        const Field& brute = bruteField(shape.name, shape.mesh, shape.res);
        for (SignMethod sign : {SignMethod::Pseudonormal, SignMethod::Winding}) {
            const BakeResult result = bakeWith(shape.mesh, shape.res, DistanceMethod::Exact, sign);
            EXPECT_EQ(result.sign, sign);
            EXPECT_FALSE(result.checked);
            const SignCounts c = countSigns(result.field, brute);
            EXPECT_EQ(c.farWrong, 0u) << shape.name << " " << toString(sign);
            EXPECT_GT(c.referenceInside, 0u) << shape.name;
            EXPECT_EQ(compareFields(result.field, brute, 1.0).signDifferences, c.farWrong);
        }
    }
}

TEST(Signs, WindingEqualsBruteOnOpenAndOverlappingMeshes) {
    for (const Shape& shape : openShapes()) {
        const Field& brute = bruteField(shape.name, shape.mesh, shape.res);
        const BakeResult result = bakeWith(shape.mesh, shape.res, DistanceMethod::Exact, SignMethod::Winding);
        const SignCounts c = countSigns(result.field, brute);
        EXPECT_EQ(c.farWrong, 0u) << shape.name;
        // Not vacuous: the shapes with an inside have one (a flat disk's winding number stays below 1/2).
        if (shape.name == "disk") {
            EXPECT_EQ(c.referenceInside, 0u);
        } else if (shape.name != "cup, flipped") {
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
            const SignCounts c = countSigns(result.field, brute);
            EXPECT_EQ(c.farWrong, 0u) << name << " res " << res << ": " << c.farWrong << " of " << c.far
                                      << " samples beyond one voxel have the wrong sign";
        }
    }
}

TEST(Signs, WindingInsideMatchesTheReferenceWindingNumberExactly) {
    // Sample by sample against windingNumber() itself, on the shells with one flipped: there the
    // winding number is -1, 0 and 1 in different regions.
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
                EXPECT_EQ(bool(inside[index]), w > 0.5) << i << "," << j << "," << k << " w = " << w;
            }
    EXPECT_GT(regions[0], 0u);
    EXPECT_GT(regions[2], 0u);
}

// ---------------------------------------------------------------------------------------------
// 3b. The mesh check and sign auto.

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
    EXPECT_EQ(check.nonManifoldVertices, 1u) << check.describe();
    EXPECT_EQ(check.boundaryEdges, 0u);
    EXPECT_EQ(check.nonManifoldEdges, 0u);
    EXPECT_EQ(check.inconsistentEdges, 0u);
    EXPECT_EQ(check.selfIntersections, 0u);
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
    EXPECT_EQ(check.inconsistentEdges, 3u) << check.describe();
    EXPECT_EQ(check.boundaryEdges, 0u);
    EXPECT_EQ(check.nonManifoldEdges, 0u);
    EXPECT_EQ(check.nonManifoldVertices, 0u);
    EXPECT_EQ(check.selfIntersections, 0u);
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

// ---------------------------------------------------------------------------------------------
// 4. The ray mode's error, measured against the exact field.

TEST(RaysVsExact, ErrorShrinksWithRaysAndRaysNeverUndercut) {
    const Mesh mesh = loadMesh(test::bundledBunnyPath());
    const int res = 24;
    const Field exact = bakeWith(mesh, res, DistanceMethod::Exact, SignMethod::Auto).field;
    const double voxel = exact.grid.voxel;
    double previousMean = std::numeric_limits<double>::infinity();
    for (int rays : {16, 64, 256}) {
        const Field field = bakeWith(mesh, res, DistanceMethod::Rays, SignMethod::Rays, 0, rays).field;
        double sum = 0;
        std::size_t undercuts = 0;
        for (std::size_t i = 0; i < exact.values.size(); ++i) {
            const double ray = std::fabs(field.values[i]), truth = std::fabs(exact.values[i]);
            const double error = (ray - truth) / voxel;
            sum += std::fabs(error);
            if (ray < truth - 1e-5 * voxel) ++undercuts;
        }
        const double mean = sum / double(exact.values.size());
        EXPECT_EQ(undercuts, 0u) << rays << " rays";
        EXPECT_LT(mean, previousMean) << rays << " rays";
        previousMean = mean;
    }
}

// ---------------------------------------------------------------------------------------------
// 5. compareFields.

Field rampField(glm::ivec3 dims) {
    Field f;
    f.grid.origin = {-1, -1, -1};
    f.grid.voxel = 0.25f;
    f.grid.dims = dims;
    f.values.resize(f.grid.sampleCount());
    for (int k = 0; k < dims.z; ++k)
        for (int j = 0; j < dims.y; ++j)
            for (int i = 0; i < dims.x; ++i) f.values[f.grid.index(i, j, k)] = glm::length(glm::vec3(f.grid.position(i, j, k))) - 0.6f;
    return f;
}

TEST(CompareFields, IdenticalNegatedBandAndMismatch) {
    const Field a = rampField({8, 8, 8});
    FieldDifference d = compareFields(a, a, 0.0);
    EXPECT_EQ(d.maxAbs, 0.0);
    EXPECT_EQ(d.meanAbs, 0.0);
    EXPECT_EQ(d.rmsAbs, 0.0);
    EXPECT_EQ(d.signDifferences, 0u);
    EXPECT_EQ(d.compared, a.grid.sampleCount());
    EXPECT_EQ(d.voxel, double(a.grid.voxel));
    EXPECT_EQ(d.signFraction(), 0.0);

    // One far sample negated: one sign difference, the max twice its magnitude.
    Field b = a;
    const std::size_t far = a.grid.index(0, 0, 0);
    b.values[far] = -b.values[far];
    d = compareFields(a, b, 0.0);
    EXPECT_EQ(d.signDifferences, 1u);
    EXPECT_DOUBLE_EQ(d.maxAbs, 2.0 * std::fabs(double(a.values[far])));
    EXPECT_DOUBLE_EQ(d.meanAbs, 2.0 * std::fabs(double(a.values[far])) / double(a.grid.sampleCount()));
    EXPECT_DOUBLE_EQ(d.signFraction(), 1.0 / double(a.grid.sampleCount()));
    EXPECT_EQ(compareFields(b, a, 0.0).signDifferences, 1u); // symmetric

    // A near-surface sample negated is excluded by a band wider than its distance.
    Field c = a;
    std::size_t nearest = 0;
    for (std::size_t i = 0; i < a.values.size(); ++i) {
        if (std::fabs(a.values[i]) < std::fabs(a.values[nearest])) nearest = i;
    }
    const double nearVoxels = std::fabs(a.values[nearest]) / a.grid.voxel;
    ASSERT_LT(nearVoxels, 1.0);
    c.values[nearest] = -c.values[nearest];
    EXPECT_EQ(compareFields(a, c, 0.0).signDifferences, 1u);
    d = compareFields(a, c, 1.0);
    EXPECT_EQ(d.signDifferences, 0u);
    EXPECT_EQ(d.maxAbs, 0.0);
    std::size_t inBand = 0;
    for (float v : a.values) inBand += std::fabs(v) < a.grid.voxel;
    EXPECT_EQ(d.compared, a.grid.sampleCount() - inBand);
    // The band is on either field: a sample moved into the band in one field is skipped too.
    Field e = a;
    e.values[far] = 0.0f;
    d = compareFields(a, e, 1.0);
    EXPECT_EQ(d.maxAbs, 0.0);
    EXPECT_EQ(d.compared, a.grid.sampleCount() - inBand - 1);

    // Different grids throw.
    EXPECT_THROW(compareFields(a, rampField({8, 8, 7}), 0.0), Error);
    Field moved = a;
    moved.grid.origin.x += 0.1f;
    EXPECT_THROW(compareFields(a, moved, 0.0), Error);
    Field scaled = a;
    scaled.grid.voxel *= 1.5f;
    EXPECT_THROW(compareFields(a, scaled, 0.0), Error);
}

// ---------------------------------------------------------------------------------------------
// 6. Determinism.

TEST(ExactBake, BitIdenticalForAnyThreadCount) {
    const Mesh mesh = loadMesh(test::bundledBunnyPath());
    for (SignMethod sign : {SignMethod::Winding, SignMethod::Pseudonormal}) {
        const Field one = bakeWith(mesh, 28, DistanceMethod::Exact, sign, 1).field;
        const Field many = bakeWith(mesh, 28, DistanceMethod::Exact, sign, 5).field;
        ASSERT_EQ(one.values.size(), many.values.size());
        EXPECT_EQ(std::memcmp(one.values.data(), many.values.data(), one.values.size() * sizeof(float)), 0) << toString(sign);
    }
    const Mesh small = test::torus(1.0f, 0.3f, 24, 12);
    const Field one = bakeWith(small, 16, DistanceMethod::Brute, SignMethod::Winding, 1).field;
    const Field many = bakeWith(small, 16, DistanceMethod::Brute, SignMethod::Winding, 5).field;
    EXPECT_EQ(std::memcmp(one.values.data(), many.values.data(), one.values.size() * sizeof(float)), 0) << "brute";
}

// ---------------------------------------------------------------------------------------------
// 7. Cancellation.

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

} // namespace
} // namespace sdfgen
