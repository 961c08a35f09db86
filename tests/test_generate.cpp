// The ray-sampling generator against analytic fields, the naive definition, and itself.
#include "core/accel/directions.hpp"
#include "core/distance/kernel.hpp"
#include "sdfgen/error.hpp"
#include "core/bake/bake.hpp"
#include "core/accel/ray_generator.hpp"
#include "core/mesh/sample_positions.hpp"
#include "support/checks.hpp"
#include "support/binary_rays.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <random>

namespace sdfgen {
namespace {

struct Baked {
    Mesh mesh;
    Field field;
};

// A ray-method field of `mesh`, kept together with the mesh.
Baked bakeMesh(Mesh mesh, int res, int rays, int threads = 0) {
    BakeSettings settings;
    settings.res = res;
    settings.rays = rays;
    settings.method = DistanceMethod::Rays;
    Field field = test::bakeMesh(mesh, settings, threads).field.dense();
    return {std::move(mesh), std::move(field)};
}

// The largest angle between any direction on the sphere and its nearest ray direction, estimated
// from 200k random directions and widened by 10% so it does not underestimate.
float coveringAngle(int rays) {
    const std::vector<glm::vec3> dirs = sphereDirections(rays);
    std::mt19937 rng(11);
    std::normal_distribution<float> gauss;
    float worst = 1.0f;
    for (int s = 0; s < 200000; ++s) {
        const glm::vec3 v = glm::normalize(glm::vec3(gauss(rng), gauss(rng), gauss(rng)));
        float best = -1.0f;
        for (const glm::vec3& d : dirs) best = std::max(best, glm::dot(v, d));
        worst = std::min(worst, best);
    }
    return std::acos(worst) * 1.1f;
}

struct ErrorStats {
    double mean = 0, median = 0; // in voxels
};
ErrorStats summarise(std::vector<double> errors) {
    ErrorStats s;
    if (errors.empty()) return s;
    std::sort(errors.begin(), errors.end());
    for (double e : errors) s.mean += e;
    s.mean /= double(errors.size());
    s.median = errors[errors.size() / 2];
    return s;
}

// Checks every sample of `baked` against the true distance `truth` (known to within `slack` of the
// mesh's own distance): the sign is right wherever |truth| > one voxel + slack, and the ray distance
// never undercuts the true distance (it is the length of a real ray to a real hit). Returns the errors.
std::vector<double> checkSignsAndUpperBound(const Baked& baked, const std::function<float(glm::vec3)>& truth, float slack) {
    const Grid& g = baked.field.grid;
    std::vector<double> errors;
    int wrongSigns = 0, undercuts = 0;
    for (int k = 0; k < g.dims.z; ++k)
        for (int j = 0; j < g.dims.y; ++j)
            for (int i = 0; i < g.dims.x; ++i) {
                const float value = baked.field.at(i, j, k);
                const float exact = truth(glm::vec3(g.position(i, j, k)));
                EXPECT_TRUE(std::isfinite(value));
                if (std::fabs(exact) > g.voxel + slack && (value < 0) != (exact < 0)) ++wrongSigns;
                if (std::fabs(value) < std::fabs(exact) - slack - 1e-5f) ++undercuts;
                errors.push_back((std::fabs(value) - std::fabs(exact)) / g.voxel);
            }
    EXPECT_EQ(wrongSigns, 0);
    EXPECT_EQ(undercuts, 0);
    return errors;
}

TEST(RayGenerator, SphereMatchesAnalyticWithinTheCoveringAngleBound) {
    const float r = 1.0f;
    const int rays = 256;
    const float sag = test::icosphereSag(r, 4);
    const Baked baked = bakeMesh(test::icosphere(r, 4), 32, rays);
    const float theta = coveringAngle(rays);
    const Grid& g = baked.field.grid;
    checkSignsAndUpperBound(baked, [&](glm::vec3 p) { return test::sphereDistance(p, r); }, sag);

    // Some ray lies within theta of the direction to the closest point. Inside, that ray leaves the
    // mesh before the circumscribed sphere; outside, it meets the mesh before the inscribed sphere.
    const float inner = r - sag;
    for (int k = 0; k < g.dims.z; ++k)
        for (int j = 0; j < g.dims.y; ++j)
            for (int i = 0; i < g.dims.x; ++i) {
                const float D = glm::length(glm::vec3(g.position(i, j, k)));
                const float s = D * std::sin(theta), c = D * std::cos(theta);
                float bound;
                if (D < inner) bound = c + std::sqrt(r * r - s * s);
                else if (D > r && s < inner) bound = c - std::sqrt(inner * inner - s * s);
                else continue; // between the spheres: within sag of the surface
                EXPECT_LE(std::fabs(baked.field.at(i, j, k)), bound * (1.0f + 1e-5f)) << "D = " << D;
            }
}

TEST(RayGenerator, BoxInsideErrorBoundedByCoveringAngle) {
    const glm::vec3 h(1.0f, 0.6f, 0.4f);
    const int rays = 256;
    const Baked baked = bakeMesh(test::box(h), 32, rays);
    const float theta = coveringAngle(rays);
    const Grid& g = baked.field.grid;
    checkSignsAndUpperBound(baked, [&](glm::vec3 p) { return test::boxDistance(p, h); }, 0.0f);
    // Inside a convex solid the ray nearest the closest face's normal leaves through that face or
    // earlier, so it travels at most d / cos(theta).
    for (int k = 0; k < g.dims.z; ++k)
        for (int j = 0; j < g.dims.y; ++j)
            for (int i = 0; i < g.dims.x; ++i) {
                const float d = test::boxDistance(glm::vec3(g.position(i, j, k)), h);
                if (d < 0) {
                    EXPECT_LE(-baked.field.at(i, j, k), -d / std::cos(theta) * (1.0f + 1e-5f));
                }
            }
}

TEST(RayGenerator, TorusSignsAndErrorDistribution) {
    const float R = 1.0f, rr = 0.35f;
    const int rays = 256;
    const Baked baked = bakeMesh(test::torus(R, rr, 96, 48), 48, rays);
    const float sag = test::torusSag(R, rr, 96, 48);
    const ErrorStats s = summarise(
        checkSignsAndUpperBound(baked, [&](glm::vec3 p) { return test::torusDistance(p, R, rr); }, sag));
    // The torus is not convex, so no per-sample bound holds; the bulk of samples is still tight:
    // the sphere's bound at this covering angle gives about 2% of the distance (< 1 voxel here).
    EXPECT_LT(s.median, 0.5);
    EXPECT_LT(s.mean, 1.0);
}

TEST(RayGenerator, ErrorShrinksWithMoreRays) {
    const Mesh sphere = test::icosphere(1.0f, 4);
    const float sag = test::icosphereSag(1.0f, 4);
    double previous = 1e30;
    for (int rays : {16, 64, 256, 1024}) {
        const Baked baked = bakeMesh(sphere, 24, rays);
        const ErrorStats s =
            summarise(checkSignsAndUpperBound(baked, [](glm::vec3 p) { return test::sphereDistance(p, 1.0f); }, sag));
        EXPECT_LT(s.mean, previous);
        previous = s.mean;
    }
}

TEST(RayGenerator, EqualsTheNaiveDefinition) {
    // Every ray traced in full, one at a time: the generator's packets and early vote must agree exactly.
    const Mesh mesh = loadMesh(test::bundledBunnyPath());
    const Bvh tree(mesh);
    const int rays = 24;
    const Grid grid = makeGrid(mesh.worldBounds(), 10, 0.1f);
    const Field field = generateRayField(mesh, tree, grid, rays, RunControl{});
    const std::vector<glm::vec3> dirs = sphereDirections(rays);
    for (int k = 0; k < grid.dims.z; ++k)
        for (int j = 0; j < grid.dims.y; ++j)
            for (int i = 0; i < grid.dims.x; ++i) {
                float nearest = std::numeric_limits<float>::infinity();
                int hits = 0, backs = 0;
                for (const glm::vec3& d : dirs) {
                    test::RayHit hit;
                    const glm::vec3 origin(localPosition(mesh, grid, i, j, k));
                    if (!test::intersect(mesh, tree, origin, d, std::numeric_limits<float>::infinity(), hit)) continue;
                    ++hits;
                    backs += hit.backFace;
                    nearest = std::min(nearest, hit.t);
                }
                if (hits == 0) continue;
                const float distance = float(double(nearest) * mesh.unit);
                const float expected = 2 * backs > hits ? -distance : distance;
                ASSERT_EQ(field.at(i, j, k), expected) << i << "," << j << "," << k;
            }
}

// The generator as it was before the ray tree: the same 2x2x2 blocks and early vote, each direction
// traced by the binary tree's packet traversal (test::intersect). The wide traversal must give these
// bits exactly.
std::vector<float> binaryTreeRayField(const Mesh& mesh, const Bvh& tree, const Grid& grid, int rays) {
    using namespace simd;
    const std::vector<glm::vec3> directions = sphereDirections(rays);
    const float infinity = std::numeric_limits<float>::infinity();
    std::vector<float> values(grid.sampleCount());
    for (int k0 = 0; k0 < grid.dims.z; k0 += 2)
        for (int j0 = 0; j0 < grid.dims.y; j0 += 2)
            for (int i0 = 0; i0 < grid.dims.x; i0 += 2) {
                test::RayPacket packet;
                i8 active = splat(0);
                glm::ivec3 sample[8];
                for (int lane = 0; lane < 8; ++lane) {
                    const glm::ivec3 s(i0 + (lane & 1), j0 + ((lane >> 1) & 1), k0 + (lane >> 2));
                    const bool inGrid = s.x < grid.dims.x && s.y < grid.dims.y && s.z < grid.dims.z;
                    sample[lane] = inGrid ? s : glm::ivec3(i0, j0, k0);
                    const glm::vec3 p(localPosition(mesh, grid, sample[lane].x, sample[lane].y, sample[lane].z));
                    packet.ox[lane] = p.x, packet.oy[lane] = p.y, packet.oz[lane] = p.z;
                    active[lane] = inGrid ? -1 : 0;
                }
                f8 nearest = splat(infinity);
                i8 hits = splat(0), backs = splat(0), decided = ~active;
                for (int r = 0; r < rays; ++r) {
                    packet.direction = directions[std::size_t(r)];
                    packet.tMax = select(active, select(decided, nearest, splat(infinity)), splat(-1.0f));
                    test::intersect(mesh, tree, packet);
                    nearest = select(packet.hit, min(nearest, packet.tMax), nearest);
                    const i8 voting = packet.hit & ~decided;
                    hits -= voting;
                    backs -= voting & packet.backFace;
                    const i8 fronts = hits - backs, remaining = splat(rays - r - 1);
                    decided |= (backs > fronts + remaining) | (fronts >= backs + remaining);
                }
                for (int lane = 0; lane < 8; ++lane) {
                    if (!active[lane]) continue;
                    float& value = values[grid.index(sample[lane].x, sample[lane].y, sample[lane].z)];
                    if (hits[lane] == 0) {
                        const glm::vec3 p(packet.ox[lane], packet.oy[lane], packet.oz[lane]);
                        const glm::vec3 far = glm::max(glm::abs(p - mesh.bounds.min), glm::abs(p - mesh.bounds.max));
                        value = float(double(glm::length(far)) * mesh.unit);
                        continue;
                    }
                    const float distance = float(double(nearest[lane]) * mesh.unit);
                    value = backs[lane] > hits[lane] - backs[lane] ? -distance : distance;
                }
            }
    return values;
}

TEST(RayGenerator, EqualsTheBinaryTreePacketTraversalOnBothSimdPaths) {
    // The bunny, and a box whose faces and edges lie on sample planes (rays through edges and
    // corners, hits at equal distances on several triangles): bit for bit on every compiled path.
    const SimdPath chosen = simdPath();
    struct Case {
        Mesh mesh;
        int res, rays;
    };
    for (const Case& c : {Case{loadMesh(test::bundledBunnyPath()), 20, 40}, Case{test::box({1.0f, 1.0f, 1.0f}), 17, 64}}) {
        SCOPED_TRACE(c.mesh.source);
        const Bvh tree(c.mesh);
        const Grid grid = makeGrid(c.mesh.worldBounds(), c.res, 0.25);
        const std::vector<float> expected = binaryTreeRayField(c.mesh, tree, grid, c.rays);
        for (SimdPath path : kSimdPaths) {
            if (!simdPathAvailable(path)) continue;
            setSimdPath(path);
            const std::vector<float> values = generateRayField(c.mesh, tree, grid, c.rays, RunControl{}).values;
            EXPECT_EQ(std::memcmp(values.data(), expected.data(), values.size() * sizeof(float)), 0) << toString(path);
        }
    }
    setSimdPath(chosen);
}

TEST(RayGenerator, BitIdenticalForAnyThreadCount) {
    const Mesh mesh = loadMesh(test::bundledBunnyPath());
    const Field one = bakeMesh(mesh, 28, 32, 1).field;
    const Field many = bakeMesh(mesh, 28, 32, 5).field;
    ASSERT_EQ(one.values.size(), many.values.size());
    EXPECT_EQ(std::memcmp(one.values.data(), many.values.data(), one.values.size() * sizeof(float)), 0);
}

TEST(RayGenerator, SamplesWhoseRaysAllMissGetTheFarCornerDistance) {
    // One flat triangle and one ray direction, (1, 0, 0), in its plane: nothing is ever hit.
    const Mesh mesh = buildMesh("flat", std::vector<glm::dvec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
    const Bvh tree(mesh);
    const Grid grid = makeGrid(mesh.worldBounds(), 6, 0.1f);
    const Field field = generateRayField(mesh, tree, grid, 1, RunControl{});
    for (int k = 0; k < grid.dims.z; ++k)
        for (int j = 0; j < grid.dims.y; ++j)
            for (int i = 0; i < grid.dims.x; ++i) {
                const glm::dvec3 p = grid.position(i, j, k);
                const WorldBounds box = mesh.worldBounds();
                const glm::dvec3 far = glm::max(glm::abs(p - box.min), glm::abs(p - box.max));
                EXPECT_FLOAT_EQ(field.at(i, j, k), float(glm::length(far)));
            }
}

TEST(RayGenerator, ReportsProgressAndHonoursCancel) {
    const Mesh mesh = test::icosphere(1.0f, 2);
    const Bvh tree(mesh);
    const Grid grid = makeGrid(mesh.worldBounds(), 16, 0.1f);
    RunControl control;
    std::vector<double> seen;
    control.progress = [&](double f) { seen.push_back(f); };
    control.threads = 1;
    generateRayField(mesh, tree, grid, 8, control);
    ASSERT_FALSE(seen.empty());
    EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
    EXPECT_EQ(seen.back(), 1.0);

    std::atomic<bool> cancel{false};
    control.cancel = &cancel;
    control.progress = [&](double f) { if (f > 0.2) cancel = true; };
    EXPECT_THROW(generateRayField(mesh, tree, grid, 8, control), Cancelled);
}

TEST(RayGenerator, RejectsImpossibleSettings) {
    const Mesh mesh = test::icosphere(1.0f, 1);
    const Bvh tree(mesh);
    BakeSettings settings;
    settings.rays = 0;
    EXPECT_THROW(bake(mesh, tree, settings, RunControl{}), Error);
    settings = BakeSettings{};
    settings.res = 0;
    EXPECT_THROW(bake(mesh, tree, settings, RunControl{}), Error);
    settings = BakeSettings{};
    settings.padding = -0.5f;
    EXPECT_THROW(bake(mesh, tree, settings, RunControl{}), Error);
}

TEST(SphereDirections, UnitLengthAndEvenlySpread) {
    for (int n : {1, 2, 16, 64, 257}) {
        const std::vector<glm::vec3> dirs = sphereDirections(n);
        ASSERT_EQ(int(dirs.size()), n);
        glm::vec3 sum(0.0f);
        for (const glm::vec3& d : dirs) {
            EXPECT_NEAR(glm::length(d), 1.0f, 1e-6f);
            sum += d;
        }
        if (n >= 16) {
            EXPECT_LT(glm::length(sum) / float(n), 0.05f); // balanced: no hemisphere favoured
        }
    }
    // Even: the covering angle is close to that of an ideal packing of 256 caps (about 0.125 rad).
    EXPECT_LT(coveringAngle(256), 0.2f);
}

TEST(Shapes, GeneratedMeshesAreOutwardOriented) {
    for (const Mesh& mesh : {test::icosphere(1.0f, 2), test::box({1, 2, 3}), test::torus(1.0f, 0.3f, 24, 12)}) {
        double volume = 0;
        for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
            volume += glm::dot(glm::dvec3(mesh.vertex(t, 0)), glm::cross(glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2))));
        }
        EXPECT_GT(volume, 0.0) << mesh.source;
    }
}

} // namespace
} // namespace sdfgen
