// The winding sign's inside rule, |w| > 1/2 (w the generalized winding number), on the meshes it
// is for: a closed part modelled inside out beside one that is not (both solid), a hollow part
// whose inner shell faces into its cavity (hollow), meshes inside out as a whole (solid, no flip,
// and the mesh check still says so), and copies facing opposite ways (where they overlap the two
// cancel: w = 0, outside). Every bake is compared sample by sample with the winding number summed
// here triangle by triangle in double, and point queries with the baked grid.
#include "core/mesh/sample_positions.hpp"
#include "sdfgen/model.hpp"
#include "support/checks.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <cmath>
#include <string>
#include <vector>

namespace sdfgen {
namespace {

Mesh reversed(const Mesh& mesh) {
    std::vector<glm::uvec3> triangles = mesh.triangles;
    for (glm::uvec3& t : triangles) std::swap(t.y, t.z);
    return buildMesh(mesh.source, mesh.worldPositions(), std::move(triangles));
}

Mesh moved(const Mesh& mesh, const glm::dvec3& offset) {
    std::vector<glm::dvec3> positions = mesh.worldPositions();
    for (glm::dvec3& p : positions) p += offset;
    return buildMesh(mesh.source, std::move(positions), mesh.triangles);
}

Mesh combined(const std::string& name, const std::vector<Mesh>& parts) {
    std::vector<glm::dvec3> positions;
    std::vector<glm::uvec3> triangles;
    for (const Mesh& part : parts) {
        const unsigned base = unsigned(positions.size());
        const std::vector<glm::dvec3> more = part.worldPositions();
        positions.insert(positions.end(), more.begin(), more.end());
        for (const glm::uvec3& t : part.triangles) triangles.push_back(t + base);
    }
    return buildMesh(name, std::move(positions), std::move(triangles));
}

// `mesh` without the triangles whose centroid lies above y = cut: a hole.
Mesh cutOpen(const Mesh& mesh, float cut) {
    std::vector<glm::uvec3> kept;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        if (mesh.vertex(t, 0).y + mesh.vertex(t, 1).y + mesh.vertex(t, 2).y <= 3.0f * cut) kept.push_back(mesh.triangles[t]);
    }
    return buildMesh(mesh.source, mesh.worldPositions(), std::move(kept));
}

// The winding number at p (local coordinates): every triangle's solid angle (Van Oosterom and
// Strackee) summed in double, over 4π.
double referenceWinding(const Mesh& mesh, const glm::dvec3& p) {
    double sum = 0.0;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const glm::dvec3 a = glm::dvec3(mesh.vertex(t, 0)) - p, b = glm::dvec3(mesh.vertex(t, 1)) - p, c = glm::dvec3(mesh.vertex(t, 2)) - p;
        const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
        const double det = glm::dot(a, glm::cross(b, c));
        const double den = la * lb * lc + glm::dot(a, b) * lc + glm::dot(b, c) * la + glm::dot(c, a) * lb;
        sum += 2.0 * std::atan2(det, den);
    }
    return sum / (4.0 * M_PI);
}

struct Case {
    std::string name;
    Mesh mesh;
    std::vector<glm::dvec3> inside, outside; // world points whose side is known
    SignMethod autoSign;                    // what auto picks
    bool insideOut;                         // what the mesh check reports
    std::size_t misorientedShells;          // likewise
};

std::vector<Case> cases() {
    const Mesh sphere = test::icosphere(1.0f, 2), small = test::icosphere(0.6f, 2), hollowed = test::icosphere(0.5f, 2);
    const Mesh hollow = combined("hollow sphere (inner shell reversed)", {sphere, reversed(hollowed)});
    return {
        {"sphere beside a smaller sphere inside out", combined("beside", {moved(sphere, {-1.2, 0, 0}), reversed(moved(small, {1.0, 0, 0}))}),
         {{-1.2, 0, 0}, {-0.5, 0.3, 0}, {1.0, 0, 0}, {1.3, 0, 0.2}}, {{0.1, 0, 0}, {0, 1.5, 0}, {1.0, 0.9, 0}},
         SignMethod::Winding, false, 1},
        {"hollow sphere (inner shell reversed)", hollow, {{0.75, 0, 0}, {0, -0.8, 0}}, {{0, 0, 0}, {0.2, 0.1, 0}, {1.3, 0, 0}},
         SignMethod::Pseudonormal, false, 0},
        {"hollow sphere inside out as a whole", reversed(hollow), {{0.75, 0, 0}, {0, -0.8, 0}}, {{0, 0, 0}, {0.2, 0.1, 0}, {1.3, 0, 0}},
         SignMethod::Pseudonormal, true, 0},
        {"sphere inside out", reversed(sphere), {{0, 0, 0}, {0.5, 0.5, 0}}, {{1.2, 0, 0}}, SignMethod::Pseudonormal, true, 0},
        // Both facing out, one within the other: w = 2 in the inner one, solid like the rest.
        {"sphere within a sphere, both facing out", combined("nested", {sphere, hollowed}), {{0, 0, 0}, {0.75, 0, 0}}, {{1.2, 0, 0}},
         SignMethod::Winding, false, 1},
        {"sphere inside out with a hole", reversed(cutOpen(sphere, 0.9f)), {{0, 0, 0}, {0, -0.6, 0}}, {{1.2, 0, 0}, {0, 1.4, 0}},
         SignMethod::Winding, false, 0},
        // The same sphere twice, facing opposite ways: w = 0 everywhere, nothing inside.
        {"sphere and its reversed copy", combined("opposite copies", {sphere, reversed(sphere)}), {}, {{0, 0, 0}, {0.5, 0, 0}, {1.2, 0, 0}},
         SignMethod::Winding, false, 0},
        // Overlapping: w = 1 in the first alone, -1 in the second alone, 0 where they overlap.
        {"sphere overlapped by a smaller one inside out", combined("opposite overlapping", {sphere, reversed(moved(small, {0.8, 0, 0}))}),
         {{-0.5, 0, 0}, {1.25, 0, 0}}, {{0.6, 0, 0}, {0.6, 0.5, 0}, {2.0, 0, 0}}, SignMethod::Winding, false, 0},
    };
}

// The reference winding number at every sample of `grid`.
std::vector<double> referenceWindings(const Mesh& mesh, const Grid& grid) {
    std::vector<double> w(grid.sampleCount());
    for (int k = 0; k < grid.dims.z; ++k)
        for (int j = 0; j < grid.dims.y; ++j)
            for (int i = 0; i < grid.dims.x; ++i) w[grid.index(i, j, k)] = referenceWinding(mesh, localPosition(mesh, grid, i, j, k));
    return w;
}

// Signs against |w| > 1/2 of the reference winding numbers at every sample not a rounding error
// from |w| = 1/2; returns the samples inside.
std::size_t expectReferenceSigns(const Case& c, const Field& field, const std::vector<double>& reference) {
    std::size_t inside = 0, ties = 0;
    for (std::size_t n = 0; n < reference.size(); ++n) {
        const double w = reference[n];
        if (std::fabs(std::fabs(w) - 0.5) < 1e-9) {
            ++ties;
            continue;
        }
        const bool negative = std::signbit(field.values[n]);
        EXPECT_EQ(negative, std::fabs(w) > 0.5) << c.name << " at sample " << n << ": w = " << w;
        if (negative != (std::fabs(w) > 0.5)) return inside;
        inside += negative;
    }
    EXPECT_LT(ties, reference.size() / 1000 + 1) << c.name;
    return inside;
}

TEST(InsideRule, BakesEqualTheReferenceWindingNumber) {
    for (const Case& c : cases()) {
        SCOPED_TRACE(c.name);
        const Model model(c.mesh);
        EXPECT_EQ(model.check().insideOut, c.insideOut);
        if (c.insideOut) {
            EXPECT_CONTAINS(model.check().describe(), "inside out");
        }
        EXPECT_EQ(model.check().misorientedShells, c.misorientedShells);
        if (c.misorientedShells) {
            EXPECT_CONTAINS(model.check().describe(), "closed shells facing against their nesting");
        }
        std::vector<double> reference;
        for (SignMethod sign : {SignMethod::Winding, SignMethod::Auto}) {
            SCOPED_TRACE(toString(sign));
            BakeSettings settings;
            settings.res = 20;
            settings.sign = sign;
            const BakeResult result = model.bake(settings);
            EXPECT_EQ(result.sign, sign == SignMethod::Auto ? c.autoSign : sign);
            EXPECT_EQ(result.warnings.size(), 0u);
            if (reference.empty()) reference = referenceWindings(c.mesh, result.field.dense().grid);
            const std::size_t inside = expectReferenceSigns(c, result.field.dense(), reference);
            EXPECT_EQ(inside > 0, !c.inside.empty());
            if (sign == SignMethod::Auto) {
                EXPECT_EQ(result.check.insideOut, c.insideOut);
            }
        }
    }
}

// The queries at the grid's samples give the baked field, bit for bit; at the known points, the
// known sides.
TEST(InsideRule, PointQueriesEqualTheGrid) {
    for (const Case& c : cases()) {
        SCOPED_TRACE(c.name);
        const Model model(c.mesh);
        for (SignMethod sign : {SignMethod::Winding, SignMethod::Auto}) {
            SCOPED_TRACE(toString(sign));
            BakeSettings settings;
            settings.res = 16;
            settings.sign = sign;
            const Field field = model.bake(settings).field.dense();
            const Grid& grid = field.grid;
            const std::vector<double> xyz = test::samplePositions(grid);
            std::vector<float> values(grid.sampleCount());
            PointQueryOutputs out;
            out.signedDistance = values.data();
            model.query(xyz.data(), grid.sampleCount(), out, sign);
            for (std::size_t n = 0; n < values.size(); ++n) ASSERT_EQ(values[n], field.values[n]) << n;

            std::vector<double> known;
            for (const glm::dvec3& p : c.inside) known.insert(known.end(), {p.x, p.y, p.z});
            for (const glm::dvec3& p : c.outside) known.insert(known.end(), {p.x, p.y, p.z});
            std::vector<float> sides(c.inside.size() + c.outside.size());
            out.signedDistance = sides.data();
            model.query(known.data(), sides.size(), out, sign);
            for (std::size_t n = 0; n < sides.size(); ++n) {
                EXPECT_EQ(sides[n] < 0.0f, n < c.inside.size()) << "point " << n << ": " << sides[n];
            }
        }
    }
}

} // namespace
} // namespace sdfgen
