// Local coordinates: a mesh far from the origin or at an extreme scale is as exact as one of unit
// size at the origin (issue: a cube at 1e7 baked to all zeros, one scaled by 1e20 had wrong signs).
#include "core/bake/bake.hpp"
#include "core/accel/bvh.hpp"
#include "core/io/formats/format.hpp"
#include "sdfgen/field.hpp"
#include "sdfgen/sparse_field.hpp"
#include "support/checks.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

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
    const Field field = test::bakeMesh(mesh, settings).field.dense();
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

// The distance from p to the triangle soup, all in double: the projection onto a triangle's plane
// where it falls inside the triangle, the nearest edge otherwise.
double bruteDistance(const glm::dvec3& p, const std::vector<glm::dvec3>& corners) {
    auto toSegment = [&](const glm::dvec3& a, const glm::dvec3& b) {
        const glm::dvec3 e = b - a;
        const double t = std::clamp(glm::dot(p - a, e) / glm::dot(e, e), 0.0, 1.0);
        return glm::length(p - (a + t * e));
    };
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t c = 0; c < corners.size(); c += 3) {
        const glm::dvec3 &a = corners[c], &b = corners[c + 1], &d = corners[c + 2];
        const glm::dvec3 n = glm::cross(b - a, d - a);
        const double s = glm::dot(p - a, n) / glm::dot(n, n);
        const glm::dvec3 q = p - s * n;
        const bool inside = glm::dot(glm::cross(b - a, q - a), n) >= 0 && glm::dot(glm::cross(d - b, q - b), n) >= 0 &&
                            glm::dot(glm::cross(a - d, q - d), n) >= 0;
        nearest = std::min(nearest, inside ? std::fabs(s) * glm::length(n) : std::min({toSegment(a, b), toSegment(b, d), toSegment(d, a)}));
    }
    return nearest;
}

// A lumpy closed sphere (an icosphere with its vertices moved radially by up to 10%) of diameter
// `size` centred at `centre`, its vertices rounded to float in world coordinates, as a scan's file
// holds them.
Mesh floatLumpySphere(const glm::dvec3& centre, double size) {
    const Mesh sphere = test::icosphere(0.5f, 3);
    std::mt19937 random(7);
    std::uniform_real_distribution<double> bump(0.9, 1.1);
    std::vector<glm::vec3> positions;
    for (const glm::dvec3& p : sphere.worldPositions()) positions.emplace_back(centre + p * bump(random) * size);
    return buildMesh("lumpy", positions, sphere.triangles);
}

using Samples = std::vector<std::pair<glm::ivec3, float>>; // (i, j, k) and the value there

// The samples within 2 voxels of the surface: of a dense field, and of 500 of a band field's bricks.
Samples nearSurface(const Field& field) {
    Samples near;
    const Grid& g = field.grid;
    for (int k = 0; k < g.dims.z; ++k)
        for (int j = 0; j < g.dims.y; ++j)
            for (int i = 0; i < g.dims.x; ++i) {
                if (std::fabs(field.at(i, j, k)) < 2.0 * g.voxel) near.emplace_back(glm::ivec3(i, j, k), field.at(i, j, k));
            }
    return near;
}
Samples nearSurface(const SparseField& field) {
    Samples near;
    constexpr int B = SparseField::kBrick;
    for (std::size_t b = 0; b < field.bricks().size(); b += std::max<std::size_t>(1, field.bricks().size() / 500))
        for (int z = 0; z < B; ++z)
            for (int y = 0; y < B; ++y)
                for (int x = 0; x < B; ++x) {
                    const glm::ivec3 s = field.bricks()[b] * B + glm::ivec3(x, y, z);
                    const float v = field.values()[b * SparseField::kBrickSamples + std::size_t((z * B + y) * B + x)];
                    if (glm::all(glm::lessThan(s, field.grid().dims)) && std::fabs(v) < 2.0 * field.grid().voxel) near.emplace_back(s, v);
                }
    return near;
}

// The largest difference, in voxels, between the distances of about 3000 of the samples (spread
// over the list) and the brute force in double over the mesh's vertices in world coordinates.
double worstAgainstBruteForce(const Mesh& mesh, const Grid& g, const Samples& near) {
    std::vector<glm::dvec3> corners;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        for (int c = 0; c < 3; ++c) corners.push_back(mesh.toWorld(glm::dvec3(mesh.vertex(t, c))));
    }
    EXPECT_GT(near.size(), 3000u);
    double worst = 0.0;
    for (std::size_t n = 0; n < near.size(); n += std::max<std::size_t>(1, near.size() / 3000)) {
        const auto& [s, value] = near[n];
        worst = std::max(worst, std::fabs(std::fabs(double(value)) - bruteDistance(g.position(s.x, s.y, s.z), corners)) / g.voxel);
    }
    return worst;
}

// A float mesh of size 1 at 40 (a scan's coordinates) and of size 250 at 1e4, baked as a band at
// res 1024 and dense at res 160: every sampled distance near the surface within 1e-4 voxel of the brute force
// in double over the same float vertices.
TEST(LocalCoordinates, FloatMeshFarFromTheOriginIsExactAtHighResolution) {
    for (const auto& [centre, size] : {std::pair{glm::dvec3(40.3, 39.7, -40.1), 1.0}, std::pair{glm::dvec3(1e4, -1e4, 1e4), 250.0}}) {
        SCOPED_TRACE("at " + std::to_string(centre.x) + ", size " + std::to_string(size));
        const Mesh mesh = floatLumpySphere(centre, size);
        BakeSettings settings;
        settings.res = 1024;
        settings.padding = 0.5; // the mesh across 512 voxels: a quarter of the bricks of padding 0.1
        settings.band = 3;
        const SparseField band = test::bakeMesh(mesh, settings).field.band();
        EXPECT_LT(worstAgainstBruteForce(mesh, band.grid(), nearSurface(band)), 1e-4);
        settings.res = 160;
        settings.band = 0;
        const Field dense = test::bakeMesh(mesh, settings).field.dense();
        EXPECT_LT(worstAgainstBruteForce(mesh, dense.grid, nearSurface(dense)), 1e-4);
    }
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
