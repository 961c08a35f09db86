// Point queries through sdfgen::Model: exact like the grid, and equal to the baked field at its samples.
#include "core/mesh/geometry.hpp"
#include "core/sign/winding_sign.hpp"
#include "sdfgen/model.hpp"
#include "support/checks.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <cmath>
#include <cstring>
#include <random>

namespace sdfgen {
namespace {

// The icosphere without its top cap: a hole, so auto signs by the winding number.
Mesh holedSphere() {
    const Mesh sphere = test::icosphere(1.0f, 2);
    std::vector<glm::uvec3> kept;
    for (std::size_t t = 0; t < sphere.triangleCount(); ++t) {
        const float y = (sphere.vertex(t, 0).y + sphere.vertex(t, 1).y + sphere.vertex(t, 2).y) / 3.0f;
        if (y < 0.8f) kept.push_back(sphere.triangles[t]);
    }
    return buildMesh("holed sphere", sphere.worldPositions(), kept);
}

std::vector<double> positionsOf(const Field& field) {
    const Grid& g = field.grid;
    std::vector<double> xyz;
    xyz.reserve(3 * g.sampleCount());
    for (int k = 0; k < g.dims.z; ++k)
        for (int j = 0; j < g.dims.y; ++j)
            for (int i = 0; i < g.dims.x; ++i) {
                const glm::dvec3 p = g.position(i, j, k);
                xyz.insert(xyz.end(), {p.x, p.y, p.z});
            }
    return xyz;
}

void expectQueriesEqualTheField(const Model& model, int res, SignMethod expectedSign) {
    SCOPED_TRACE(model.mesh().source);
    BakeSettings settings;
    settings.res = res;
    const BakeResult baked = model.bake(settings);
    EXPECT_EQ(baked.sign, expectedSign);
    const std::vector<double> points = positionsOf(baked.field.dense());
    std::vector<float> distance(baked.field.dense().values.size());
    PointQueryOutputs out;
    out.signedDistance = distance.data();
    model.query(points.data(), distance.size(), out);
    std::size_t differing = 0;
    for (std::size_t i = 0; i < distance.size(); ++i) {
        const bool differs = std::memcmp(&distance[i], &baked.field.dense().values[i], sizeof(float)) != 0;
        differing += differs;
        if (differs) ADD_FAILURE() << "sample " << i << ": query " << distance[i] << ", field " << baked.field.dense().values[i];
    }
    EXPECT_EQ(differing, 0u) << "of " << distance.size();
}

TEST(PointQuery, EqualsTheBakedFieldAtItsSamples) {
    expectQueriesEqualTheField(Model(loadObj(test::bundledBunnyPath())), 24, SignMethod::Pseudonormal);
    expectQueriesEqualTheField(Model(holedSphere()), 20, SignMethod::Winding);
    expectQueriesEqualTheField(Model(test::torus(1.0f, 0.3f, 24, 12)), 20, SignMethod::Pseudonormal);
}

TEST(PointQuery, WindingSignAtSamplesEqualsTheBakedWindingField) {
    const Model model(loadObj(test::bundledBunnyPath()));
    BakeSettings settings;
    settings.res = 20;
    settings.sign = SignMethod::Winding;
    const Field field = model.bake(settings).field.dense();
    const std::vector<double> points = positionsOf(field);
    std::vector<float> distance(field.values.size());
    PointQueryOutputs out;
    out.signedDistance = distance.data();
    model.query(points.data(), distance.size(), out, SignMethod::Winding);
    for (std::size_t i = 0; i < distance.size(); ++i) ASSERT_EQ(distance[i], field.values[i]) << i;
}

TEST(PointQuery, MatchesBruteForceAtRandomPoints) {
    // Nearest triangle, closest point, distance and winding number against every triangle in double.
    for (const Mesh& mesh : {holedSphere(), test::torus(1.0f, 0.3f, 24, 12)}) {
        SCOPED_TRACE(mesh.source);
        const Model model(mesh);
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> coordinate(-1.6, 1.6);
        const std::size_t n = 3000;
        std::vector<double> points(3 * n);
        for (double& c : points) c = coordinate(rng);
        std::vector<float> unsignedDistance(n), signedDistance(n);
        std::vector<double> closest(3 * n), winding(n);
        std::vector<std::int64_t> triangle(n);
        PointQueryOutputs out{signedDistance.data(), unsignedDistance.data(), closest.data(), triangle.data(), winding.data()};
        model.query(points.data(), n, out, SignMethod::Winding);
        for (std::size_t i = 0; i < n; ++i) {
            const glm::dvec3 p(points[3 * i], points[3 * i + 1], points[3 * i + 2]);
            const glm::dvec3 local = mesh.toLocal(p);
            double best = std::numeric_limits<double>::infinity();
            for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
                best = std::min(best, closestPointOnTriangle(local, glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)),
                                                             glm::dvec3(mesh.vertex(t, 2))).distanceSquared);
            }
            const double truth = std::sqrt(best) * mesh.unit;
            ASSERT_NEAR(unsignedDistance[i], truth, 1e-6) << i;
            const glm::dvec3 q(closest[3 * i], closest[3 * i + 1], closest[3 * i + 2]);
            EXPECT_NEAR(glm::length(q - p), truth, 1e-6) << i;
            // The nearest triangle reported is one at the true distance.
            ASSERT_GE(triangle[i], 0) << i;
            ASSERT_LT(std::size_t(triangle[i]), mesh.triangleCount()) << i;
            const std::size_t t = std::size_t(triangle[i]);
            EXPECT_NEAR(std::sqrt(closestPointOnTriangle(local, glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)),
                                                         glm::dvec3(mesh.vertex(t, 2))).distanceSquared) * mesh.unit,
                        truth, 1e-6) << i;
            const double w = windingNumber(mesh, local);
            EXPECT_NEAR(winding[i], w, 1e-9) << i;
            if (std::fabs(std::fabs(w) - 0.5) > 1e-6) {
                EXPECT_EQ(signedDistance[i] < 0, std::fabs(w) > 0.5) << i << " w = " << w;
            }
        }
    }
}

TEST(PointQuery, ClosestHitMatchesBruteForceInDouble) {
    // Model::closest's record (triangle, point, barycentrics, signed distance, sign, gradient)
    // against every triangle measured in double, at random points and on the surface.
    for (const Mesh& mesh : {holedSphere(), test::torus(1.0f, 0.3f, 24, 12)}) {
        SCOPED_TRACE(mesh.source);
        const Model model(mesh);
        std::mt19937 rng(11);
        std::uniform_real_distribution<double> coordinate(-1.6, 1.6);
        std::vector<glm::dvec3> points(2000);
        for (glm::dvec3& p : points) p = {coordinate(rng), coordinate(rng), coordinate(rng)};
        const std::size_t onSurface = 50; // face centroids: distance 0
        for (std::size_t t = 0; t < onSurface; ++t) {
            const std::size_t face = t * 7 % mesh.triangleCount();
            points.push_back(mesh.toWorld((glm::dvec3(mesh.vertex(face, 0)) + glm::dvec3(mesh.vertex(face, 1)) + glm::dvec3(mesh.vertex(face, 2))) / 3.0));
        }
        const std::vector<ClosestHit> hits = model.closest(points, SignMethod::Winding);
        const std::vector<float> signedDistance = model.signedDistance(points);
        ASSERT_EQ(hits.size(), points.size());
        std::size_t unique = 0, zero = 0;
        for (std::size_t i = 0; i < points.size(); ++i) {
            const ClosestHit& hit = hits[i];
            const glm::dvec3 local = mesh.toLocal(points[i]);
            auto measure = [&](std::size_t t) {
                return closestPointOnTriangle(local, glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2)));
            };
            double best = std::numeric_limits<double>::infinity(), second = best;
            std::size_t bestTriangle = 0;
            for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
                const double d = measure(t).distanceSquared;
                if (d < best) second = best, best = d, bestTriangle = t;
                else second = std::min(second, d);
            }
            ASSERT_GE(hit.triangle, 0);
            const std::size_t t = std::size_t(hit.triangle);
            const ClosestPoint truth = measure(t);
            EXPECT_NEAR(std::sqrt(truth.distanceSquared) * mesh.unit, std::sqrt(best) * mesh.unit, 1e-6) << i;
            if (std::sqrt(second) - std::sqrt(best) > 1e-6) {
                ++unique;
                EXPECT_EQ(t, bestTriangle) << i;
            }
            EXPECT_EQ(glm::length(hit.point - mesh.toWorld(truth.point)), 0.0) << i;
            const glm::dvec3 w = hit.barycentric;
            EXPECT_EQ(w, barycentricOf(truth, glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2)))) << i;
            EXPECT_NEAR(w.x + w.y + w.z, 1.0, 1e-12) << i;
            EXPECT_GE(std::min({w.x, w.y, w.z}), -1e-12) << i;
            const glm::dvec3 recombined = w.x * mesh.toWorld(glm::dvec3(mesh.vertex(t, 0))) + w.y * mesh.toWorld(glm::dvec3(mesh.vertex(t, 1))) +
                                          w.z * mesh.toWorld(glm::dvec3(mesh.vertex(t, 2)));
            EXPECT_LT(glm::length(recombined - hit.point), 1e-12) << i;
            EXPECT_EQ(hit.distance, float(std::sqrt(truth.distanceSquared) * mesh.unit) * float(hit.sign)) << i;
            EXPECT_EQ(hit.sign, std::signbit(hit.distance) ? -1 : 1) << i;
            EXPECT_NEAR(std::fabs(glm::length(hit.gradient) - 1.0), 0.0, 1e-6) << i;
            if (i < points.size() - onSurface) {
                EXPECT_EQ(hit.distance, signedDistance[i]) << i; // auto signs this holed sphere and torus by the winding number too
                const glm::dvec3 expected = (points[i] - hit.point) / glm::length(points[i] - hit.point) * double(hit.sign);
                EXPECT_LT(glm::length(hit.gradient - expected), 1e-6) << i;
            } else { // on the surface (up to the rounding of the world frame): the face normal
                EXPECT_LT(std::fabs(hit.distance), 1e-6f) << i;
                if (hit.distance == 0.0f) {
                    ++zero;
                    EXPECT_EQ(hit.gradient, glm::dvec3(mesh.faceNormals[t])) << i;
                }
            }
        }
        EXPECT_GT(unique, points.size() / 4); // the rest tie at a shared edge or vertex
        EXPECT_GT(zero, 0u);
    }
}

TEST(PointQuery, RefitModelAnswersAsAFreshOne) {
    // Vertices moved three times (a wobble, then a swirl): every query of the refit model equals the
    // same query of a model built from the moved mesh, for every sign; the check is kept.
    for (const Mesh& start : {test::icosphere(1.0f, 3), holedSphere(), test::torus(1.0f, 0.3f, 24, 12)}) {
        SCOPED_TRACE(start.source);
        std::vector<glm::dvec3> positions = start.worldPositions();
        Model model(start);
        const MeshCheck firstCheck = model.check();
        std::mt19937 rng(5);
        std::uniform_real_distribution<double> coordinate(-1.6, 1.6);
        std::vector<double> points(3 * 1500);
        for (double& c : points) c = coordinate(rng);
        for (int step = 1; step <= 3; ++step) {
            for (glm::dvec3& p : positions) {
                p += 0.02 * step * glm::dvec3(std::sin(3.0 * p.y), std::cos(2.0 * p.z), std::sin(p.x + p.y));
            }
            model = model.refit(buildMesh(start.source, positions, start.triangles));
            const Model fresh(buildMesh(start.source, positions, start.triangles));
            EXPECT_EQ(model.check().selfIntersections, firstCheck.selfIntersections);
            EXPECT_EQ(model.check().describe(), fresh.check().describe()); // no self-intersection made: the same check
            for (const SignMethod sign : {SignMethod::Auto, SignMethod::Winding, SignMethod::Pseudonormal}) {
                auto answers = [&](const Model& m) {
                    const std::size_t n = points.size() / 3;
                    std::vector<float> sdf(n), udf(n);
                    std::vector<double> closest(3 * n), gradient(3 * n), barycentric(3 * n), winding(n);
                    std::vector<std::int64_t> triangle(n);
                    PointQueryOutputs out{sdf.data(), udf.data(), closest.data(), triangle.data(), winding.data(), gradient.data(), barycentric.data()};
                    m.query(points.data(), n, out, sign);
                    return std::make_tuple(sdf, udf, closest, triangle, winding, gradient, barycentric);
                };
                EXPECT_TRUE(answers(model) == answers(fresh)) << toString(sign) << " step " << step;
            }
            BakeSettings settings;
            settings.res = 24;
            EXPECT_TRUE(model.bake(settings).field.dense().values == fresh.bake(settings).field.dense().values) << step;
        }
    }
}

TEST(PointQuery, RefitKeepsTheCheckWhileTheEdgesHold) {
    // A sphere pushed through itself: a fresh check finds the self-intersections; the refit model
    // keeps the check it had (auto's decision), as documented. A changed triangle list builds afresh.
    const Mesh sphere = test::icosphere(1.0f, 2);
    std::vector<glm::dvec3> positions = sphere.worldPositions();
    const Model model(sphere);
    ASSERT_TRUE(model.check().closedAndClean());
    for (glm::dvec3& p : positions) {
        if (p.y > 0.5) p.y -= 1.2; // the cap through the sphere's inside and out of its other side
    }
    const Model refit = model.refit(buildMesh("pushed", positions, sphere.triangles));
    const Model fresh(buildMesh("pushed", positions, sphere.triangles));
    EXPECT_GT(fresh.check().selfIntersections, 0u);
    EXPECT_EQ(refit.check().selfIntersections, 0u);
    std::vector<glm::uvec3> fewer(sphere.triangles.begin() + 1, sphere.triangles.end());
    const Model rebuilt = model.refit(buildMesh("fewer", positions, fewer));
    EXPECT_EQ(rebuilt.mesh().triangleCount(), fewer.size());
    EXPECT_EQ(rebuilt.check().selfIntersections, Model(buildMesh("fewer", positions, fewer)).check().selfIntersections);
}

TEST(PointQuery, IndependentOfTheThreadCount) {
    const Model model(loadObj(test::bundledBunnyPath()));
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> coordinate(-0.1, 0.1);
    std::vector<double> points(3 * 5000);
    for (double& c : points) c = coordinate(rng);
    std::vector<float> one(5000), many(5000);
    RunControl control;
    control.threads = 1;
    PointQueryOutputs out;
    out.signedDistance = one.data();
    model.query(points.data(), 5000, out, SignMethod::Auto, control);
    control.threads = 5;
    out.signedDistance = many.data();
    model.query(points.data(), 5000, out, SignMethod::Auto, control);
    EXPECT_EQ(std::memcmp(one.data(), many.data(), one.size() * sizeof(float)), 0);
}

// Channels asked of a query (PointQueryOutputs::channels) are the bake's at its samples, bit for
// bit: interleaved where the field's are planar.
TEST(PointQuery, ChannelsEqualTheBakedChannelsAtItsSamples) {
    const Model model(holedSphere());
    BakeSettings settings;
    settings.res = 12;
    settings.channels = Channels::all();
    const BakeResult baked = model.bake(settings);
    const Field& field = baked.field.dense();
    const std::vector<double> points = positionsOf(field);
    const std::size_t count = field.values.size();
    std::vector<float> distance(count);
    std::vector<ChannelValues> channels;
    PointQueryOutputs out;
    out.signedDistance = distance.data();
    out.channels = settings.channels;
    out.channelValues = &channels;
    model.query(points.data(), count, out);
    EXPECT_EQ(distance, field.values);
    ASSERT_EQ(channels.size(), field.channels.size());
    for (std::size_t c = 0; c < channels.size(); ++c) {
        const ChannelValues& queried = channels[c];
        const ChannelValues& bakedChannel = field.channels[c];
        SCOPED_TRACE(queried.name);
        EXPECT_EQ(queried.name, bakedChannel.name);
        const std::size_t width = std::size_t(queried.info().width);
        ASSERT_EQ(queried.size(), width * count);
        for (std::size_t i = 0; i < count; ++i) {
            for (std::size_t a = 0; a < width; ++a) {
                if (queried.info().type == ChannelType::Int32) {
                    EXPECT_EQ(queried.ints[width * i + a], bakedChannel.ints[a * count + i]) << i;
                } else {
                    EXPECT_EQ(queried.floats[width * i + a], bakedChannel.floats[a * count + i]) << i;
                }
            }
        }
    }
    out.channelValues = nullptr;
    EXPECT_CONTAINS(test::errorFrom([&] { model.query(points.data(), 1, out); }), "no channelValues");
}

TEST(PointQuery, BadPointsAndSignsAreErrors) {
    const Model model(test::icosphere(1.0f, 1));
    const double bad[3] = {0.0, std::nan(""), 0.0};
    float d = 0;
    PointQueryOutputs out;
    out.signedDistance = &d;
    EXPECT_CONTAINS(test::errorFrom([&] { model.query(bad, 1, out); }), "non-finite");
    const double good[3] = {0.0, 0.0, 0.0};
    EXPECT_CONTAINS(test::errorFrom([&] { model.query(good, 1, out, SignMethod::Rays); }), "auto, winding or pseudonormal");
    model.query(good, 1, out);
    EXPECT_LT(d, 0.0f);
}

TEST(PointQuery, FarPointsAreAnsweredRightOrRefused) {
    const Model model(test::icosphere(1.0f, 3)); // 2 across
    // Up to 10^4 mesh sizes away: the exact distance and the right sign, in every direction.
    std::vector<glm::dvec3> points;
    for (int i = 0; i < 200; ++i) {
        const double a = 0.7 * i, b = 0.3 * i;
        points.push_back(glm::dvec3(std::cos(a) * std::cos(b), std::sin(a) * std::cos(b), std::sin(b)) * 19990.0);
    }
    const std::vector<float> d = model.signedDistance(points);
    for (std::size_t i = 0; i < points.size(); ++i) {
        const double expected = glm::length(points[i]) - 1.0; // the sphere's facets are within 1e-2 of radius 1
        EXPECT_GT(d[i], 0.0f) << i;
        EXPECT_NEAR(d[i], expected, 0.02) << i;
    }
    // Farther: refused with the reason, never an infinity or a wrong sign.
    for (const auto& [distance, text] : {std::pair<double, const char*>{1e5, "100000"}, {1e10, "1e+10"}, {1e300, "1e+300"}}) {
        const glm::dvec3 far(distance, 0.0, 0.0); // a copy: C++17 lambdas cannot capture structured bindings
        EXPECT_CONTAINS(test::errorFrom([&] { model.signedDistance({far}); }), std::string("query point 0 (") + text + ", 0, 0) is ");
    }
    EXPECT_CONTAINS(test::errorFrom([&] { model.unsignedDistance({glm::dvec3(0.0), glm::dvec3(0.0, -1e300, 0.0)}); }),
                    "query point 1 (0, -1e+300, 0) is 5e+299 mesh sizes from the mesh's bounding box; points are answered up to "
                    "10000 mesh sizes away");
    // Within that range but beyond float's 3.4e38: an error, as for a bake, never an infinity.
    const Mesh small = test::icosphere(1.0f, 1);
    std::vector<glm::dvec3> huge = small.worldPositions();
    for (glm::dvec3& p : huge) p *= 1e36;
    const Model giant(buildMesh("giant.obj", huge, small.triangles));
    EXPECT_CONTAINS(test::errorFrom([&] { giant.unsignedDistance({glm::dvec3(1.9e40, 0.0, 0.0)}); }),
                    "giant.obj: distances overflow single precision");
    EXPECT_NEAR(giant.unsignedDistance({glm::dvec3(1e38, 0.0, 0.0)})[0], 0.99e38, 0.011e38);
}

} // namespace
} // namespace sdfgen
