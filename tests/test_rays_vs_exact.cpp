// The ray mode's error, measured against the exact field.
#include "support/reference.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>
#include <cmath>
#include <limits>

namespace sdfgen {
namespace {

using namespace test;

TEST(RaysVsExact, ErrorShrinksWithRaysAndRaysNeverUndercut) {
    const Mesh mesh = loadMesh(test::bundledBunnyPath());
    const int res = 24;
    const Field exact = bakeWith(mesh, res, DistanceMethod::Exact, SignMethod::Auto).field.dense();
    const double voxel = exact.grid.voxel;
    double previousMean = std::numeric_limits<double>::infinity();
    for (int rays : {16, 64, 256}) {
        const Field field = bakeWith(mesh, res, DistanceMethod::Rays, SignMethod::Rays, 0, rays).field.dense();
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

} // namespace
} // namespace sdfgen
