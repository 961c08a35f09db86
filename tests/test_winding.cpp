// The winding sign on meshes that make it work hard: many holes, long open borders, copies and
// coplanar overlaps. Signs must equal those of the reference winding number, sample by sample,
// work must stay bounded by what is near, and point queries must agree with the bake.
#include "core/accel/bvh.hpp"
#include "core/accel/wide_bvh.hpp"
#include "core/simd/path.hpp"
#include "core/mesh/sample_positions.hpp"
#include "core/sign/fan_kernel.hpp"
#include "core/sign/winding_sign.hpp"
#include "sdfgen/model.hpp"
#include "core/accel/topology.hpp"
#include "support/checks.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <cmath>
#include <map>
#include <random>
#include <set>

namespace sdfgen {
namespace {

// Every `every`-th triangle of `mesh` removed: that many separate holes.
Mesh withHoles(const Mesh& mesh, std::size_t every) {
    std::vector<glm::uvec3> kept;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        if (t % every != every / 2) kept.push_back(mesh.triangles[t]);
    }
    return buildMesh(mesh.source + " with holes", mesh.worldPositions(), kept);
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

// Concatenation of two meshes.
Mesh combined(const std::string& name, const Mesh& a, const Mesh& b) {
    std::vector<glm::dvec3> positions = a.worldPositions(), more = b.worldPositions();
    std::vector<glm::uvec3> triangles = a.triangles;
    positions.insert(positions.end(), more.begin(), more.end());
    for (const glm::uvec3& f : b.triangles) triangles.push_back(f + glm::uvec3(unsigned(a.positions.size())));
    return buildMesh(name, positions, triangles);
}

Mesh moved(const Mesh& mesh, const glm::dvec3& offset) {
    std::vector<glm::dvec3> positions = mesh.worldPositions();
    for (glm::dvec3& p : positions) p += offset;
    return buildMesh(mesh.source + " moved", positions, mesh.triangles);
}

// An open tube (no end caps) of `segments` sides and `rings` rings along `axis` from `base`: two
// boundary loops of `segments` edges, each closed by several fans.
Mesh openTube(const glm::dvec3& base, const glm::dvec3& axis, double radius, int segments, int rings) {
    const glm::dvec3 u = glm::normalize(glm::cross(axis, std::fabs(axis.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
    const glm::dvec3 v = glm::normalize(glm::cross(axis, u));
    std::vector<glm::dvec3> positions;
    std::vector<glm::uvec3> triangles;
    for (int r = 0; r <= rings; ++r) {
        for (int s = 0; s < segments; ++s) {
            const double a = 2.0 * M_PI * s / segments;
            positions.push_back(base + axis * (double(r) / rings) + radius * (std::cos(a) * u + std::sin(a) * v));
        }
    }
    auto at = [&](int r, int s) { return unsigned(r * segments + (s % segments)); };
    for (int r = 0; r < rings; ++r) {
        for (int s = 0; s < segments; ++s) {
            triangles.push_back({at(r, s), at(r, s + 1), at(r + 1, s + 1)});
            triangles.push_back({at(r, s), at(r + 1, s + 1), at(r + 1, s)});
        }
    }
    return buildMesh("open tube", positions, triangles);
}

// `mesh` with every face flipped: w negated everywhere.
Mesh reversed(const Mesh& mesh) {
    std::vector<glm::uvec3> triangles = mesh.triangles;
    for (glm::uvec3& t : triangles) std::swap(t.y, t.z);
    return buildMesh(mesh.source + ", reversed", mesh.worldPositions(), triangles);
}

// Compares insideByWinding with the reference winding number (times `weight`, for a mesh made of
// `weight` copies of `reference`), inside where |w| > 1/2, at every sample whose reference |w| is
// not a rounding error from 1/2, for the mesh and for it with every face flipped (the same signs).
void expectSignsEqualReference(const Mesh& mesh, const Mesh& reference, double weight, int res, WindingStats* stats = nullptr) {
    const Grid grid = makeGrid(mesh.worldBounds(), res, 0.15);
    const std::vector<std::uint8_t> inside = insideByWinding(mesh, MeshTopology(mesh), grid, RunControl{}, stats);
    const Mesh flipped = reversed(mesh);
    const std::vector<std::uint8_t> insideFlipped = insideByWinding(flipped, MeshTopology(flipped), grid, RunControl{});
    std::size_t compared = 0, referenceInside = 0, ties = 0;
    for (int k = 0; k < grid.dims.z; ++k)
        for (int j = 0; j < grid.dims.y; ++j)
            for (int i = 0; i < grid.dims.x; ++i) {
                const double w = weight * windingNumber(reference, localPosition(reference, grid, i, j, k));
                if (std::fabs(std::fabs(w) - 0.5) < 1e-9) {
                    ++ties;
                    continue;
                }
                ++compared;
                referenceInside += std::fabs(w) > 0.5;
                ASSERT_EQ(bool(inside[grid.index(i, j, k)]), std::fabs(w) > 0.5)
                    << mesh.source << " at " << i << "," << j << "," << k << ": w = " << w;
                ASSERT_EQ(bool(insideFlipped[grid.index(i, j, k)]), std::fabs(w) > 0.5)
                    << mesh.source << " flipped at " << i << "," << j << "," << k << ": w = " << w;
            }
    EXPECT_LT(ties, compared / 1000 + 1) << mesh.source;
    EXPECT_GT(referenceInside, 0u) << mesh.source;
    EXPECT_LT(referenceInside, compared) << mesh.source;
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
    const Mesh sheetOverSphere = combined("sheet over sphere", sheet, moved(test::icosphere(0.6f, 2), {0.1, 0.0, 0.2}));
    expectSignsEqualReference(sheetOverSphere, sheetOverSphere, 1.0, 18);
}

// Beside open sheets |w| nears 1/2 on both sides, and a block's samples left in doubt by its first
// measure have their cut carried on to tighter targets (only the fans added measured): the signs
// are still the reference's, among many open parts.
TEST(WindingSign, CarriedCutsDecideAsTheReferenceDoes) {
    Mesh parts = combined("sheet over holed spheres", heightfield(24, false), moved(withHoles(test::icosphere(0.35f, 2), 4), {-0.5, 0.0, 0.3}));
    parts = combined("sheet over holed spheres", parts, moved(reversed(withHoles(test::icosphere(0.3f, 2), 5)), {0.45, 0.1, -0.35}));
    WindingStats stats;
    expectSignsEqualReference(parts, parts, 1.0, 28, &stats);
    EXPECT_GT(stats.carriedSamples, 500u);
}

// Seen from a brick among open tubes, the other tubes' end fans each bound w by little but
// together by much: the samples a cut leaves in doubt have those far fans expanded exactly at the
// brick's centre (WindingCaps::expandFar), and are decided as the reference decides them.
TEST(WindingSign, FarFansExpandedForTheSamplesLeftInDoubt) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    Mesh tubes = openTube({-1.0, -1.0, -1.0}, {0.3, 0.2, 1.9}, 0.25, 12, 4);
    for (int n = 1; n < 24; ++n) {
        const glm::dvec3 base(unit(rng), unit(rng), unit(rng) - 0.5), axis(0.6 * unit(rng), 0.6 * unit(rng), 1.0 + 0.3 * unit(rng));
        Mesh tube = openTube(base, axis, 0.15 + 0.1 * (unit(rng) + 1.0), 12, 4);
        tubes = combined("open tubes", tubes, n % 3 == 0 ? reversed(tube) : tube);
    }
    ASSERT_EQ(MeshTopology(tubes).boundaryLoops().size(), 48u);
    WindingStats stats;
    expectSignsEqualReference(tubes, tubes, 1.0, 40, &stats);
    EXPECT_GT(stats.farExpansions, 10u);
}

TEST(WindingSign, CoplanarOverlapsAndFlippedCopies) {
    // Two squares in one plane, overlapping in part.
    std::vector<glm::vec3> square = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    const Mesh flat = buildMesh("square", square, {{0, 1, 2}, {0, 2, 3}});
    const Mesh overlapping = combined("overlapping squares", flat, moved(flat, {0.5, 0.25, 0.0}));
    expectSignsEqualReference(overlapping, overlapping, 1.0, 16);
    // A closed box with a flipped copy of half its faces: |w| is 1/2 nowhere, 0 or 1 in places.
    const Mesh box = test::box({1.0f, 0.7f, 0.5f});
    std::vector<glm::uvec3> triangles = box.triangles;
    for (std::size_t t = 0; t < box.triangleCount(); t += 2) triangles.push_back({box.triangles[t].x, box.triangles[t].z, box.triangles[t].y});
    const Mesh flippedCopies = buildMesh("box with flipped copies", box.worldPositions(), triangles);
    expectSignsEqualReference(flippedCopies, flippedCopies, 1.0, 16);
    // A sheet written twice.
    const Mesh sheet = heightfield(12, false);
    expectSignsEqualReference(combined("sheet twice", sheet, sheet), sheet, 2.0, 16);
}

// A double-sided panel (a sheet and its reversed copy a hair behind it): the two borders are
// closed together by the thin strip between them, one quad per border edge, rather than by fans
// spanning the panel twice with opposite signs; the signs are the reference's. A copy shifted by
// more than a tenth of its size is not paired.
TEST(WindingSign, DoubleSidedPanelsAreClosedByTheStripBetweenTheirBorders) {
    const Mesh sheet = heightfield(30, false); // a border of 120 edges
    const Mesh panel = combined("double-sided panel", sheet, moved(reversed(sheet), {0.0, 0.0, -0.003}));
    const Mesh scene = combined("double-sided panel and a sphere", panel, moved(test::icosphere(0.5f, 2), {0.0, 0.0, 0.8}));
    WindingStats stats;
    expectSignsEqualReference(scene, scene, 1.0, 24, &stats);
    EXPECT_EQ(stats.caps, 120u);
    const Mesh apart = combined("a sheet and a reversed copy apart", sheet, moved(reversed(sheet), {0.0, 0.0, -0.5}));
    const Mesh apartScene = combined("a sheet, a reversed copy apart and a sphere", apart, moved(test::icosphere(0.5f, 2), {0.0, 0.0, 0.8}));
    WindingStats apartStats;
    expectSignsEqualReference(apartScene, apartScene, 1.0, 24, &apartStats);
    EXPECT_EQ(apartStats.caps, 2 * WindingCaps(MeshTopology(sheet)).caps().size());
}

// A flat ring of `segments` quads between radii 1 and 2 in the plane z = 0: two long borders.
Mesh ring(int segments) {
    std::vector<glm::vec3> positions;
    std::vector<glm::uvec3> triangles;
    for (int s = 0; s < segments; ++s) {
        const float angle = 2.0f * float(M_PI) * float(s) / float(segments);
        positions.emplace_back(std::cos(angle), std::sin(angle), 0.0f);
        positions.emplace_back(2.0f * std::cos(angle), 2.0f * std::sin(angle), 0.0f);
    }
    for (unsigned s = 0; s < unsigned(segments); ++s) {
        const unsigned t = (s + 1) % unsigned(segments);
        triangles.push_back({2 * s, 2 * s + 1, 2 * t + 1});
        triangles.push_back({2 * s, 2 * t + 1, 2 * t});
    }
    return buildMesh("ring", positions, triangles);
}

// A long loop is closed by runs of kMaxCapEdges edges and the polygon of their chords (and so
// on), a double-sided panel by quads with a rung between each two: every chord or rung belongs to
// exactly two caps of the same weight, which run it opposite ways, so that where both caps are
// expanded together its fields cancel; every other edge of a cap is an edge of the mesh's boundary.
// Over the middle of a ring's hole, clear of its border but beside the chords that cross the hole,
// the variation bound then holds and is within a small factor of the moves seen (the chords'
// terms would make it four times looser).
TEST(WindingSign, ChordsBelongToTwoCapsThatRunThemOppositeWays) {
    const Mesh sheet = heightfield(30, false);
    const Mesh panel = combined("double-sided panel", sheet, moved(reversed(sheet), {0.0, 0.0, -0.003}));
    for (const Mesh& mesh : {sheet, panel, ring(64), withHoles(test::icosphere(1.0f, 3), 7)}) {
        const MeshTopology topology(mesh);
        const WindingCaps caps(topology);
        std::set<std::pair<std::array<double, 3>, std::array<double, 3>>> boundary; // undirected
        auto key = [](const glm::dvec3& v) { return std::array<double, 3>{v.x, v.y, v.z}; };
        for (const std::vector<std::uint32_t>& loop : topology.boundaryLoops())
            for (std::size_t i = 0; i < loop.size(); ++i) {
                const auto a = key(topology.position(loop[i])), b = key(topology.position(loop[(i + 1) % loop.size()]));
                boundary.insert({std::min(a, b), std::max(a, b)});
            }
        struct Side {
            glm::dvec3 from, to;
            int weight;
        };
        std::map<std::uint32_t, std::vector<Side>> chords;
        for (const Cap& cap : caps.caps()) {
            const std::size_t n = cap.loop.size();
            ASSERT_LE(n, Cap::kMaxEdges);
            for (std::size_t i = 0; i < n; ++i) {
                const glm::dvec3 from = cap.loop[i], to = cap.loop[(i + 1) % n];
                if (cap.chord[i]) {
                    chords[cap.chord[i]].push_back({from, to, cap.weight});
                } else {
                    const auto a = key(from), b = key(to);
                    EXPECT_TRUE(boundary.count({std::min(a, b), std::max(a, b)})) << mesh.source << ": an edge of no boundary loop";
                }
            }
        }
        for (const auto& [id, sides] : chords) {
            ASSERT_EQ(sides.size(), 2u) << mesh.source << ", chord " << id;
            EXPECT_EQ(sides[0].from, sides[1].to) << mesh.source << ", chord " << id;
            EXPECT_EQ(sides[0].to, sides[1].from) << mesh.source << ", chord " << id;
            EXPECT_EQ(sides[0].weight, sides[1].weight) << mesh.source << ", chord " << id;
        }
        if (mesh.source != "ring") continue;
        EXPECT_GT(chords.size(), 30u);
        std::mt19937 rng(5);
        std::uniform_real_distribution<double> unit(-1.0, 1.0);
        for (double height : {0.2, 0.35}) {
            const glm::dvec3 centre(0.05, -0.03, height);
            const double reach = 0.15;
            const double variation = caps.windingVariation(centre, reach);
            const double w = windingNumber(mesh, centre);
            double moved = 0.0;
            for (int m = 0; m < 64; ++m) {
                glm::dvec3 offset(unit(rng), unit(rng), unit(rng));
                offset /= glm::length(offset);
                moved = std::max(moved, std::fabs(windingNumber(mesh, centre + offset * reach) - w));
            }
            EXPECT_LE(moved, variation) << "at height " << height;
            EXPECT_LT(variation, 6.0 * moved) << "at height " << height; // 3.4-3.5 (14-17 with the chords' terms)
        }
    }
}

TEST(WindingSign, BitIdenticalForAnyThreadCount) {
    const Mesh holed = withHoles(test::torus(1.0f, 0.4f, 32, 16), 5);
    const Grid grid = makeGrid(holed.worldBounds(), 24, 0.1);
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

// The bake's form (the field negated in place, no flags) gives the flags' signs, for either
// orientation; and the topology built from the tree's copies is the one built on its own.
TEST(WindingSign, NegatingInPlaceEqualsTheFlags) {
    const Mesh torus = withHoles(test::torus(1.0f, 0.4f, 32, 16), 5);
    const Grid grid = makeGrid(torus.worldBounds(), 20, 0.1);
    for (const Mesh& holed : {torus, reversed(torus)}) {
        const MeshTopology topology(holed, Bvh(holed));
        const std::vector<std::uint8_t> inside = insideByWinding(holed, MeshTopology(holed), grid, RunControl{});
        std::vector<float> field(grid.sampleCount());
        for (std::size_t i = 0; i < field.size(); ++i) field[i] = float(i % 7) + 0.5f;
        signByWinding(holed, topology, grid, field.data(), RunControl{});
        std::size_t negated = 0;
        for (std::size_t i = 0; i < field.size(); ++i) {
            ASSERT_EQ(field[i], inside[i] ? -(float(i % 7) + 0.5f) : float(i % 7) + 0.5f) << "sample " << i;
            negated += inside[i];
        }
        EXPECT_GT(negated, 0u) << holed.source; // either way round, the torus is solid (|w| = 1 inside)
    }
}

// The fans are measured only where they can matter: far fewer than samples x fans, and no more
// than a few per sample on average (the fan kernel's four samples at once counted once), with
// many holes. At res 64 a brick of 8³ spans an eighth of the sphere (at res 32, a quarter of it
// and of its holes: a brick's near fans are then most of them).
TEST(WindingSign, WorkIsBoundedByWhatIsNear) {
    const Mesh holed = withHoles(test::icosphere(1.0f, 4), 9); // 569 one-triangle holes
    const Grid grid = makeGrid(holed.worldBounds(), 64, 0.15);
    WindingStats stats;
    insideByWinding(holed, MeshTopology(holed), grid, RunControl{}, &stats);
    ASSERT_GT(stats.caps, 500u);
    EXPECT_LT(stats.fanEvaluations, grid.sampleCount() * 3) << stats.caps << " caps";
}

// farFromEveryFan sums the bounds of the nodes it does not open, leaves included: where it holds,
// the fans' winding number stays below 0.45 at every point of the ball (measured at points spread
// over it, every fan summed), so the counts alone decide there. Balls at every distance from
// the holes of a holed sphere and from the border of an open sheet.
TEST(WindingSign, FarFromEveryFanHoldsOnlyWhereTheFansCannotDecide) {
    for (const Mesh& mesh : {withHoles(test::icosphere(1.0f, 3), 7), heightfield(12, false)}) {
        const MeshTopology topology(mesh);
        const WindingCaps caps(topology);
        ASSERT_FALSE(caps.empty());
        std::mt19937 rng(5);
        std::uniform_real_distribution<double> coordinate(-1.6, 1.6), unit(-1.0, 1.0);
        std::size_t far = 0, near = 0;
        for (int n = 0; n < 1500; ++n) {
            const glm::dvec3 centre(coordinate(rng), coordinate(rng), coordinate(rng));
            const double reach = 0.02 + 0.3 * (unit(rng) + 1.0);
            if (!caps.farFromEveryFan(centre, reach)) {
                ++near;
                continue;
            }
            ++far;
            for (int m = 0; m < 16; ++m) {
                glm::dvec3 offset(unit(rng), unit(rng), unit(rng));
                if (glm::length(offset) > 1.0) offset /= glm::length(offset);
                const glm::dvec3 p = centre + offset * reach;
                ASSERT_LT(std::fabs(caps.winding(p, 0)), 0.45) << mesh.source << " at " << p.x << "," << p.y << "," << p.z << " reach " << reach;
            }
        }
        EXPECT_GT(far, 100u) << mesh.source;
        EXPECT_GT(near, 100u) << mesh.source;
    }
}

// The fan tree's bounds hold where they are tightest: beside the fans, nearly in their plane (a
// node's bound counts how flat its fans are). For balls beside random fans, the fans a cut leaves
// far (the cut stopped at once, or as the bake makes it) differ from their estimate (the far
// dipoles' and far fans' expansion at the centre, 0 for the others) by at most the cut's farSum
// plus the expansion's curvature term at every point of the ball, and many far nodes are dipoles
// or fans bounded by their expansion; with `expand`, the near fans by their expansion too. Fans along the border of a wavy sheet and of a crumpled one (bent, far from
// planar), and over the holes of a sphere.
TEST(WindingSign, CutBoundsHoldBesideFlatAndBentFans) {
    Mesh crumpled = heightfield(16, false);
    {
        std::vector<glm::dvec3> positions = crumpled.worldPositions();
        for (glm::dvec3& v : positions) v.z += 0.15 * std::sin(23.0 * v.x + 7.0 * v.y) * std::cos(19.0 * v.y);
        crumpled = buildMesh("crumpled sheet", positions, crumpled.triangles);
    }
    for (const Mesh& mesh : {heightfield(12, false), crumpled, withHoles(test::icosphere(1.0f, 3), 7)}) {
        const MeshTopology topology(mesh);
        const WindingCaps caps(topology);
        ASSERT_FALSE(caps.empty());
        std::mt19937 rng(9);
        std::uniform_real_distribution<double> unit(-1.0, 1.0), scale(0.0, 1.0);
        WindingCaps::Cut cut;
        std::size_t bounded = 0, dipoles = 0, expanded = 0, farExpanded = 0;
        for (int n = 0; n < 2000; ++n) {
            const Cap& cap = caps.caps()[std::size_t(rng() % caps.caps().size())];
            const double size = glm::length(cap.hi - cap.lo);
            // Beside the fan, along its loop's first edge, a little off its plane.
            const glm::dvec3 along = cap.loop[1] - cap.loop[0], across = glm::cross(along, cap.centre - cap.loop[0]);
            const glm::dvec3 normal = glm::length(across) > 0.0 ? glm::normalize(across) : glm::dvec3(0.0);
            const glm::dvec3 centre = cap.loop[0] + along * (1.2 + 3.0 * scale(rng)) * (n % 2 ? 1.0 : -1.0) + normal * size * 0.05 * unit(rng);
            const double reach = n % 3 == 0 ? 0.0 : size * 0.1 * scale(rng);
            const int mode = n % 4;
            if (mode == 0) caps.cut(centre, reach, 0.0, 0, false, cut); // stops at the first fan: the nearest stay far
            else if (mode == 1) caps.cut(centre, reach, 0.05, 4, false, cut);
            else if (mode == 2) caps.cut(centre, reach, 1e-3, 4, false, cut, nullptr, false, WindingCaps::kExpandedFanPoints);
            else caps.cut(centre, reach, 0.01, 64, true, cut); // near fans expanded too
            // Every other cut has its far fans expanded too (as for the samples a brick leaves in doubt).
            if (n % 8 >= 4) farExpanded += caps.expandFar(cut, caps.farToExpand(cut), 1e-3, 1000);
            bounded += !cut.farNodes.empty();
            for (const WindingCaps::Pending& node : cut.farNodes) dipoles += node.dipole, expanded += node.expanded;
            for (int m = 0; m < 8; ++m) {
                glm::dvec3 offset(unit(rng), unit(rng), unit(rng));
                if (glm::length(offset) > 1.0) offset /= glm::length(offset);
                const glm::dvec3 p = centre + offset * reach;
                double exact = 0.0;
                caps.fanWindings(cut.exactNodes, &p, 1, &exact);
                const double near = mode == 3 ? 0.0 : caps.nearWinding(p, cut);
                const double rest = -caps.winding(p, 0) - near - exact;
                // The far nodes bounded as dipoles or fans' expansions, and an expanded cut's near
                // fans, count as their expansion at the centre.
                const glm::dvec3 d = p - centre;
                const double estimate = cut.farValue + cut.nearValue + glm::dot(cut.farGradient + cut.nearGradient, d);
                const double spread = cut.farSum + (cut.curvature * glm::length(d) + cut.slack) * glm::length(d);
                ASSERT_LE(std::fabs(rest - estimate), spread * (1.0 + 1e-9) + 1e-12)
                    << mesh.source << " at " << p.x << "," << p.y << "," << p.z << ", cut " << mode;
            }
        }
        EXPECT_GT(bounded, 1000u) << mesh.source;
        EXPECT_GT(dipoles, 100u) << mesh.source;
        EXPECT_GT(expanded, 100u) << mesh.source;
        EXPECT_GT(farExpanded, 50u) << mesh.source;
    }
}

// A node seen from afar counts as its multipole (its fans' dipole to hexadecapole), within
// 5 Σ area |y - centroid|⁴ / (4π d⁶): checked against every fan measured, on a sphere with holes
// seen from 10 and 20 radii, where that bound shrinks as the sixth power of the distance (without
// the hexadecapole it would shrink as the fifth).
TEST(WindingSign, FarNodesCountAsTheirMultipoles) {
    // Two open squares at a right angle (their fans' quadrupole is large: not coplanar), and a
    // sphere with holes.
    const Mesh corner = buildMesh("corner", std::vector<glm::dvec3>{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {0, 1, 1}},
                                  {{0, 1, 2}, {0, 2, 3}, {0, 3, 5}, {0, 5, 4}});
    for (const Mesh& mesh : {corner, withHoles(test::icosphere(1.0f, 3), 7)}) {
        const MeshTopology topology(mesh);
        const WindingCaps caps(topology);
        ASSERT_FALSE(caps.empty());
        std::mt19937 rng(13);
        std::uniform_real_distribution<double> unit(-1.0, 1.0);
        double errors[2] = {}, actual[2] = {}, worst = 0.0;
        std::size_t multipoles = 0; // far nodes of the cuts counted as their multipoles
        for (int n = 0; n < 64; ++n) {
            const glm::dvec3 direction = glm::normalize(glm::dvec3(unit(rng), unit(rng), unit(rng)) + glm::dvec3(1e-3));
            for (int far = 0; far < 2; ++far) {
                const glm::dvec3 p = direction * (far ? 20.0 : 10.0);
                WindingCaps::FansEstimate fans;
                caps.estimateFans(&p, 1, 1.0, &fans); // a node error of 1: the root counts whole
                const double exact = -caps.winding(p, 0);
                ASSERT_LE(std::fabs(fans.value - exact), fans.error) << mesh.source << " at " << p.x << "," << p.y << "," << p.z;
                errors[far] += fans.error;
                actual[far] += std::fabs(fans.value - exact);
                worst = std::max(worst, std::fabs(fans.value - exact) / fans.error);
                // Over a ball around p, as a cut's far node: the multipole's first-order expansion
                // at p, its rest within the multipole's curvature.
                WindingCaps::Cut cut;
                const double reach = far ? 4.0 : 2.0;
                caps.cut(p, reach, 0.0, 0, false, cut);
                for (const WindingCaps::Pending& node : cut.farNodes) multipoles += node.dipole;
                for (int m = 0; m < 8; ++m) {
                    glm::dvec3 offset(unit(rng), unit(rng), unit(rng));
                    if (glm::length(offset) > 1.0) offset /= glm::length(offset);
                    const glm::dvec3 d = offset * reach;
                    const double estimate = cut.farValue + glm::dot(cut.farGradient, d);
                    const double spread = cut.farSum + (cut.curvature * glm::length(d) + cut.slack) * glm::length(d);
                    ASSERT_LE(std::fabs(-caps.winding(p + d, 0) - estimate), spread * (1.0 + 1e-9) + 1e-15) << mesh.source;
                }
            }
        }
        EXPECT_GT(multipoles, 64u) << mesh.source;
        // The expansion's gradient is its value's: central differences along random directions,
        // where the three cuts bound the same nodes the same way.
        int compared = 0;
        for (int n = 0; n < 32; ++n) {
            const glm::dvec3 p = 10.0 * glm::normalize(glm::dvec3(unit(rng), unit(rng), unit(rng)) + glm::dvec3(1e-3));
            const glm::dvec3 e = glm::normalize(glm::dvec3(unit(rng), unit(rng), unit(rng)) + glm::dvec3(1e-3));
            constexpr double h = 1e-4;
            WindingCaps::Cut at, ahead, behind;
            caps.cut(p, 0.5, 0.0, 0, false, at);
            caps.cut(p + h * e, 0.5, 0.0, 0, false, ahead);
            caps.cut(p - h * e, 0.5, 0.0, 0, false, behind);
            auto same = [&](const WindingCaps::Cut& other) {
                if (other.farNodes.size() != at.farNodes.size()) return false;
                for (std::size_t i = 0; i < at.farNodes.size(); ++i) {
                    if (other.farNodes[i].node != at.farNodes[i].node || other.farNodes[i].dipole != at.farNodes[i].dipole) return false;
                }
                return true;
            };
            if (!same(ahead) || !same(behind)) continue;
            ++compared;
            const double slope = (ahead.farValue - behind.farValue) / (2.0 * h), gradient = glm::dot(at.farGradient, e);
            EXPECT_NEAR(slope, gradient, 1e-6 * glm::length(at.farGradient) + 1e-12) << mesh.source;
        }
        EXPECT_GT(compared, 16) << mesh.source;
        EXPECT_GT(errors[0] / errors[1], 48.0) << mesh.source;
        // The estimates' own errors fall as fast (as the fifth power with a wrong hexadecapole, the
        // fourth with a wrong octupole), far below their bounds.
        EXPECT_GT(actual[0] / actual[1], 58.0) << mesh.source; // 64 for the sixth power
        EXPECT_GT(worst, 1e-3) << mesh.source; // the hexadecapole's rest is there to bound
        // Nearer, where the nodes are cut off after the quadrupole or the octupole (their rests'
        // bounds the tighter within about a node's spread), and opened where that errs too much.
        for (double distance : {1.2, 1.5, 2.0, 3.0, 5.0}) {
            for (int n = 0; n < 32; ++n) {
                const glm::dvec3 p = distance * glm::normalize(glm::dvec3(unit(rng), unit(rng), unit(rng)) + glm::dvec3(1e-3));
                for (double nodeError : {1e-2, 1e-4}) {
                    WindingCaps::FansEstimate fans;
                    caps.estimateFans(&p, 1, nodeError, &fans);
                    ASSERT_LE(std::fabs(fans.value - -caps.winding(p, 0)), fans.error) << mesh.source << " at " << distance;
                }
            }
        }
    }
}

// A measured cut bounds a fan far from its ball by the fan's exact first-order expansion at the
// centre: the expansion's rest stays within curvature |δ|² (plus its rounding) at every point of
// the ball, and that bound is tight (seen from afar along its normal, a small fan is a point
// dipole, whose Hessian reaches it). One open triangle, whose cap is one fan.
TEST(WindingSign, FarFanExpansionBoundsItsRestTightly) {
    const Mesh triangle = buildMesh("triangle", std::vector<glm::dvec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
    const MeshTopology topology(triangle);
    const WindingCaps caps(topology);
    ASSERT_EQ(caps.caps().size(), 1u);
    const Cap& cap = caps.caps()[0];
    const glm::dvec3 normal = glm::normalize(glm::cross(cap.loop[1] - cap.loop[0], cap.loop[2] - cap.loop[0]));
    const double size = glm::length(cap.hi - cap.lo);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    double worst = 0.0;
    int expansions = 0;
    for (double distance : {1.5, 2.0, 2.5}) { // farther, the fan's multipole bounds it as tightly
        for (const glm::dvec3& direction : {normal, -normal, glm::normalize(normal + glm::dvec3(0.3, -0.2, 0.1))}) {
            const glm::dvec3 centre = cap.centre + distance * size * direction;
            const double reach = 0.1 * distance * size;
            // The fan's bound over the ball (a cut that stops at once), then a cut to half of it.
            WindingCaps::Cut cut;
            caps.cut(centre, reach, 0.0, 0, false, cut);
            ASSERT_EQ(cut.farNodes.size(), 1u);
            caps.cut(centre, reach, 0.5 * cut.farNodes[0].bound, 1, false, cut, nullptr, false, WindingCaps::kExpandedFanPoints);
            ASSERT_EQ(cut.farNodes.size(), 1u) << "at " << distance << " sizes";
            ASSERT_TRUE(cut.farNodes[0].expanded) << "at " << distance << " sizes";
            ++expansions;
            const WindingCaps::BallDipole& expansion = cut.dipoles[cut.farNodes[0].slot];
            for (int m = 0; m < 64; ++m) {
                // Along the axis to the rim (where the dipole's Hessian peaks), and at random.
                glm::dvec3 offset = m < 8 ? direction * (m % 2 ? 1.0 : -1.0) * (0.25 + 0.75 * (m / 2) / 3.0)
                                          : glm::dvec3(unit(rng), unit(rng), unit(rng));
                if (glm::length(offset) > 1.0) offset /= glm::length(offset);
                const glm::dvec3 d = offset * reach;
                const double fan = -caps.winding(centre + d, 0); // the fan's own winding number
                const double rest = fan - (expansion.value + glm::dot(expansion.gradient, d));
                const double bound = expansion.curvature * glm::dot(d, d) + expansion.error;
                ASSERT_LE(std::fabs(rest), bound * (1.0 + 1e-9) + 1e-15) << "at " << distance << " sizes, offset " << m;
                if (bound > 0.0) worst = std::max(worst, std::fabs(rest) / bound);
            }
        }
    }
    EXPECT_EQ(expansions, 9);
    EXPECT_GT(worst, 0.3); // not a bound that could never be reached
}

// The fan kernel (every fan's factors multiplied into one product per point, one atan2 at the end,
// four or eight points to a vector) agrees with the fans measured one by one, on each SIMD path: at points
// around the fans of a sheet with holes and of two copies of it (fans of weight 2, measured apart),
// and at a fan's own vertex, where a fan has no angle (that point is measured fan by fan).
// A cut's waiting nodes come out loosest first to within a factor of two (by their bounds' binary
// exponents, between the buckets' ends), infinite bounds first, each once, with pushes between
// the pops; those left are all there.
TEST(WindingSign, WaitingNodesComeLoosestFirstWithinAFactorOfTwo) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> exponent(-60.0, 40.0);
    WindingCaps::Waiting waiting;
    for (int round = 0; round < 3; ++round) {
        waiting.clear();
        std::multiset<double> held;
        std::uint32_t next = 0;
        auto add = [&](double bound) {
            waiting.push({bound, next++});
            held.insert(bound);
        };
        for (int i = 0; i < 200; ++i) add(std::exp2(exponent(rng)));
        add(std::numeric_limits<double>::infinity());
        for (int i = 0; i < 150; ++i) {
            ASSERT_FALSE(waiting.empty());
            const double loosest = waiting.loosest().bound, most = *held.rbegin();
            if (std::isinf(most)) {
                ASSERT_TRUE(std::isinf(loosest)) << i;
            } else if (most >= 0x1p-39 && most < 0x1p22) {
                ASSERT_GT(2.0 * loosest, most) << i;
            }
            held.erase(held.find(loosest));
            waiting.pop();
            if (i % 3 == 0) add(std::exp2(exponent(rng)));
        }
        std::multiset<double> left;
        waiting.forEach([&](const WindingCaps::Pending& node) { left.insert(node.bound); });
        EXPECT_EQ(left, held);
    }
}

TEST(WindingSign, FanKernelEqualsEachFanMeasuredAlone) {
    const Mesh sheet = withHoles(heightfield(10, false), 9);
    const SimdPath chosen = simdPath();
    std::size_t nearFans = 0, farFans = 0, wideFans = 0; // as the kernel measures them (fans::FanReach)
    for (const Mesh& mesh : {sheet, combined("two copies", sheet, sheet)}) {
        const MeshTopology topology(mesh);
        const WindingCaps caps(topology);
        bool weighted = false;
        for (const Cap& cap : caps.caps()) weighted |= cap.weight != 1;
        EXPECT_EQ(weighted, mesh.triangleCount() > sheet.triangleCount()) << mesh.source;
        std::mt19937 rng(4);
        std::uniform_real_distribution<double> unit(-1.2, 1.2);
        for (SimdPath path : kSimdPaths) {
            if (!simdPathAvailable(path)) continue;
            setSimdPath(path);
            WindingCaps::Cut cut;
            for (int n = 0; n < 200; ++n) {
                glm::dvec3 points[kFanPoints];
                for (glm::dvec3& p : points) p = glm::dvec3(unit(rng), unit(rng), 0.4 * unit(rng));
                if (n % 2) { // a block's samples: most fans are farther than they are across (no per-factor checks)
                    for (glm::dvec3& p : points) p = points[0] + 0.01 * glm::dvec3(unit(rng), unit(rng), unit(rng));
                }
                if (n % 10 == 0) points[n % kFanPoints] = caps.caps()[std::size_t(n) % caps.caps().size()].loop[0];
                if (n % 10 == 5) points[n % kFanPoints] += glm::dvec3(2e30, 0.0, -1e30); // every fan Wide: its factors (~1e92) rescaled after each
                const int count = 1 + n % kFanPoints;
                caps.cut(points[0], 0.0, 0.0, std::size_t(-1), false, cut); // every fan near (but those of no area)
                ASSERT_TRUE(cut.farNodes.empty());
                ASSERT_GT(cut.nearNodes.size(), caps.caps().size() / 2);
                double windings[kFanPoints];
                caps.fanWindings(cut.nearNodes, points, count, windings);
                const fans::FanReach reach(points, count);
                for (const Cap& cap : caps.caps()) {
                    switch (reach.seen(cap.lo, cap.hi, cap.loop.size())) {
                    case fans::FanReach::Seen::Far: ++farFans; break;
                    case fans::FanReach::Seen::Near: ++nearFans; break;
                    case fans::FanReach::Seen::Wide: ++wideFans; break;
                    }
                }
                for (int s = 0; s < count; ++s) {
                    const double alone = caps.nearWinding(points[s], cut);
                    ASSERT_NEAR(windings[s], alone, 1e-12) << mesh.source << ", " << toString(path) << ", point " << s << " of " << count;
                }
            }
        }
    }
    setSimdPath(chosen);
    EXPECT_GT(nearFans, 1000u);
    EXPECT_GT(farFans, 1000u);
    EXPECT_GT(wideFans, 1000u);
}

// The fan-terms kernel (eight caps to a vector on AVX-512, four on AVX2 and the baseline) gives
// each cap's expansion as fanTerms computes it alone, on each SIMD path, for batches of 1 to 8 caps
// of 2 to 5 edges (runs of a long border, their chords' polygons, a strip's quads) around balls of
// every size: the same answer (false where the ball reaches an edge or its centre lies on the
// fan), and the same terms but for rounding. The fields kernel gives the same terms but the
// winding number wherever fanTerms does, and answers for centres on a fan as well.
TEST(WindingSign, FanTermsKernelEqualsEachCapAlone) {
    const Mesh sheet = heightfield(30, false);
    const Mesh panel = combined("double-sided panel", sheet, moved(reversed(sheet), {0.0, 0.0, -0.003}));
    const SimdPath chosen = simdPath();
    std::size_t answers = 0, refused = 0, fieldsOnly = 0;
    for (const Mesh& mesh : {sheet, panel, withHoles(test::icosphere(1.0f, 3), 7)}) {
        const MeshTopology topology(mesh);
        const WindingCaps caps(topology);
        std::mt19937 rng(8);
        std::uniform_real_distribution<double> unit(-1.2, 1.2), share(0.0, 1.0);
        for (SimdPath path : kSimdPaths) {
            if (!simdPathAvailable(path)) continue;
            setSimdPath(path);
            for (int n = 0; n < 300; ++n) {
                const int count = 1 + n % kFanPoints;
                const Cap* batch[kFanPoints];
                for (int f = 0; f < count; ++f) batch[f] = &caps.caps()[std::size_t(rng()) % caps.caps().size()];
                glm::dvec3 centre(unit(rng), unit(rng), 0.5 * unit(rng));
                if (n % 7 == 0) centre = batch[0]->centre; // on a fan
                // Factors of ~1e92, the product rescaled after each; edges lost to rounding there (their
                // terms 0, its chords' kept by the kernel and not by fanTerms).
                const bool remote = n % 11 == 4;
                if (remote) centre += glm::dvec3(3e30, -1e30, 2e30);
                const double reach = n % 3 == 0 ? 0.0 : 0.2 * share(rng);
                FanTerms terms[kFanPoints];
                bool ok[kFanPoints];
                fans::activeTerms()(batch, count, centre, reach, terms, ok);
                FanTerms fields[kFanPoints];
                bool fieldsOk[kFanPoints];
                fans::activeFields()(batch, count, centre, reach, fields, fieldsOk);
                for (int f = 0; f < count; ++f) {
                    FanTerms alone;
                    const bool aloneOk = fanTerms(*batch[f], centre, reach, alone);
                    const std::string where = mesh.source + ", " + toString(path) + ", batch " + std::to_string(n) + ", cap " + std::to_string(f);
                    ASSERT_EQ(ok[f], aloneOk) << where;
                    ++(ok[f] ? answers : refused);
                    fieldsOnly += fieldsOk[f] && !ok[f];
                    if (!ok[f]) continue;
                    ASSERT_TRUE(fieldsOk[f]) << where;
                    EXPECT_EQ(fields[f].value, 0.0) << where;
                    EXPECT_EQ(fields[f].gradient, terms[f].gradient) << where;
                    EXPECT_EQ(fields[f].curvature, terms[f].curvature) << where;
                    EXPECT_EQ(fields[f].slack, terms[f].slack) << where;
                    ASSERT_EQ(fields[f].chordCount, terms[f].chordCount) << where;
                    for (std::size_t c = 0; c < terms[f].chordCount; ++c) EXPECT_EQ(fields[f].chords[c].curvature, terms[f].chords[c].curvature) << where;
                    const auto near = [](double a, double b) { return std::fabs(a - b) <= 1e-12 * (1.0 + std::fabs(b)); };
                    EXPECT_TRUE(near(terms[f].value, alone.value)) << where;
                    if (remote) {
                        EXPECT_EQ(terms[f].allCurvature(), 0.0) << where;
                        EXPECT_EQ(alone.allCurvature(), 0.0) << where;
                        EXPECT_TRUE(near(terms[f].slack, alone.slack)) << where;
                        continue;
                    }
                    EXPECT_TRUE(near(terms[f].curvature, alone.curvature)) << where;
                    EXPECT_TRUE(near(terms[f].slack, alone.slack)) << where;
                    EXPECT_LE(glm::length(terms[f].gradient - alone.gradient), 1e-12 * (1.0 + glm::length(alone.gradient))) << where;
                    ASSERT_EQ(terms[f].chordCount, alone.chordCount) << where;
                    for (std::size_t c = 0; c < alone.chordCount; ++c) {
                        EXPECT_EQ(terms[f].chords[c].id, alone.chords[c].id) << where;
                        EXPECT_TRUE(near(terms[f].chords[c].curvature, alone.chords[c].curvature)) << where;
                    }
                }
            }
        }
    }
    setSimdPath(chosen);
    EXPECT_GT(answers, 2000u);
    EXPECT_GT(refused, 100u);
    EXPECT_GT(fieldsOnly, 10u); // centres on a fan
}

// The fan kernels' own atan2, on each SIMD path: std::atan2's angle to 2 ulps of π, over every
// octant, magnitudes from 2^-300 to 2^300, ratios at the argument reduction's edge (tan π/8) and
// on the axes, with std::atan2's sign of zero and of π (the product of a fan's factors on the
// negative real axis, im = ±0, takes the side that its count of turns took).
TEST(WindingSign, FanKernelAngleEqualsStdAtan2) {
    std::vector<double> y, x;
    std::mt19937_64 rng(12);
    std::uniform_real_distribution<double> unit(-1.0, 1.0), exponent(-300.0, 300.0);
    for (int n = 0; n < 200000; ++n) {
        double b = unit(rng), a = unit(rng);
        if (n % 3 == 1) a *= std::exp2(exponent(rng)), b *= std::exp2(exponent(rng));
        if (n % 3 == 2) b = a * std::tan(M_PI / 8 * (1.0 + 1e-9 * unit(rng))) * (n % 2 ? 1.0 : -1.0);
        if (n % 4 == 0) std::swap(a, b);
        y.push_back(b), x.push_back(a);
    }
    for (const double b : {0.0, -0.0, 1.0, -1.0, 1e-300, -1e-300, 5e-324, -5e-324})
        for (const double a : {0.0, -0.0, 1.0, -1.0, 1e-300, -1e-300, 5e-324, -5e-324}) y.push_back(b), x.push_back(a);
    const double ulpOfPi = std::nextafter(M_PI, 4.0) - M_PI;
    const SimdPath chosen = simdPath();
    for (SimdPath path : kSimdPaths) {
        if (!simdPathAvailable(path)) continue;
        setSimdPath(path);
        std::vector<double> angles(y.size());
        fans::activeAngles()(y.data(), x.data(), y.size(), angles.data());
        for (std::size_t s = 0; s < y.size(); ++s) {
            const double expected = std::atan2(y[s], x[s]);
            ASSERT_LE(std::fabs(angles[s] - expected), 2.0 * ulpOfPi) << toString(path) << ": atan2(" << y[s] << ", " << x[s] << ")";
            ASSERT_EQ(std::signbit(angles[s]), std::signbit(expected)) << toString(path) << ": atan2(" << y[s] << ", " << x[s] << ")";
        }
    }
    setSimdPath(chosen);
}

// The count of crossings ahead through the wide tree's walk (point queries) equals the binary
// tree's (the bake's reference) at points on vertices, edges and faces of the mesh and its fans as
// well as off them: a holed sphere, copies of an open sheet (a weighted fan, copies counted once)
// and an axis-aligned box, whose faces hold many points' rows.
TEST(WindingSign, CrossingsAheadAgreeOnEitherTree) {
    const Mesh sheet = heightfield(12, false);
    for (const Mesh& mesh : {withHoles(test::icosphere(1.0f, 3), 7), combined("two copies", sheet, sheet), test::box({0.5f, 0.5f, 0.5f})}) {
        const MeshTopology topology(mesh);
        const WindingCaps caps(topology);
        const Bvh tree(mesh);
        const WideBvh wide(mesh, tree);
        std::mt19937 rng(11);
        std::uniform_real_distribution<double> unit(-1.3, 1.3), weight(0.0, 1.0);
        std::vector<glm::dvec3> points;
        const std::vector<glm::dvec3> positions = mesh.worldPositions();
        for (int n = 0; n < 3000; ++n) points.push_back(glm::dvec3(unit(rng), unit(rng), unit(rng)));
        for (std::size_t t = 0; t < mesh.triangleCount(); t += 3) {
            const glm::uvec3& f = mesh.triangles[t];
            const double u = weight(rng), v = weight(rng) * (1.0 - u);
            points.push_back(positions[f.x]);
            points.push_back(0.5 * (positions[f.x] + positions[f.y]));
            points.push_back(positions[f.x] + u * (positions[f.y] - positions[f.x]) + v * (positions[f.z] - positions[f.x]));
        }
        for (const Cap& cap : caps.caps()) points.push_back(cap.centre);
        std::size_t nonzero = 0;
        for (const glm::dvec3& world : points) {
            const glm::dvec3 p = mesh.toLocal(world);
            const int binary = crossingsAhead(mesh, tree, caps, p);
            ASSERT_EQ(crossingsAhead(mesh, wide, tree, caps, p), binary) << mesh.source << " at " << p.x << "," << p.y << "," << p.z;
            nonzero += binary != 0;
        }
        EXPECT_GT(nonzero, points.size() / 25) << mesh.source;
    }
}

// Near an open sheet every sample needs fans: there the bricks' first-order expansion of the near
// fans decides, sample by sample exactly as WindingCaps::inside does, with about as many fans
// measured as inside() measures sample by sample (the samples of 4³ blocks measure their near
// fans, eight at a time, which costs less than expanding them). The last fan of the border spans
// the sheet: bricks that it crosses are decided too, that fan measured at each sample.
TEST(WindingSign, ExpansionDecidesSheetsAsInsideDoes) {
    const Mesh sheet = heightfield(48, false);
    const Grid grid = makeGrid(sheet.worldBounds(), 48, 0.1);
    const MeshTopology topology(sheet);
    WindingStats stats;
    const std::vector<std::uint8_t> inside = insideByWinding(sheet, topology, grid, RunControl{}, &stats);
    const Bvh tree(sheet);
    const WindingCaps caps(topology);
    std::size_t insideCount = 0, perSampleEvaluations = 0;
    for (int k = 0; k < grid.dims.z; ++k)
        for (int j = 0; j < grid.dims.y; ++j)
            for (int i = 0; i < grid.dims.x; ++i) {
                const glm::dvec3 p = localPosition(sheet, grid, i, j, k);
                ASSERT_EQ(bool(inside[grid.index(i, j, k)]), caps.inside(p, crossingsAhead(sheet, tree, caps, p), &perSampleEvaluations)) << i << "," << j << "," << k;
                insideCount += inside[grid.index(i, j, k)];
            }
    EXPECT_GT(insideCount, grid.sampleCount() / 40);
    EXPECT_LT(insideCount, grid.sampleCount() / 2);
    // Under |w| > 1/2 both sides of the sheet are in doubt near it (w near 1/2 on one, -1/2 on the
    // other); the bricks measure fewer fans than inside() does sample by sample (about 83 k against
    // 152 k here).
    EXPECT_LT(stats.fanEvaluations, perSampleEvaluations * 3 / 4) << stats.caps << " caps";
    // Some samples (about 1 in 230) are decided with the big fan measured at each: how many
    // depends on how the fan tree groups the border's fans.
    EXPECT_GT(stats.exactFanSamples, grid.sampleCount() / 400);
}

// The distance from q to the nearest triangle of `mesh`, in double (brute force).
double distanceToMesh(const Mesh& mesh, const glm::dvec3& q) {
    double distance = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const glm::dvec3 a(mesh.vertex(t, 0)), b(mesh.vertex(t, 1)), c(mesh.vertex(t, 2));
        distance = std::min(distance, glm::length(closestPointOnTriangle(q, a, b, c).point - q));
    }
    return distance;
}

// Meshes whose fans matter: a sphere with 7 holes, a terrain sheet, and holes beside a reversed sheet.
std::vector<Mesh> holesAndSheets() {
    return {withHoles(test::icosphere(1.0f, 3), 7), heightfield(24, false),
            combined("holes and a reversed sheet", withHoles(test::icosphere(1.0f, 3), 7),
                     moved(reversed(heightfield(12, false)), glm::dvec3(0.0, 0.0, 1.6)))};
}

// The band bake sides whole cubes off the surface from their centre's w and windingVariation's
// bound on how far w moves over them. The bound holds against the reference winding number at
// points throughout balls that miss the mesh, beside many small holes, a long border (whose fans
// are closed by chords) and a reversed sheet; and it is small enough for the band in most of them.
// sideBeyond, given that bound as its margin, answers with the reference w's side wherever w is
// off ±1/2 by more than the margin, and only there; so does sidesBeyond for the same balls taken
// eight at a time (their estimate shared), and with the same answers.
TEST(WindingSign, VariationBoundsHowFarTheWindingNumberMovesOffTheMesh) {
    for (const Mesh& mesh : holesAndSheets()) {
        const MeshTopology topology(mesh);
        const WindingCaps caps(topology);
        const Bvh tree(mesh);
        ASSERT_FALSE(caps.empty());
        const glm::dvec3 lo(mesh.bounds.min), hi(mesh.bounds.max);
        const double size = glm::length(hi - lo);
        std::mt19937 rng(11);
        std::uniform_real_distribution<double> unit(-1.0, 1.0), share(0.0, 1.0);
        std::size_t balls = 0, small = 0; // balls whose bound is below the 0.25 the band's cubes take
        std::size_t sided = 0;            // of those, the balls sideBeyond sides
        double worst = 0.0; // the largest move seen, over its bound
        std::vector<glm::dvec3> centres; // the balls with a bound below 0.25: their centres, counts ahead,
        std::vector<int> aheads;         // margins and reference winding numbers
        std::vector<double> margins, references;
        while (balls < 300) {
            const glm::dvec3 centre = 0.5 * (lo + hi) + 0.6 * (hi - lo) * glm::dvec3(unit(rng), unit(rng), unit(rng));
            const double reach = size * (0.005 + 0.03 * share(rng));
            if (!(distanceToMesh(mesh, centre) > reach)) continue;
            ++balls;
            const double variation = caps.windingVariation(centre, reach);
            if (!(variation < std::numeric_limits<double>::infinity())) continue;
            small += variation < 0.25;
            const double w = windingNumber(mesh, centre);
            if (variation < 0.25) {
                centres.push_back(centre), aheads.push_back(crossingsAhead(mesh, tree, caps, centre));
                margins.push_back(variation + 1e-6), references.push_back(w);
            }
            for (int m = 0; m < 12; ++m) {
                glm::dvec3 offset(unit(rng), unit(rng), unit(rng));
                offset *= (m < 6 ? 1.0 : share(rng)) / glm::length(offset); // on the rim, and within
                const glm::dvec3 p = centre + offset * reach;
                const double moved = std::fabs(windingNumber(mesh, p) - w);
                ASSERT_LE(moved, variation) << mesh.source << " at " << p.x << "," << p.y << "," << p.z << " reach " << reach;
                worst = std::max(worst, moved / variation);
            }
        }
        for (std::size_t first = 0; first < centres.size(); first += kFanPoints) {
            const int n = int(std::min<std::size_t>(kFanPoints, centres.size() - first));
            int sides[kFanPoints];
            caps.sidesBeyond(&centres[first], &aheads[first], &margins[first], n, sides);
            for (int i = 0; i < n; ++i) {
                const std::size_t b = first + std::size_t(i);
                const double w = references[b], off = std::fabs(std::fabs(w) - 0.5);
                EXPECT_EQ(sides[i], caps.sideBeyond(centres[b], aheads[b], margins[b])) << mesh.source << " w " << w;
                if (sides[i] >= 0) {
                    ++sided;
                    EXPECT_EQ(sides[i], int(std::fabs(w) > 0.5)) << mesh.source << " w " << w;
                    EXPECT_GT(off, margins[b] - 1e-9) << mesh.source << " w " << w;
                } else {
                    EXPECT_LE(off, margins[b] + 1e-9) << mesh.source << " w " << w << " margin " << margins[b];
                }
            }
        }
        EXPECT_GT(small, 150u) << mesh.source;
        EXPECT_GT(sided, small / 2) << mesh.source;
        EXPECT_GT(worst, 0.1) << mesh.source; // within a small factor of the moves seen (0.19-0.76 here)
    }
}

// A band brick near fans is decided from its centre where no fan meets it: the fans' winding
// number (the count of crossings ahead less the mesh's own w) is harmonic over a ball that misses
// every fan, with the surface inside or not, so windingVariation bounds its change there, and
// estimateFans gives it at the centre within its error (shared by up to eight centres). Checked
// against the reference winding number on balls that hold some of the surface.
TEST(WindingSign, VariationBoundsTheFansOverBallsThatHoldTheSurface) {
    for (const Mesh& mesh : holesAndSheets()) {
        const MeshTopology topology(mesh);
        const WindingCaps caps(topology);
        const Bvh tree(mesh);
        const glm::dvec3 lo(mesh.bounds.min), hi(mesh.bounds.max);
        const double size = glm::length(hi - lo);
        // The fans' winding number at p: the closed surface's (its count ahead) less the mesh's.
        auto fansAt = [&](const glm::dvec3& p) { return double(crossingsAhead(mesh, tree, caps, p)) - windingNumber(mesh, p); };
        std::mt19937 rng(5);
        std::uniform_real_distribution<double> unit(-1.0, 1.0), share(0.0, 1.0);
        std::size_t balls = 0, bounded = 0; // balls holding the surface and missing every fan; of those, with a bound below 0.45
        std::vector<glm::dvec3> centres;
        for (int tries = 0; balls < 150 && tries < 20000; ++tries) {
            // A ball around a point of the surface, pushed off it by up to its reach.
            const std::size_t t = std::size_t(share(rng) * double(mesh.triangleCount())) % mesh.triangleCount();
            const double a = share(rng), b = share(rng) * (1.0 - a);
            const glm::dvec3 onSurface = glm::dvec3(mesh.vertex(t, 0)) * (1.0 - a - b) + glm::dvec3(mesh.vertex(t, 1)) * a + glm::dvec3(mesh.vertex(t, 2)) * b;
            const double reach = size * (0.003 + 0.02 * share(rng));
            const glm::dvec3 centre = onSurface + 0.7 * reach * glm::dvec3(unit(rng), unit(rng), unit(rng));
            if (!(distanceToMesh(mesh, centre) < reach) || !caps.fansMiss(centre, reach)) continue;
            ++balls;
            const double variation = caps.windingVariation(centre, reach, 0.45);
            if (!(variation < 0.45)) continue;
            ++bounded;
            centres.push_back(centre);
            const double atCentre = fansAt(centre);
            for (int m = 0; m < 12; ++m) {
                glm::dvec3 offset(unit(rng), unit(rng), unit(rng));
                offset *= (m < 6 ? 1.0 : share(rng)) / glm::length(offset); // on the rim, and within
                const glm::dvec3 p = centre + offset * reach;
                ASSERT_LE(std::fabs(fansAt(p) - atCentre), variation * (1.0 + 1e-6) + 1e-9) << mesh.source << " reach " << reach;
            }
        }
        EXPECT_GE(balls, 150u) << mesh.source;
        EXPECT_GT(bounded, balls / 4) << mesh.source; // the bound is checked on dozens of balls
        for (std::size_t first = 0; first < centres.size(); first += kFanPoints) {
            const int n = int(std::min<std::size_t>(kFanPoints, centres.size() - first));
            WindingCaps::FansEstimate fans[kFanPoints];
            caps.estimateFans(&centres[first], n, 1e-3, fans);
            for (int i = 0; i < n; ++i) {
                const double reference = fansAt(centres[first + std::size_t(i)]);
                EXPECT_LE(std::fabs(fans[i].value - reference), fans[i].error + 1e-9) << mesh.source;
                EXPECT_LT(fans[i].error, 0.1) << mesh.source;
            }
        }
    }
}

// Signed point queries at the samples of the winding bake at `res` (the baked values, as
// Model::query gives them) and the baked field.
std::pair<std::vector<float>, Field> queriedAndBaked(const Mesh& mesh, int res) {
    const Model model(mesh);
    BakeSettings settings;
    settings.res = res;
    settings.sign = SignMethod::Winding;
    Field field = model.bake(settings).field.dense();
    const std::vector<double> xyz = test::samplePositions(field.grid);
    std::vector<float> values(field.grid.sampleCount());
    PointQueryOutputs out;
    out.signedDistance = values.data();
    model.query(xyz.data(), field.grid.sampleCount(), out, SignMethod::Winding);
    return {std::move(values), std::move(field)};
}

// Small parts on an integer lattice (tetrahedra with missing, flipped, doubled and collapsed faces),
// so that samples often lie exactly on a fan (loops of 3-4 edges whose fan triangles pass through
// lattice fractions): there the fan's solid angle jumps, and the side it is taken on must be the
// side the row's crossings counted. Their signs must be those of the reference winding number.
Mesh latticeParts(std::mt19937& rng) {
    std::uniform_int_distribution<int> corner(-2, 2), scale(1, 2), parts(1, 3);
    std::uniform_real_distribution<double> chance(0.0, 1.0);
    std::vector<glm::dvec3> positions;
    std::vector<glm::uvec3> triangles;
    for (int part = parts(rng); part > 0; --part) {
        const glm::dvec3 base(corner(rng), corner(rng), corner(rng));
        const double size = scale(rng);
        const unsigned o = unsigned(positions.size());
        for (const glm::dvec3& v : {glm::dvec3(0, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1)}) positions.push_back(base + size * v);
        for (glm::uvec3 f : {glm::uvec3(0, 2, 1), glm::uvec3(0, 1, 3), glm::uvec3(0, 3, 2), glm::uvec3(1, 2, 3)}) {
            const double r = chance(rng);
            if (r < 0.15) continue; // a hole
            if (r < 0.3) std::swap(f.y, f.z);
            triangles.push_back(f + o);
            if (chance(rng) < 0.15) triangles.push_back(glm::uvec3(f.x, f.z, f.y) + o);
            if (chance(rng) < 0.1) triangles.push_back(glm::uvec3(f.x, f.y, f.y) + o);
        }
    }
    if (triangles.empty()) triangles.push_back({0, 1, 2});
    return buildMesh("lattice parts", positions, triangles);
}

TEST(WindingSign, SamplesOnFansTakeTheSideTheirRowsCounted) {
    // An open tetrahedron with two faces sharing an edge the same way round: loops 0-1-3-2 and
    // 1-3-2, and a point that lies on the first loop's fan, where w is 0.3625 (outside).
    const Mesh tetra = buildMesh("open tetrahedron", std::vector<glm::dvec3>{{0, 1, 0}, {1, 1, 0}, {0, 3, 0}, {0, 1, 2}},
                                 std::vector<glm::uvec3>{{0, 1, 3}, {0, 3, 2}, {3, 2, 1}});
    const MeshTopology topology(tetra);
    const WindingCaps caps(topology);
    const Bvh tree(tetra);
    const WideBvh wide(tetra, tree);
    const glm::dvec3 p = tetra.toLocal(glm::dvec3(1.0, 8.0, 1.0) / 7.0);
    const double reference = windingNumber(tetra, p);
    EXPECT_NEAR(reference, 0.3625, 1e-4);
    EXPECT_NEAR(caps.winding(p, crossingsAhead(tetra, tree, caps, p)), reference, 1e-9);
    EXPECT_NEAR(caps.winding(p, crossingsAhead(tetra, wide, tree, caps, p)), reference, 1e-9);

    std::mt19937 rng(5);
    std::size_t compared = 0, onFans = 0;
    for (int n = 0; n < 80; ++n) {
        const Mesh mesh = latticeParts(rng);
        const Grid grid = makeGrid(mesh.worldBounds(), 5 + n % 8, 0.15);
        const MeshTopology meshTopology(mesh);
        const WindingCaps meshCaps(meshTopology);
        const std::vector<std::uint8_t> inside = insideByWinding(mesh, meshTopology, grid, RunControl{});
        const std::vector<glm::dvec3> positions = mesh.worldPositions();
        for (int k = 0; k < grid.dims.z; ++k)
            for (int j = 0; j < grid.dims.y; ++j)
                for (int i = 0; i < grid.dims.x; ++i) {
                    const glm::dvec3 q = localPosition(mesh, grid, i, j, k);
                    const double w = windingNumber(mesh, q);
                    if (std::fabs(std::fabs(w) - 0.5) < 1e-9 || distanceToMesh(mesh, q) < 1e-9) continue; // a tie, or on the mesh
                    ++compared;
                    for (const Cap& cap : meshCaps.caps()) {
                        for (std::size_t v = 0; v < cap.loop.size(); ++v) {
                            const glm::dvec3 a = cap.loop[(v + 1) % cap.loop.size()], b = cap.loop[v];
                            onFans += glm::length(closestPointOnTriangle(q, a, b, cap.centre).point - q) < 1e-12;
                        }
                    }
                    ASSERT_EQ(bool(inside[grid.index(i, j, k)]), std::fabs(w) > 0.5)
                        << "mesh " << n << " at " << i << "," << j << "," << k << ": w = " << w;
                }
    }
    EXPECT_GT(compared, 10000u);
    EXPECT_GT(onFans, 20u); // the case under test occurs
}

// Where the fans close the mesh exactly (fansCloseMesh), a point's count may be taken on the
// shorter side of its row: minus the crossings behind it equals the crossings ahead at every
// sample of lattice meshes full of holes, flips, doubled and collapsed faces (samples on the mesh
// and on fans included), on both instruction sets; and point queries equal the baked field.
TEST(WindingSign, CountsBehindEqualCountsAheadWhereTheFansCloseTheMesh) {
    std::mt19937 rng(17);
    std::size_t closed = 0, open = 0, compared = 0;
    const SimdPath original = simdPath();
    for (int n = 0; n < 120; ++n) {
        const Mesh mesh = latticeParts(rng);
        const Grid grid = makeGrid(mesh.worldBounds(), 6 + n % 7, 0.15);
        const MeshTopology topology(mesh);
        const WindingCaps caps(topology);
        const Bvh tree(mesh);
        const WideBvh wide(mesh, tree);
        const bool fansClose = fansCloseMesh(topology);
        (fansClose ? closed : open) += 1;
        for (SimdPath path : kSimdPaths) {
            if (!simdPathAvailable(path)) continue;
            setSimdPath(path);
            for (int k = 0; k < grid.dims.z; ++k)
                for (int j = 0; j < grid.dims.y; ++j)
                    for (int i = 0; i < grid.dims.x; ++i) {
                        const glm::dvec3 q = localPosition(mesh, grid, i, j, k);
                        const int ahead = crossingsAhead(mesh, tree, caps, q);
                        ASSERT_EQ(crossingsAhead(mesh, wide, tree, caps, q, fansClose), ahead)
                            << "mesh " << n << " at " << i << "," << j << "," << k << " (" << toString(path) << ")";
                        compared += fansClose;
                    }
        }
        setSimdPath(original);
        if (n % 10 == 0) { // and point queries, through Model, equal the baked field
            const auto [values, field] = queriedAndBaked(mesh, 12);
            for (std::size_t s = 0; s < values.size(); ++s) ASSERT_EQ(values[s], field.values[s]) << "mesh " << n << ", sample " << s;
        }
    }
    setSimdPath(original);
    EXPECT_GT(closed, 60u) << open << " meshes not closed by their fans";
    EXPECT_GT(compared, 100000u);
}

// A sample a few ulps from a fan's plane bounds that fan by about 1e30: once the fan is measured,
// the running sum of the other nodes' bounds must not be what is left of 1e30 minus 1e30 (0), or
// a fan bounded by 0.99 goes unmeasured and the side is wrong (found by the bake fuzzer: queries
// said inside where w = 0.45).
TEST(WindingSign, BoundsOutliveANodeThatAllButTouchesItsBox) {
    const Mesh mesh = buildMesh("cube corner and copies",
                                std::vector<glm::dvec3>{{1, 0, 0}, {1, 1, 0}, {0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}, {1, 0, 1}},
                                std::vector<glm::uvec3>{{0, 3, 2}, {0, 2, 1}, {4, 5, 0}, {0, 3, 2}, {0, 2, 1}, {5, 6, 7}});
    const MeshTopology topology(mesh);
    const WindingCaps caps(topology);
    const Bvh tree(mesh);
    const Grid grid = makeGrid(mesh.worldBounds(), 6, 0.1); // samples a few ulps from the fans' planes
    std::size_t compared = 0;
    for (int k = 0; k < grid.dims.z; ++k)
        for (int j = 0; j < grid.dims.y; ++j)
            for (int i = 0; i < grid.dims.x; ++i) {
                const glm::dvec3 q = localPosition(mesh, grid, i, j, k);
                const double w = windingNumber(mesh, q);
                if (std::fabs(std::fabs(w) - 0.5) < 1e-9 || distanceToMesh(mesh, q) < 1e-9) continue; // a tie, or on the mesh
                const int ahead = crossingsAhead(mesh, tree, caps, q);
                ASSERT_EQ(caps.inside(q, ahead), std::fabs(w) > 0.5) << i << "," << j << "," << k << ": w = " << w;
                std::uint8_t queried = 0;
                caps.insideMany(&q, &ahead, 1, &queried);
                ASSERT_EQ(bool(queried), std::fabs(w) > 0.5) << i << "," << j << "," << k << ": w = " << w;
                ++compared;
            }
    EXPECT_GT(compared, 100u);
    const auto [values, field] = queriedAndBaked(mesh, 6);
    for (std::size_t n = 0; n < values.size(); ++n) ASSERT_EQ(values[n], field.values[n]) << n;
}

// Point queries run the same steps per point as the bake's samples: at the samples' positions
// they give the baked field, bit for bit, on meshes whose signs need the fans.
// Dense points near a holed shell and a shell nested in it inside out, asked in one call: each
// point may take its Morton neighbour's count of crossings where no surface or fan lies between
// them, and every side must still be the reference winding number's.
TEST(WindingSign, NeighbouringQueryPointsKeepTheirOwnSides) {
    const Mesh outer = withHoles(test::icosphere(1.0f, 3), 11);
    const Mesh mesh = combined("holed shell around a reversed shell", outer, reversed(test::icosphere(0.5f, 2)));
    std::mt19937 rng(7);
    std::uniform_int_distribution<std::size_t> pick(0, mesh.triangleCount() - 1);
    std::uniform_real_distribution<double> unit(0.0, 1.0), offset(-0.05, 0.05);
    std::vector<glm::dvec3> points;
    while (points.size() < 40000) {
        const std::size_t t = pick(rng);
        const glm::dvec3 a(mesh.vertex(t, 0)), b(mesh.vertex(t, 1)), c(mesh.vertex(t, 2));
        double u = unit(rng), v = unit(rng);
        if (u + v > 1.0) u = 1.0 - u, v = 1.0 - v;
        const glm::dvec3 normal = glm::normalize(glm::cross(b - a, c - a));
        points.push_back(mesh.toWorld(a + u * (b - a) + v * (c - a) + offset(rng) * normal));
    }
    const std::vector<float> values = Model(mesh).signedDistance(points);
    std::size_t compared = 0, inside = 0;
    for (std::size_t n = 0; n < points.size(); ++n) {
        const double w = windingNumber(mesh, mesh.toLocal(points[n]));
        if (std::fabs(std::fabs(w) - 0.5) < 1e-9 || values[n] == 0.0f) continue;
        ++compared;
        inside += std::fabs(w) > 0.5;
        ASSERT_EQ(values[n] < 0.0f, std::fabs(w) > 0.5) << n << ": w = " << w;
    }
    EXPECT_GT(compared, 39000u);
    EXPECT_GT(inside, 10000u);
}

TEST(WindingSign, PointQueriesEqualTheBakedField) {
    for (const Mesh& mesh : {withHoles(test::torus(1.0f, 0.4f, 32, 16), 5), heightfield(30, true)}) {
        SCOPED_TRACE(mesh.source);
        const auto [values, field] = queriedAndBaked(mesh, 20);
        std::size_t inside = 0;
        for (std::size_t n = 0; n < values.size(); ++n) {
            ASSERT_EQ(values[n], field.values[n]) << n;
            inside += values[n] < 0.0f;
        }
        EXPECT_GT(inside, 0u);
    }
}

} // namespace
} // namespace sdfgen
