// Exact distances against the brute-force reference, on closed and on open or overlapping meshes.
#include "sdfgen/compare.hpp"
#include "core/distance/exact.hpp"
#include "support/broken_meshes.hpp"
#include "support/reference.hpp"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <algorithm>
#include <cmath>

namespace sdfgen {
namespace {

using namespace test;

TEST(ExactDistance, EqualsBruteForceOnClosedMeshes) {
    for (const Shape& shape : closedShapes()) {
        const Field& brute = bruteField(shape.name, shape.mesh, shape.res);
        const BakeResult exact = bakeWith(shape.mesh, shape.res, DistanceMethod::Exact, SignMethod::Auto);
        const Grid& g = exact.field.dense().grid;
        const double tolerance = 1e-5 * g.voxel * glm::length(glm::vec3(g.dims));
        const FieldDifference d = compareFields(exact.field.dense(), brute, 1.0);
        EXPECT_LT(d.maxAbs, tolerance) << shape.name;
        EXPECT_EQ(d.signDifferences, 0u) << shape.name;
        EXPECT_GT(d.compared, g.sampleCount() / 2) << shape.name;
        // Unsigned distances agree everywhere, the near-surface band included.
        double worst = 0;
        for (std::size_t i = 0; i < brute.values.size(); ++i) {
            worst = std::max(worst, double(std::fabs(std::fabs(exact.field.dense().values[i]) - std::fabs(brute.values[i]))));
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

} // namespace
} // namespace sdfgen
