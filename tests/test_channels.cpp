// A bake's and samples' channels (gradient, closest point, nearest triangle) against brute force
// in double, the distance they leave untouched, their determinism, and their files.
#include "core/bake/bake.hpp"
#include "core/mesh/geometry.hpp"
#include "core/distance/kernel.hpp"
#include "core/bake/memory_estimate.hpp"
#include "core/runtime/memory.hpp"
#include "core/mesh/sample_positions.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/formats.hpp"
#include "sdfgen/model.hpp"
#include "sdfgen/sample.hpp"
#include "support/checks.hpp"
#include "support/shapes.hpp"
#include "support/stand_in_device.hpp"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#if SDFGEN_HAS_OPENVDB
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#endif
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>

namespace sdfgen {
namespace {

Channels allChannels() { return Channels::all(); }

// A channel's values, empty when absent.
template <class Holder>
const std::vector<float>& floats(const Holder& holder, const char* name) {
    static const std::vector<float> none;
    const ChannelValues* channel = holder.channel(name);
    return channel ? channel->floats : none;
}
template <class Holder>
const std::vector<std::int32_t>& ints(const Holder& holder, const char* name) {
    static const std::vector<std::int32_t> none;
    const ChannelValues* channel = holder.channel(name);
    return channel ? channel->ints : none;
}

BakeResult bakeChannels(const Mesh& mesh, int res, SignMethod sign, const Channels& channels, int threads = 0) {
    BakeSettings settings;
    settings.res = res;
    settings.sign = sign;
    settings.device = "cpu";
    settings.channels = channels;
    RunControl control;
    control.threads = threads;
    return bake(mesh, Bvh(mesh), settings, control);
}

// An open surface: random triangles in the unit cube (holes everywhere, so auto signs by winding).
Mesh randomSoup(int count, unsigned seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
    std::vector<glm::dvec3> positions;
    std::vector<glm::uvec3> triangles;
    for (int t = 0; t < count; ++t) {
        for (int c = 0; c < 3; ++c) positions.emplace_back(coordinate(random), coordinate(random), coordinate(random));
        triangles.emplace_back(3 * t, 3 * t + 1, 3 * t + 2);
    }
    return buildMesh("soup", positions, triangles);
}

double distanceSquaredTo(const Mesh& mesh, const glm::dvec3& p, std::size_t t) {
    return closestPointOnTriangle(p, glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2)))
        .distanceSquared;
}

// Checks every sample's channels against every triangle, in double.
void expectMatchesBruteForce(const Mesh& mesh, const Field& field) {
    const Grid& grid = field.grid;
    const std::size_t n = grid.sampleCount();
    ASSERT_EQ(floats(field, "gradient").size(), 3 * n);
    ASSERT_EQ(floats(field, "closest").size(), 3 * n);
    ASSERT_EQ(ints(field, "triangle").size(), n);
    int failures = 0;
    for (int k = 0; k < grid.dims.z; ++k) {
        for (int j = 0; j < grid.dims.y; ++j) {
            for (int i = 0; i < grid.dims.x && failures < 10; ++i) {
                const std::size_t index = grid.index(i, j, k);
                const glm::dvec3 p = localPosition(mesh, grid, i, j, k);
                double nearest = std::numeric_limits<double>::infinity();
                for (std::size_t t = 0; t < mesh.triangleCount(); ++t) nearest = std::min(nearest, distanceSquaredTo(mesh, p, t));
                // The triangle: the nearest, or one tied with it to the float search's rounding.
                const std::int32_t t = ints(field, "triangle")[index];
                ASSERT_GE(t, 0);
                ASSERT_LT(std::size_t(t), mesh.triangleCount());
                const double found = std::sqrt(distanceSquaredTo(mesh, p, std::size_t(t))), best = std::sqrt(nearest);
                if (!(found <= best * (1.0 + 1e-5) + 1e-7)) {
                    ADD_FAILURE() << "sample " << index << ": triangle " << t << " at " << found << ", the nearest at " << best;
                    ++failures;
                }
                // The distance is the triangle's, measured in double.
                EXPECT_EQ(std::fabs(field.values[index]), float(found * mesh.unit)) << "sample " << index;
                // The closest point: on that triangle, in world coordinates.
                const ClosestPoint c = closestPointOnTriangle(p, glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)),
                                                              glm::dvec3(mesh.vertex(t, 2)));
                const glm::dvec3 world = mesh.toWorld(c.point);
                for (std::size_t a = 0; a < 3; ++a) {
                    const float stored = floats(field, "closest")[a * n + index];
                    if (!(std::fabs(double(stored) - world[int(a)]) <= 1e-6 * (std::fabs(world[int(a)]) + mesh.unit))) {
                        ADD_FAILURE() << "sample " << index << ": closest " << stored << " vs " << world[int(a)];
                        ++failures;
                    }
                }
                // The gradient: sign * (p - c) / |p - c|, the outward face normal where the distance is 0.
                glm::dvec3 expected = glm::dvec3(mesh.faceNormals[std::size_t(t)]);
                if (field.values[index] != 0.0f) expected = (p - c.point) / std::sqrt(c.distanceSquared) * (field.values[index] < 0 ? -1.0 : 1.0);
                const glm::dvec3 g(floats(field, "gradient")[index], floats(field, "gradient")[n + index], floats(field, "gradient")[2 * n + index]);
                if (!(glm::length(g - expected) <= 1e-6)) {
                    ADD_FAILURE() << "sample " << index << ": gradient (" << g.x << ", " << g.y << ", " << g.z << ") vs (" << expected.x
                                  << ", " << expected.y << ", " << expected.z << ")";
                    ++failures;
                }
            }
        }
    }
}

struct Case {
    const char* name;
    Mesh mesh;
    int res;
};

std::vector<Case> cases() {
    std::vector<Case> list;
    list.push_back({"box", test::box({1.0f, 0.5f, 0.75f}), 14});
    list.push_back({"torus", test::torus(1.0f, 0.3f, 16, 8), 16});
    list.push_back({"icosphere far from the origin", test::icosphere(1.0f, 1), 12});
    // Far from the world origin and at another scale: world = origin + local * unit.
    std::vector<glm::dvec3> moved = list.back().mesh.worldPositions();
    for (glm::dvec3& v : moved) v = v * 1000.0 + glm::dvec3(5e5, -2e5, 1e4);
    list.back().mesh = buildMesh("moved icosphere", moved, list.back().mesh.triangles);
    list.push_back({"random soup", randomSoup(30, 7), 14});
    return list;
}

TEST(Channels, EqualBruteForceInDouble) {
    for (const Case& c : cases()) {
        for (SignMethod sign : {SignMethod::Auto, SignMethod::Winding, SignMethod::Pseudonormal}) {
            SCOPED_TRACE(std::string(c.name) + ", sign " + toString(sign));
            const BakeResult result = bakeChannels(c.mesh, c.res, sign, allChannels());
            expectMatchesBruteForce(c.mesh, result.field.dense());
        }
    }
}

TEST(Channels, LeaveTheDistancesBitIdentical) {
    for (const Case& c : cases()) {
        for (SignMethod sign : {SignMethod::Auto, SignMethod::Winding, SignMethod::Pseudonormal, SignMethod::Rays}) {
            SCOPED_TRACE(std::string(c.name) + ", sign " + toString(sign));
            const Field plain = bakeChannels(c.mesh, c.res, sign, Channels{}).field.dense();
            EXPECT_TRUE(floats(plain, "gradient").empty() && floats(plain, "closest").empty() && ints(plain, "triangle").empty());
            Channels one;
            one.add("triangle");
            for (const Channels& channels : {allChannels(), one}) {
                const Field with = bakeChannels(c.mesh, c.res, sign, channels).field.dense();
                ASSERT_EQ(with.values.size(), plain.values.size());
                EXPECT_EQ(std::memcmp(with.values.data(), plain.values.data(), plain.values.size() * sizeof(float)), 0);
                EXPECT_EQ(channelsOf(with.channels), channels);
            }
        }
    }
}

TEST(Channels, BitIdenticalForAnyThreadCountAndSimdPath) {
    const Mesh mesh = loadMesh(test::bundledBunnyPath());
    const Field one = bakeChannels(mesh, 24, SignMethod::Auto, allChannels(), 1).field.dense();
    auto expectSame = [&](const Field& other, const std::string& what) {
        EXPECT_EQ(other.values, one.values) << what;
        EXPECT_EQ(std::memcmp(floats(other, "gradient").data(), floats(one, "gradient").data(), floats(one, "gradient").size() * sizeof(float)), 0) << what;
        EXPECT_EQ(std::memcmp(floats(other, "closest").data(), floats(one, "closest").data(), floats(one, "closest").size() * sizeof(float)), 0) << what;
        EXPECT_EQ(ints(other, "triangle"), ints(one, "triangle")) << what;
    };
    expectSame(bakeChannels(mesh, 24, SignMethod::Auto, allChannels(), 3).field.dense(), "3 threads");
    const SimdPath chosen = simdPath();
    for (SimdPath path : kSimdPaths) {
        if (!simdPathAvailable(path)) continue;
        setSimdPath(path);
        expectSame(bakeChannels(mesh, 24, SignMethod::Auto, allChannels(), 2).field.dense(), toString(path));
    }
    setSimdPath(chosen);
}

TEST(Channels, PointQueriesGiveTheBakedGradientAtSamplePositions) {
    const Model model(test::torus(1.0f, 0.3f, 16, 8));
    BakeSettings settings;
    settings.res = 12;
    settings.device = "cpu";
    settings.channels = allChannels();
    const Field field = model.bake(settings).field.dense();
    const Grid& grid = field.grid;
    const std::size_t n = grid.sampleCount();
    const std::vector<double> points = test::samplePositions(grid);
    std::vector<double> gradient(3 * n), closest(3 * n);
    std::vector<std::int64_t> triangle(n);
    PointQueryOutputs out;
    out.gradient = gradient.data();
    out.closestPoint = closest.data();
    out.triangle = triangle.data();
    model.query(points.data(), n, out);
    for (std::size_t i = 0; i < n; ++i) {
        ASSERT_EQ(triangle[i], ints(field, "triangle")[i]) << i;
        for (std::size_t a = 0; a < 3; ++a) {
            ASSERT_EQ(float(gradient[3 * i + a]), floats(field, "gradient")[a * n + i]) << i;
            ASSERT_EQ(float(closest[3 * i + a]), floats(field, "closest")[a * n + i]) << i;
        }
    }
}

TEST(Channels, GradientOnTheSurfaceIsTheOutwardFaceNormal) {
    const Model model(test::box({1.0f, 1.0f, 1.0f}));
    const std::vector<double> points = {1.0, 0.25, -0.5, 0.1, -1.0, 0.3};
    std::vector<double> gradient(6);
    std::vector<float> distance(2);
    PointQueryOutputs out;
    out.gradient = gradient.data();
    out.signedDistance = distance.data();
    model.query(points.data(), 2, out);
    EXPECT_EQ(distance[0], 0.0f);
    EXPECT_EQ(std::vector<double>(gradient.begin(), gradient.begin() + 3), std::vector<double>({1.0, 0.0, 0.0}));
    EXPECT_EQ(std::vector<double>(gradient.begin() + 3, gradient.end()), std::vector<double>({0.0, -1.0, 0.0}));
}

TEST(Channels, SamplesCarryThemFromTheSameQuery) {
    const Model model(randomSoup(20, 3));
    SampleSettings settings;
    settings.seed = 5;
    const Samples plain = sampleSdf(model, 2000, settings);
    settings.channels = allChannels();
    RunControl one;
    one.threads = 1;
    const Samples with = sampleSdf(model, 2000, settings, one);
    EXPECT_EQ(with.sdf, plain.sdf);
    EXPECT_EQ(with.points, plain.points);
    ASSERT_EQ(floats(with, "gradient").size(), 3 * with.size());
    ASSERT_EQ(floats(with, "closest").size(), 3 * with.size());
    ASSERT_EQ(ints(with, "triangle").size(), with.size());
    const Mesh& mesh = model.mesh();
    for (std::size_t i = 0; i < with.size(); ++i) {
        const glm::dvec3 p = mesh.toLocal(glm::dvec3(with.points[3 * i], with.points[3 * i + 1], with.points[3 * i + 2]));
        double nearest = std::numeric_limits<double>::infinity();
        for (std::size_t t = 0; t < mesh.triangleCount(); ++t) nearest = std::min(nearest, distanceSquaredTo(mesh, p, t));
        const std::size_t t = std::size_t(ints(with, "triangle")[i]);
        ASSERT_LE(std::sqrt(distanceSquaredTo(mesh, p, t)), std::sqrt(nearest) * (1.0 + 1e-5) + 1e-7) << i;
        const ClosestPoint c = closestPointOnTriangle(p, glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2)));
        const glm::dvec3 expected = (p - c.point) / std::sqrt(c.distanceSquared) * (with.sdf[i] < 0 ? -1.0 : 1.0);
        const glm::dvec3 g(floats(with, "gradient")[3 * i], floats(with, "gradient")[3 * i + 1], floats(with, "gradient")[3 * i + 2]);
        ASSERT_LE(glm::length(g - expected), 1e-6) << i;
        for (int a = 0; a < 3; ++a) ASSERT_NEAR(floats(with, "closest")[3 * i + std::size_t(a)], mesh.toWorld(c.point)[a], 1e-6) << i;
    }
    RunControl three;
    three.threads = 3;
    const Samples again = sampleSdf(model, 2000, settings, three);
    EXPECT_EQ(floats(again, "gradient"), floats(with, "gradient"));
    EXPECT_EQ(floats(again, "closest"), floats(with, "closest"));
    EXPECT_EQ(ints(again, "triangle"), ints(with, "triangle"));
}

TEST(Channels, ParseAndName) {
    EXPECT_FALSE(parseChannels("sdf").any());
    EXPECT_FALSE(parseChannels("").any());
    const Channels c = parseChannels("triangle,sdf,gradient");
    EXPECT_TRUE(c.has("gradient") && c.has("triangle") && !c.has("closest"));
    EXPECT_EQ(toString(c), "sdf,gradient,triangle");
    EXPECT_EQ(toString(parseChannels("closest")), "sdf,closest");
    EXPECT_THROW(parseChannels("sdf,normals"), Error);
    EXPECT_THROW(parseChannels("sdf,"), Error);
}

TEST(Channels, RefusedWhereTheyCannotBeMade) {
    const Mesh mesh = test::icosphere(1.0f, 1);
    const Bvh tree(mesh);
    BakeSettings settings;
    settings.res = 8;
    settings.channels.add("gradient");
    for (DistanceMethod method : {DistanceMethod::Rays, DistanceMethod::Brute}) {
        settings.method = method;
        try {
            bake(mesh, tree, settings, {});
            ADD_FAILURE() << toString(method) << " made channels";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("exact"), std::string::npos) << e.what();
        }
    }
    settings.method = DistanceMethod::Exact;
    const test::ScopedDevice device(test::standInDevice("stand-in", true));
    settings.device = "stand-in";
    EXPECT_CONTAINS(test::errorFrom([&] { bake(mesh, tree, settings, {}); }), "are made on the CPU only");
    settings.device = "auto";
    const BakeResult result = bake(mesh, tree, settings, {});
    EXPECT_FALSE(result.onDevice);
    // Formats that hold the distance only refuse a field with channels, naming the alternative.
    const std::string folder = testing::TempDir();
    for (const char* extension : {".sdf", ".npy", ".nrrd"}) {
        const std::string path = folder + "/channels" + extension;
        try {
            saveField(result.field.dense(), path);
            ADD_FAILURE() << extension << " took the channels";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(".npz or .vdb"), std::string::npos) << e.what();
        }
        EXPECT_FALSE(std::filesystem::exists(path));
        EXPECT_THROW(checkFormatHoldsChannels(path, settings.channels), Error);
        EXPECT_NO_THROW(checkFormatHoldsChannels(path, Channels{}));
    }
    EXPECT_NO_THROW(checkFormatHoldsChannels(folder + "/f.npz", settings.channels));
    EXPECT_NO_THROW(checkFormatHoldsChannels(folder + "/f.vdb", settings.channels));
}

TEST(Channels, CountedByTheMemoryEstimate) {
    const Mesh mesh = test::icosphere(1.0f, 2);
    const Grid grid = makeGrid(mesh.worldBounds(), 40, 0.1);
    BakeSettings settings;
    settings.sign = SignMethod::Pseudonormal;
    const double plain = double(estimateBakeBytes(mesh, grid, settings));
    settings.channels = allChannels();
    double bytes = 0;
    for (const ChannelInfo& info : channelInfos()) bytes += 4.0 * info.width;
    EXPECT_EQ(double(estimateBakeBytes(mesh, grid, settings)) - plain, double(grid.sampleCount()) * bytes);
}

// Each channel of the registry alone: baked (its width and type, the distances untouched), named,
// sampled from the same query, and saved under its name in .npz and .vdb.
TEST(Channels, EveryRegisteredOneIsBakedSampledAndSaved) {
    const Model model(test::torus(1.0f, 0.3f, 16, 8));
    BakeSettings settings;
    settings.res = 10;
    settings.device = "cpu";
    const Field plain = model.bake(settings).field.dense();
    const std::size_t n = plain.grid.sampleCount();
    for (const ChannelInfo& info : channelInfos()) {
        SCOPED_TRACE(info.name);
        settings.channels = parseChannels(std::string("sdf,") + info.name);
        EXPECT_EQ(toString(settings.channels), std::string("sdf,") + info.name);
        const Field field = model.bake(settings).field.dense();
        EXPECT_EQ(field.values, plain.values);
        ASSERT_EQ(field.channels.size(), 1u);
        const ChannelValues& channel = field.channels[0];
        EXPECT_EQ(channel.name, info.name);
        EXPECT_EQ(channel.size(), std::size_t(info.width) * n);
        EXPECT_EQ(channel.ints.empty(), info.type == ChannelType::Float32);

        SampleSettings sampling;
        sampling.channels = settings.channels;
        const Samples samples = sampleSdf(model, 300, sampling);
        ASSERT_NE(samples.channel(info.name), nullptr);
        EXPECT_EQ(samples.channel(info.name)->size(), std::size_t(info.width) * 300);

        const std::string npz = testing::TempDir() + "/one-channel.npz";
        saveField(field, npz);
        std::ifstream in(npz, std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        EXPECT_NE(bytes.find(std::string(info.name) + ".npy"), std::string::npos); // stored members: names in the clear
#if SDFGEN_HAS_OPENVDB
        const std::string vdb = testing::TempDir() + "/one-channel.vdb";
        saveField(field, vdb);
        openvdb::initialize();
        openvdb::io::File file(vdb);
        file.open(false);
        EXPECT_TRUE(file.hasGrid(info.name));
        file.close();
#endif
    }
}

#if SDFGEN_HAS_OPENVDB
// The channel grids of a .vdb: the surface grid's active voxels, each with its sample's channel.
TEST(Channels, VdbGridsHoldThem) {
    const Mesh mesh = test::torus(1.0f, 0.3f, 16, 8);
    const Field field = bakeChannels(mesh, 14, SignMethod::Auto, allChannels()).field.dense();
    const std::size_t n = field.grid.sampleCount();
    for (double band : {0.0, 2.0}) {
        SCOPED_TRACE("band " + std::to_string(band));
        const std::string path = testing::TempDir() + "/channels.vdb";
        SaveOptions options;
        options.band = band;
        saveField(field, path, options);
        EXPECT_EQ(loadField(path).values.size(), n); // the surface grid still reads as the field
        openvdb::initialize();
        openvdb::io::File file(path);
        file.open(false);
        const auto surface = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("surface"));
        const auto gradient = openvdb::gridPtrCast<openvdb::Vec3SGrid>(file.readGrid("gradient"));
        const auto closest = openvdb::gridPtrCast<openvdb::Vec3SGrid>(file.readGrid("closest"));
        const auto triangle = openvdb::gridPtrCast<openvdb::Int32Grid>(file.readGrid("triangle"));
        file.close();
        ASSERT_TRUE(surface && gradient && closest && triangle);
        EXPECT_EQ(gradient->getVectorType(), openvdb::VEC_COVARIANT_NORMALIZE);
        EXPECT_EQ(closest->getVectorType(), openvdb::VEC_CONTRAVARIANT_ABSOLUTE);
        EXPECT_EQ(gradient->activeVoxelCount(), surface->activeVoxelCount());
        EXPECT_EQ(triangle->activeVoxelCount(), surface->activeVoxelCount());
        EXPECT_EQ(triangle->transform(), surface->transform());
        if (band == 0) EXPECT_EQ(surface->activeVoxelCount(), openvdb::Index64(n));
        else EXPECT_LT(surface->activeVoxelCount(), openvdb::Index64(n));
        std::size_t checked = 0;
        for (auto voxel = surface->cbeginValueOn(); voxel; ++voxel) {
            const openvdb::Coord c = voxel.getCoord();
            const std::size_t i = field.grid.index(c.x(), c.y(), c.z());
            const openvdb::Vec3s g = gradient->tree().getValue(c), p = closest->tree().getValue(c);
            ASSERT_TRUE(gradient->tree().isValueOn(c));
            for (int a = 0; a < 3; ++a) {
                ASSERT_EQ(g[a], floats(field, "gradient")[std::size_t(a) * n + i]);
                ASSERT_EQ(p[a], floats(field, "closest")[std::size_t(a) * n + i]);
            }
            ASSERT_EQ(triangle->tree().getValue(c), ints(field, "triangle")[i]);
            ++checked;
        }
        EXPECT_EQ(checked, std::size_t(surface->activeVoxelCount()));
    }
}
#endif

} // namespace
} // namespace sdfgen
