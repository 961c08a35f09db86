// makeGrid: the padded box, voxel size and dims, and clear errors for impossible requests.
#include "sdfgen/error.hpp"
#include "sdfgen/grid.hpp"

#include "support/checks.hpp"
#include "core/runtime/memory.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

namespace sdfgen {
namespace {

using test::errorFrom;

WorldBounds box(glm::dvec3 min, glm::dvec3 max) {
    WorldBounds b;
    b.min = min;
    b.max = max;
    return b;
}

TEST(MakeGrid, ExactMultiples) {
    // Longest 4, padding 1 on every side: padded box 6 x 4 x 3 from (0, 1, 2), voxel 1.
    const Grid grid = makeGrid(box({1, 2, 3}, {5, 4, 4}), 6, 0.25f);
    EXPECT_EQ(grid.dims, glm::ivec3(6, 4, 3));
    EXPECT_EQ(grid.voxel, 1.0f);
    EXPECT_EQ(grid.origin, glm::dvec3(0, 1, 2));
    EXPECT_EQ(grid.sampleCount(), 72u);
    EXPECT_EQ(grid.position(0, 0, 0), glm::dvec3(0.5, 1.5, 2.5));
    EXPECT_EQ(grid.position(5, 3, 2), glm::dvec3(5.5, 4.5, 4.5));
}

TEST(MakeGrid, ShorterAxesRoundUp) {
    // Padded box 5 x 3 x 2 from -0.5, 12 voxels of 5/12 along x: 3 / (5/12) = 7.2 -> 8, 2 / (5/12) = 4.8 -> 5.
    const Grid grid = makeGrid(box({0, 0, 0}, {4, 2, 1}), 12, 0.125f);
    EXPECT_EQ(grid.dims, glm::ivec3(12, 8, 5));
    EXPECT_FLOAT_EQ(grid.voxel, 5.0f / 12.0f);
    EXPECT_EQ(grid.origin, glm::dvec3(-0.5));
}

TEST(MakeGrid, RoundingNoiseDoesNotAddAVoxel) {
    // 0.45f / (0.9f / 14) is 7.0000000000000009 in double: still 7 voxels, not 8.
    const Grid grid = makeGrid(box({0, 0, 0}, {0.9f, 0.45f, 0.45f}), 14, 0.0f);
    EXPECT_EQ(grid.dims, glm::ivec3(14, 7, 7));
    const Grid other = makeGrid(box({0, 0, 0}, {3.5f, 2.625f, 1.0f}), 20, 0.0f);
    EXPECT_EQ(other.dims, glm::ivec3(20, 15, 6));
}

TEST(MakeGrid, LongestAxisCanBeAnyAxis) {
    EXPECT_EQ(makeGrid(box({0, 0, 0}, {1, 8, 1}), 16, 0.0f).dims, glm::ivec3(2, 16, 2));
    EXPECT_EQ(makeGrid(box({0, 0, 0}, {1, 1, 8}), 16, 0.0f).dims, glm::ivec3(2, 2, 16));
    EXPECT_EQ(makeGrid(box({-1, -1, -1}, {1, 1, 1}), 7, 0.5f).dims, glm::ivec3(7, 7, 7));
}

TEST(MakeGrid, FlatBoundsGetOneVoxelAcross) {
    // A single square has no thickness; without padding its grid is one voxel deep.
    const Grid grid = makeGrid(box({0, 0, 0}, {2, 2, 0}), 4, 0.0f);
    EXPECT_EQ(grid.dims, glm::ivec3(4, 4, 1));
    EXPECT_EQ(grid.voxel, 0.5f);
    // With padding it gets 2 * padding * longest of depth.
    EXPECT_EQ(makeGrid(box({0, 0, 0}, {2, 2, 0}), 8, 0.5f).dims, glm::ivec3(8, 8, 4));
}

TEST(MakeGrid, ResolutionOne) {
    const Grid grid = makeGrid(box({0, 0, 0}, {3, 1, 2}), 1, 0.0f);
    EXPECT_EQ(grid.dims, glm::ivec3(1, 1, 1));
    EXPECT_EQ(grid.voxel, 3.0f);
}

TEST(MakeGrid, FollowsTheFormulaForRandomBounds) {
    std::mt19937 rng(99u);
    std::uniform_real_distribution<float> coord(-100.0f, 100.0f);
    std::uniform_real_distribution<float> size(0.01f, 50.0f);
    std::uniform_int_distribution<int> resolution(1, 300);
    std::uniform_real_distribution<float> padding(0.0f, 0.5f);
    for (int trial = 0; trial < 500; ++trial) {
        const glm::vec3 min(coord(rng), coord(rng), coord(rng));
        const glm::vec3 max = min + glm::vec3(size(rng), size(rng), size(rng));
        const int res = resolution(rng);
        const float pad = trial % 5 == 0 ? 0.0f : padding(rng);
        const Grid grid = makeGrid(box(min, max), res, pad);

        const glm::dvec3 extent = glm::dvec3(max) - glm::dvec3(min);
        const double longest = std::max({extent.x, extent.y, extent.z});
        const glm::dvec3 padded = extent + 2.0 * glm::dvec3(pad * longest);
        const double paddedLongest = std::max({padded.x, padded.y, padded.z});
        const double h = paddedLongest / res;
        SCOPED_TRACE("trial " + std::to_string(trial));
        EXPECT_DOUBLE_EQ(grid.voxel, h);
        for (int a = 0; a < 3; ++a) {
            EXPECT_DOUBLE_EQ(grid.origin[a], min[a] - pad * longest);
            const int expected = std::max(1, int(std::ceil(double(padded[a]) / h - 1e-9)));
            EXPECT_EQ(grid.dims[a], expected) << "axis " << a;
            EXPECT_LE(grid.dims[a], res);
            // The grid covers the padded box, and one voxel fewer would not.
            EXPECT_GE(grid.dims[a] * h, double(padded[a]) * (1 - 1e-6)) << "axis " << a;
            EXPECT_LT((grid.dims[a] - 1) * h, double(padded[a])) << "axis " << a;
        }
        const int longestAxis = padded.x >= padded.y && padded.x >= padded.z ? 0 : padded.y >= padded.z ? 1 : 2;
        EXPECT_EQ(grid.dims[longestAxis], res);
    }
}

TEST(MakeGrid, ResolutionBelowOneIsAnError) {
    for (const int res : {0, -1, std::numeric_limits<int>::min()}) {
        const std::string message = errorFrom([&] { makeGrid(box({0, 0, 0}, {1, 1, 1}), res, 0.1f); });
        EXPECT_CONTAINS(message, "resolution");
        EXPECT_CONTAINS(message, std::to_string(res));
    }
}

TEST(MakeGrid, BadPaddingIsAnError) {
    for (const float padding : {-0.1f, -std::numeric_limits<float>::denorm_min(), std::numeric_limits<float>::quiet_NaN(),
                                std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity()}) {
        const std::string message = errorFrom([&] { makeGrid(box({0, 0, 0}, {1, 1, 1}), 8, padding); });
        EXPECT_CONTAINS(message, "padding");
    }
    // -0 is zero padding.
    EXPECT_EQ(makeGrid(box({0, 0, 0}, {1, 1, 1}), 8, -0.0f).dims, glm::ivec3(8));
}

TEST(MakeGrid, ZeroExtentIsAnError) {
    const std::string message = errorFrom([] { makeGrid(box({1, 2, 3}, {1, 2, 3}), 8, 0.1f); });
    EXPECT_CONTAINS(message, "no extent");
}

TEST(MakeGrid, GridLargerThanMemoryIsAnError) {
    ASSERT_GT(physicalMemoryBytes(), 0u);
    const std::string message = errorFrom([] { makeGrid(box({0, 0, 0}, {1, 1, 1}), 65536, 0.1f); });
    EXPECT_CONTAINS(message, "65536x65536x65536");
    EXPECT_CONTAINS(message, "MiB");
    // 65536^3 floats are 2^20 GiB.
    EXPECT_CONTAINS(message, "needs 1073741824 MiB");
    // A long thin grid of the same resolution is fine.
    EXPECT_EQ(makeGrid(box({0, 0, 0}, {1, 0, 0}), 65536, 0.0f).dims, glm::ivec3(65536, 1, 1));
}

TEST(MakeGrid, HugeGridMessageStatesTheSize) {
    // 2e9^3 floats: the message must not print a wrapped-around size such as "needs 0 MiB".
    const std::string message = errorFrom([] { makeGrid(box({0, 0, 0}, {1, 1, 1}), 2000000000, 0.0f); });
    EXPECT_CONTAINS(message, "2000000000x2000000000x2000000000");
    EXPECT_EQ(message.find("needs 0 MiB"), std::string::npos) << message;
}

TEST(MakeGrid, PaddingThatOverflowsIsAnError) {
    // padding * longest is finite, but the padded box is not: the grid must not come out with
    // an infinite voxel and garbage (negative) dims.
    bool threw = false;
    try {
        const Grid grid = makeGrid(box({0, 0, 0}, {10, 10, 10}), 8, 3e37f);
        EXPECT_TRUE(std::isfinite(grid.voxel) && grid.voxel > 0.0f) << grid.voxel;
        for (int a = 0; a < 3; ++a) EXPECT_TRUE(grid.dims[a] >= 1 && grid.dims[a] <= 8) << grid.dims[a];
    } catch (const Error& e) {
        threw = true;
        EXPECT_CONTAINS(e.what(), "padding");
    }
    (void)threw;
}

TEST(MakeGrid, PhysicalMemoryIsKnown) {
    // Linux always reports it; the memory checks above rely on it.
    EXPECT_GT(physicalMemoryBytes(), std::uint64_t(1) << 26);
}

} // namespace
} // namespace sdfgen
