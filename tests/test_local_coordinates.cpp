// Local coordinates: a mesh far from the origin or at an extreme scale is as exact as one of unit
// size at the origin (issue: a cube at 1e7 baked to all zeros, one scaled by 1e20 had wrong signs).
#include "core/bake/bake.hpp"
#include "core/accel/bvh.hpp"
#include "core/io/formats/format.hpp"
#include "sdfgen/field.hpp"
#include "support/checks.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>
#include <glm/common.hpp>
#include <cmath>
#include <string>

namespace sdfgen {
namespace {

// The unit-half-extent box moved by `offset` and scaled by `scale`, in double.
Mesh transformedBox(const glm::dvec3& offset, double scale) {
    const Mesh box = test::box(glm::vec3(1.0f));
    std::vector<glm::dvec3> positions = box.worldPositions();
    for (glm::dvec3& p : positions) p = offset + p * scale;
    return buildMesh("box", std::move(positions), box.triangles);
}

// Every sample against the analytic distance of the box, in voxels, and every sign farther than
// half a voxel from the surface.
void expectExactBox(const glm::dvec3& offset, double scale, SignMethod sign) {
    SCOPED_TRACE("offset " + std::to_string(offset.x) + ", scale " + std::to_string(scale));
    const Mesh mesh = transformedBox(offset, scale);
    BakeSettings settings;
    settings.res = 16;
    settings.sign = sign;
    const Field field = test::bakeMesh(mesh, settings).field;
    const Grid& g = field.grid;
    double worst = 0.0;
    std::size_t wrongSigns = 0;
    for (int k = 0; k < g.dims.z; ++k)
        for (int j = 0; j < g.dims.y; ++j)
            for (int i = 0; i < g.dims.x; ++i) {
                // The analytic distance in the box's own frame, in double.
                const glm::dvec3 p = (g.position(i, j, k) - offset) / scale;
                const glm::dvec3 q = glm::abs(p) - 1.0;
                const double outside = glm::length(glm::max(q, 0.0));
                const double truth = (outside + std::min(std::max({q.x, q.y, q.z}), 0.0)) * scale;
                const double value = field.at(i, j, k);
                worst = std::max(worst, std::fabs(value - truth) / g.voxel);
                if (std::fabs(truth) > 0.5 * g.voxel && (value < 0) != (truth < 0)) ++wrongSigns;
            }
    EXPECT_LT(worst, 1e-5);
    EXPECT_EQ(wrongSigns, 0u);
}

TEST(LocalCoordinates, FarFromTheOriginIsAsExactAsAtIt) {
    for (SignMethod sign : {SignMethod::Auto, SignMethod::Winding}) {
        expectExactBox({0, 0, 0}, 1.0, sign);
        expectExactBox({3e5, 3e5, 3e5}, 1.0, sign);
        expectExactBox({1e7, -1e7, 1e7}, 1.0, sign);
        expectExactBox({6.5e12, 0, -2e11}, 1.0, sign);
    }
}

TEST(LocalCoordinates, ExactAtExtremeScales) {
    for (SignMethod sign : {SignMethod::Auto, SignMethod::Winding}) {
        for (double scale : {1e-20, 1e-30, 1e20, 1e30}) expectExactBox({0, 0, 0}, scale, sign);
        expectExactBox({3e-18, 0, 0}, 1e-20, sign);
    }
}

TEST(LocalCoordinates, TheMeshIsCentredInAPowerOfTwoUnit) {
    const Mesh mesh = transformedBox({1e7, 2e7, -3e7}, 3.0);
    EXPECT_EQ(mesh.origin, glm::dvec3(1e7, 2e7, -3e7));
    EXPECT_EQ(mesh.unit, 4.0); // half extent 3 -> the next power of two
    EXPECT_EQ(mesh.bounds.max, glm::vec3(0.75f));
    EXPECT_TRUE(mesh.warnings.empty());
}

TEST(LocalCoordinates, FloatInputTooCoarseForTheMeshWarns) {
    // Float positions 1e7 from the origin resolve 1 unit; a mesh 10 units across is barely resolved.
    const std::vector<glm::vec3> positions = {{1e7f, 1e7f, 1e7f}, {1e7f + 8, 1e7f, 1e7f}, {1e7f, 1e7f + 8, 1e7f}};
    const Mesh mesh = buildMesh("coarse", positions, {{0, 1, 2}});
    ASSERT_EQ(mesh.warnings.size(), 1u);
    EXPECT_CONTAINS(mesh.warnings[0], "coarse");
    EXPECT_CONTAINS(mesh.warnings[0], "single-precision");
    const Mesh fine = buildMesh("fine", std::vector<glm::vec3>{{0, 0, 0}, {8, 0, 0}, {0, 8, 0}}, {{0, 1, 2}});
    EXPECT_TRUE(fine.warnings.empty());
}

class LocalCoordinatesText : public test::ScratchFolderTest {};

TEST_F(LocalCoordinatesText, TheGridIsKeptInDouble) {
    Field field;
    field.source = "far";
    field.method = "exact";
    field.grid.origin = {1e7 + 0.123456789012, -3e5 - 1e-9, 6.02214076e23};
    field.grid.voxel = 1.0 / 3.0;
    field.grid.dims = {1, 1, 1};
    field.values = {0.5f};
    const std::string path = (dir_ / "far.sdf").string();
    saveFieldText(field, path);
    const Field back = loadFieldText(path);
    EXPECT_EQ(back.grid.origin, field.grid.origin);
    EXPECT_EQ(back.grid.voxel, field.grid.voxel);
}

} // namespace
} // namespace sdfgen
