// The winding sign on meshes that make it work hard: many holes, long open borders, copies and
// coplanar overlaps. Signs must equal those of the reference winding number, sample by sample,
// and copies must not multiply the work. Plus the mesh check on copies.
#include "core/bvh.hpp"
#include "core/duplicates.hpp"
#include "core/sign.hpp"
#include "core/topology.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <cmath>

namespace sdfgen {
namespace {

// Every `every`-th triangle of `mesh` removed: that many separate holes.
Mesh withHoles(const Mesh& mesh, std::size_t every) {
    std::vector<glm::uvec3> kept;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        if (t % every != every / 2) kept.push_back(mesh.triangles[t]);
    }
    return buildMesh(mesh.source + " with holes", mesh.positions, kept);
}

// An open terrain-like sheet z = f(x, y) over [-1, 1]², n x n cells: one boundary loop of 4n edges.
Mesh heightfield(int n, bool flip) {
    std::vector<glm::vec3> positions;
    std::vector<glm::uvec3> triangles;
    for (int j = 0; j <= n; ++j) {
        for (int i = 0; i <= n; ++i) {
            const float x = -1.0f + 2.0f * float(i) / float(n), y = -1.0f + 2.0f * float(j) / float(n);
            positions.emplace_back(x, y, 0.3f * std::sin(3.0f * x) * std::cos(2.0f * y) + 0.1f * x * y);
        }
    }
    auto at = [&](int i, int j) { return unsigned(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            glm::uvec3 a(at(i, j), at(i + 1, j), at(i + 1, j + 1)), b(at(i, j), at(i + 1, j + 1), at(i, j + 1));
            if (flip) {
                std::swap(a.y, a.z);
                std::swap(b.y, b.z);
            }
            triangles.push_back(a);
            triangles.push_back(b);
        }
    }
    return buildMesh(flip ? "heightfield, flipped" : "heightfield", positions, triangles);
}

// `copies` copies of each triangle of `mesh`, some starting at another corner.
Mesh repeated(const Mesh& mesh, int copies) {
    std::vector<glm::uvec3> triangles;
    for (int copy = 0; copy < copies; ++copy) {
        for (const glm::uvec3& f : mesh.triangles) triangles.push_back(copy % 2 ? glm::uvec3(f.z, f.x, f.y) : f);
    }
    return buildMesh(mesh.source + " x" + std::to_string(copies), mesh.positions, triangles);
}

// Concatenation of two meshes.
Mesh combined(const std::string& name, const Mesh& a, const Mesh& b) {
    std::vector<glm::vec3> positions = a.positions;
    std::vector<glm::uvec3> triangles = a.triangles;
    positions.insert(positions.end(), b.positions.begin(), b.positions.end());
    for (const glm::uvec3& f : b.triangles) triangles.push_back(f + glm::uvec3(unsigned(a.positions.size())));
    return buildMesh(name, positions, triangles);
}

Mesh moved(const Mesh& mesh, const glm::vec3& offset) {
    std::vector<glm::vec3> positions = mesh.positions;
    for (glm::vec3& p : positions) p += offset;
    return buildMesh(mesh.source + " moved", positions, mesh.triangles);
}

// Compares insideByWinding with the reference winding number (times `weight`, for a mesh made of
// `weight` copies of `reference`) at every sample whose reference w is not a rounding error from 1/2.
void expectSignsEqualReference(const Mesh& mesh, const Mesh& reference, double weight, int res, WindingStats* stats = nullptr) {
    const Grid grid = makeGrid(mesh.bounds, res, 0.15f);
    const std::vector<std::uint8_t> inside = insideByWinding(mesh, MeshTopology(mesh), grid, RunControl{}, stats);
    std::size_t compared = 0, referenceInside = 0, ties = 0;
    for (int k = 0; k < grid.dims.z; ++k)
        for (int j = 0; j < grid.dims.y; ++j)
            for (int i = 0; i < grid.dims.x; ++i) {
                const double w = weight * windingNumber(reference, glm::dvec3(grid.sample(i, j, k)));
                if (std::fabs(w - 0.5) < 1e-9) {
                    ++ties;
                    continue;
                }
                ++compared;
                referenceInside += w > 0.5;
                ASSERT_EQ(bool(inside[grid.index(i, j, k)]), w > 0.5)
                    << mesh.source << " at " << i << "," << j << "," << k << ": w = " << w;
            }
    EXPECT_LT(ties, compared / 1000 + 1) << mesh.source;
    std::printf("[ winding ] %-32s %zu samples, %zu inside\n", mesh.source.c_str(), compared, referenceInside);
}

TEST(WindingSign, EqualsTheReferenceWithManyHoles) {
    const Mesh holed = withHoles(test::icosphere(1.0f, 3), 9); // 142 separate one-triangle holes
    ASSERT_GT(MeshTopology(holed).boundaryLoops().size(), 100u);
    expectSignsEqualReference(holed, holed, 1.0, 20);
    const Mesh holedTorus = withHoles(test::torus(1.0f, 0.4f, 32, 16), 5);
    expectSignsEqualReference(holedTorus, holedTorus, 1.0, 20);
}

TEST(WindingSign, EqualsTheReferenceOnOpenSheetsWithLongBorders) {
    for (bool flip : {false, true}) {
        const Mesh sheet = heightfield(40, flip); // a 160-edge border, closed by many small fans
        WindingStats stats;
        expectSignsEqualReference(sheet, sheet, 1.0, 20, &stats);
        EXPECT_GE(stats.caps, 160u / 8u);
    }
    // Two sheets crossing each other, and a sheet over a closed shape.
    const Mesh sheet = heightfield(24, false);
    expectSignsEqualReference(combined("sheet over sphere", sheet, moved(test::icosphere(0.6f, 2), {0.1f, 0.0f, 0.2f})),
                              combined("sheet over sphere", sheet, moved(test::icosphere(0.6f, 2), {0.1f, 0.0f, 0.2f})), 1.0, 18);
}

// Regression: each copy of an open triangle had its own fan, evaluated for every sample, and its
// own crossings per row: quadratic in copies. Copies now share one weighted fan.
TEST(WindingSign, CopiesShareOneFanAndKeepTheSign) {
    std::vector<glm::vec3> positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const Mesh openTetrahedron = buildMesh("open tetrahedron", positions, {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}});
    const Mesh copies = repeated(openTetrahedron, 20000);
    WindingStats stats;
    expectSignsEqualReference(copies, openTetrahedron, 20000.0, 12, &stats);
    EXPECT_EQ(stats.caps, 1u);
    const Grid grid = makeGrid(copies.bounds, 12, 0.15f);
    EXPECT_LE(stats.fanEvaluations, 2 * grid.sampleCount());
    EXPECT_EQ(Bvh(copies).triangleCount(), 3u);
}

TEST(WindingSign, CoplanarOverlapsAndFlippedCopies) {
    // Two squares in one plane, overlapping in part.
    std::vector<glm::vec3> square = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    const Mesh flat = buildMesh("square", square, {{0, 1, 2}, {0, 2, 3}});
    const Mesh overlapping = combined("overlapping squares", flat, moved(flat, {0.5f, 0.25f, 0.0f}));
    expectSignsEqualReference(overlapping, overlapping, 1.0, 16);
    // A closed box with a flipped copy of half its faces: w is 1/2 nowhere, 0 or 1 in places.
    const Mesh box = test::box({1.0f, 0.7f, 0.5f});
    std::vector<glm::uvec3> triangles = box.triangles;
    for (std::size_t t = 0; t < box.triangleCount(); t += 2) triangles.push_back({box.triangles[t].x, box.triangles[t].z, box.triangles[t].y});
    const Mesh flippedCopies = buildMesh("box with flipped copies", box.positions, triangles);
    expectSignsEqualReference(flippedCopies, flippedCopies, 1.0, 16);
    // A sheet written twice.
    const Mesh sheet = heightfield(12, false);
    expectSignsEqualReference(combined("sheet twice", sheet, sheet), sheet, 2.0, 16);
}

TEST(WindingSign, BitIdenticalForAnyThreadCount) {
    const Mesh holed = withHoles(test::torus(1.0f, 0.4f, 32, 16), 5);
    const Grid grid = makeGrid(holed.bounds, 24, 0.1f);
    const MeshTopology topology(holed);
    RunControl one;
    one.threads = 1;
    const std::vector<std::uint8_t> serial = insideByWinding(holed, topology, grid, one);
    for (int threads : {2, 3, 8}) {
        RunControl control;
        control.threads = threads;
        EXPECT_EQ(insideByWinding(holed, topology, grid, control), serial) << threads << " threads";
    }
}

// The mesh check counts copies as the triangle-by-triangle definition would, without pairing them.
TEST(MeshCheck, CopiesCountAsOftenAsTheyOccur) {
    // Two triangles crossing each other, each three times: 9 crossing pairs.
    std::vector<glm::vec3> positions = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}, {0, -0.5f, -1}, {0, -0.5f, 1}, {0, 0.5f, 0}};
    const Mesh pair = buildMesh("crossing pair", positions, {{0, 1, 2}, {3, 4, 5}});
    const Mesh tripled = repeated(pair, 3);
    const Bvh tree(tripled);
    const MeshCheck check = MeshTopology(tripled).check(tripled, tree);
    EXPECT_EQ(check.selfIntersections, 9u);
    EXPECT_EQ(MeshTopology(pair).check(pair, Bvh(pair)).selfIntersections, 1u);
    // 20000 copies of a tetrahedron: every edge is shared by 40000 triangles, none is a boundary.
    Mesh tetrahedron = buildMesh("tetrahedron", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}});
    const Mesh many = repeated(tetrahedron, 20000);
    const MeshCheck manyCheck = MeshTopology(many).check(many, Bvh(many));
    EXPECT_EQ(manyCheck.nonManifoldEdges, 6u);
    EXPECT_EQ(manyCheck.boundaryEdges, 0u);
    EXPECT_EQ(manyCheck.selfIntersections, 0u);
    const TriangleCopies copies = findTriangleCopies(many);
    ASSERT_EQ(copies.unique.size(), 4u);
    EXPECT_EQ(copies.count, std::vector<std::uint32_t>(4, 20000u));
}

} // namespace
} // namespace sdfgen
