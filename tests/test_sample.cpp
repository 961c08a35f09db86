// DeepSDF-style sampling: exact counts, reproducibility whatever the thread count, distances equal
// to the model's point queries, and the noise scales and uniform box of the documented defaults.
#include "sdfgen/error.hpp"
#include "sdfgen/model.hpp"
#include "sdfgen/sample.hpp"

#include "support/checks.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numeric>

namespace sdfgen {
namespace {

using test::errorFrom;

TEST(Sample, CountsFollowTheSurfaceFraction) {
    SampleSettings settings;
    const SampleCounts c = sampleCounts(10001, settings);
    EXPECT_EQ(c.nearSurface, 4701u); // round(10001 * 47 / 50) = 9401, split 4701 + 4700
    EXPECT_EQ(c.farSurface, 4700u);
    EXPECT_EQ(c.uniform, 600u);
    settings.surfaceFraction = 0.0;
    EXPECT_EQ(sampleCounts(7, settings).uniform, 7u);
    settings.surfaceFraction = 1.0;
    EXPECT_EQ(sampleCounts(7, settings).uniform, 0u);
    EXPECT_EQ(sampleCounts(0, settings).nearSurface, 0u);
}

TEST(Sample, SameSeedSameSamplesWhateverTheThreads) {
    const Model model(test::icosphere(1.0f, 2));
    SampleSettings settings;
    settings.seed = 42;
    RunControl one, three;
    one.threads = 1;
    three.threads = 3;
    const Samples a = sampleSdf(model, 9000, settings, one);
    const Samples b = sampleSdf(model, 9000, settings, three);
    ASSERT_EQ(a.size(), 9000u);
    ASSERT_EQ(a.points.size(), 27000u);
    EXPECT_EQ(a.points, b.points);
    EXPECT_EQ(a.sdf, b.sdf);
    settings.seed = 43;
    EXPECT_NE(sampleSdf(model, 9000, settings, three).points, a.points);
    EXPECT_EQ(sampleSdf(model, 0, settings).size(), 0u);
}

TEST(Sample, DistancesAreThoseOfPointQueries) {
    const Model model(test::torus(1.0f, 0.3f, 24, 12));
    const Samples s = sampleSdf(model, 3000, {});
    std::vector<glm::dvec3> points(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) points[i] = glm::dvec3(s.points[3 * i], s.points[3 * i + 1], s.points[3 * i + 2]);
    EXPECT_EQ(model.signedDistance(points), s.sdf);
}

// On a sphere of radius 1 (radius 1.03 normalized), a surface point plus isotropic noise lies at a
// signed distance of about the noise's radial component: normal with the scale's deviation.
TEST(Sample, NoiseScalesAndUniformBoxAreDeepSdfs) {
    const Model model(test::icosphere(1.0f, 4));
    SampleSettings settings;
    const std::size_t n = 40000;
    const Samples s = sampleSdf(model, n, settings);
    const SampleCounts c = sampleCounts(n, settings);
    auto deviation = [&](std::size_t from, std::size_t to) {
        const double mean = std::accumulate(s.sdf.begin() + long(from), s.sdf.begin() + long(to), 0.0) / double(to - from);
        double squares = 0;
        for (std::size_t i = from; i < to; ++i) squares += (s.sdf[i] - mean) * (s.sdf[i] - mean);
        return std::sqrt(squares / double(to - from - 1));
    };
    EXPECT_NEAR(deviation(0, c.nearSurface) / (std::sqrt(0.0025) * 1.03), 1.0, 0.04);
    EXPECT_NEAR(deviation(c.nearSurface, c.nearSurface + c.farSurface) / (std::sqrt(0.00025) * 1.03), 1.0, 0.04);
    // Uniform points fill the bounding box padded by 0.1 of its longest side (2): [-1.2, 1.2]^3.
    glm::dvec3 lo(1e9), hi(-1e9);
    for (std::size_t i = c.nearSurface + c.farSurface; i < n; ++i) {
        const glm::dvec3 p(s.points[3 * i], s.points[3 * i + 1], s.points[3 * i + 2]);
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    for (int a = 0; a < 3; ++a) {
        EXPECT_GE(lo[a], -1.2 - 1e-6);
        EXPECT_LE(hi[a], 1.2 + 1e-6);
        EXPECT_LT(lo[a], -1.1);
        EXPECT_GT(hi[a], 1.1);
    }
}

TEST(Sample, BadSettingsAreErrors) {
    const Model model(test::icosphere(1.0f, 1));
    SampleSettings settings;
    settings.surfaceFraction = 1.5;
    EXPECT_CONTAINS(errorFrom([&] { sampleSdf(model, 10, settings); }), "surface fraction");
    settings = {};
    settings.nearVariance = -1;
    EXPECT_CONTAINS(errorFrom([&] { sampleSdf(model, 10, settings); }), "variances");
    settings = {};
    settings.padding = std::nan("");
    EXPECT_CONTAINS(errorFrom([&] { sampleSdf(model, 10, settings); }), "padding");
}

TEST(Sample, CancelStopsIt) {
    const Model model(test::icosphere(1.0f, 2));
    std::atomic<bool> cancel{true};
    RunControl control;
    control.cancel = &cancel;
    EXPECT_THROW(sampleSdf(model, 100000, {}, control), Cancelled);
}

TEST(Sample, SamplesBeyondSinglePrecisionAreErrors) {
    const Mesh sphere = test::icosphere(1.0f, 1);
    std::vector<glm::dvec3> huge = sphere.worldPositions();
    for (glm::dvec3& p : huge) p *= 1e39; // beyond float's 3.4e38
    const Model model(buildMesh("huge.obj", huge, sphere.triangles));
    EXPECT_CONTAINS(errorFrom([&] { sampleSdf(model, 100, {}); }), "huge.obj: the samples' coordinates are beyond single precision");
}

class SampleFiles : public test::ScratchFolderTest {};

TEST_F(SampleFiles, SavedOnlyUnderTheExtensionWritten) {
    const Model model(test::icosphere(1.0f, 1));
    const Samples samples = sampleSdf(model, 10, {});
    for (const char* name : {"s.vdb", "s.npy", "s", "s.npz.tmp"}) {
        const std::string path = (dir_ / name).string();
        const std::string message = errorFrom([&] { saveSamples(samples, path); });
        EXPECT_EQ(message.rfind(path + ": samples are written as .npz only", 0), 0u) << message;
        EXPECT_FALSE(std::filesystem::exists(path)) << path;
    }
    saveSamples(samples, (dir_ / "s.NPZ").string());
    EXPECT_TRUE(std::filesystem::exists(dir_ / "s.NPZ"));
}

} // namespace
} // namespace sdfgen
