// The narrow-band bake against the dense bake: every sample within the band has the dense value
// bit for bit, every other sample the dense field's side and the background's magnitude; the same
// on 1 and 2 threads.
#include "support/broken_meshes.hpp"
#include "support/checks.hpp"
#include "support/reference.hpp"
#include "support/shapes.hpp"
#include "support/stand_in_device.hpp"
#include "core/bake/band_bake.hpp"
#include "core/bake/bake.hpp"
#include "core/runtime/memory.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/model.hpp"

#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>

namespace sdfgen {
namespace {

std::uint32_t bits(float v) {
    std::uint32_t b;
    std::memcpy(&b, &v, sizeof b);
    return b;
}

// Checks the band bake of `mesh` against its dense bake; returns the count of samples in the band.
std::size_t expectMatchesDense(const std::string& name, const Mesh& mesh, int res, double band, SignMethod sign, int threads) {
    BakeSettings settings;
    settings.res = res;
    settings.sign = sign;
    settings.device = "cpu";
    const BakeResult dense = test::bakeMesh(mesh, settings, threads);
    settings.band = band;
    const BakeResult sparse = test::bakeMesh(mesh, settings, threads);
    const SparseField& s = sparse.field.band(); // valid by construction
    EXPECT_EQ(sparse.sign, dense.sign) << name;
    EXPECT_EQ(s.grid().dims, dense.field.dense().grid.dims) << name;
    EXPECT_EQ(s.background(), float(band * dense.field.dense().grid.voxel)) << name;
    const Grid& g = dense.field.dense().grid;
    std::size_t inBand = 0, wrong = 0;
    for (int k = 0; k < g.dims.z; ++k)
        for (int j = 0; j < g.dims.y; ++j)
            for (int i = 0; i < g.dims.x; ++i) {
                const float d = dense.field.dense().at(i, j, k), v = s.at(i, j, k);
                if (std::fabs(d) < s.background()) {
                    ++inBand;
                    wrong += bits(v) != bits(d);
                } else {
                    wrong += v != (std::signbit(d) ? -s.background() : s.background());
                }
            }
    EXPECT_EQ(wrong, 0u) << name << " res " << res << " band " << band << " sign " << toString(sign) << " threads " << threads;
    EXPECT_EQ(s.activeCount(), inBand) << name;
    // The dense form is the dense field clamped to the band.
    const Field made = s.toDense();
    EXPECT_EQ(made.values.size(), dense.field.dense().values.size());
    return inBand;
}

struct Case {
    std::string name;
    Mesh mesh;
};

std::vector<Case> hardMeshes() {
    std::vector<Case> cases;
    for (test::Shape& shape : test::closedShapes()) cases.push_back({shape.name, std::move(shape.mesh)});
    for (test::Shape& shape : test::openShapes()) cases.push_back({shape.name, std::move(shape.mesh)});
    const Mesh box = test::box({0.5f, 0.4f, 0.3f});
    cases.push_back({"box inside out", test::translated(box, {0, 0, 0}, true)});
    cases.push_back({"overlapping boxes", test::combined("overlapping boxes", box, test::translated(box, {0.3f, 0.2f, 0.1f}, false))});
    cases.push_back({"duplicated box", test::combined("duplicated box", box, box)});
    cases.push_back({"box and an inverted copy", test::combined("cancelling", box, test::translated(box, {0.2f, 0, 0}, true))});
    cases.push_back({"unshared torus", test::unshared(test::torus(1.0f, 0.3f, 16, 8))});
    return cases;
}

TEST(BandBake, EqualsTheDenseBakeInTheBandAndItsSidesOutside) {
    for (const Case& c : hardMeshes()) {
        for (const int threads : {1, 2}) {
            EXPECT_GT(expectMatchesDense(c.name, c.mesh, 37, 2.0, SignMethod::Auto, threads), 0u) << c.name;
        }
        expectMatchesDense(c.name, c.mesh, 50, 1.0, SignMethod::Winding, 2);
        expectMatchesDense(c.name, c.mesh, 29, 3.5, SignMethod::Auto, 2);
    }
}

// Every sign the registry lets side a band matches its dense bake: on a closed mesh, and on an open
// one where its sides are not limited to meshes proven clean; the others are refused.
TEST(BandBake, EverySignThatSidesABandMatchesItsDenseBake) {
    for (const SignMethodPlugin& sign : signMethods()) {
        if (sign.band == BandSigning::Never) {
            BakeSettings settings;
            settings.res = 16;
            settings.band = 2;
            settings.sign = sign.id;
            EXPECT_NE(test::errorFrom([&] { test::bakeMesh(test::icosphere(1.0f, 1), settings); }), "") << sign.name;
            continue;
        }
        for (int threads : {1, 2}) expectMatchesDense(sign.name, test::icosphere(1.0f, 2), 33, 2.0, sign.id, threads);
        if (sign.band != BandSigning::WhereProven) expectMatchesDense(sign.name, test::holedSphere(1.0f), 41, 1.5, sign.id, 2);
    }
}

TEST(BandBake, OpenMeshesAtAFinerGrid) {
    // Finer grids leave cubes near the holes' fans but far from the surface, whose side the bake
    // takes from the winding number at their centre and the bound on its change.
    expectMatchesDense("holed sphere", test::holedSphere(1.0f), 112, 2.0, SignMethod::Auto, 2);
    expectMatchesDense("cup", test::cup(false), 112, 3.0, SignMethod::Auto, 2);
    expectMatchesDense("disk", test::flatDisk(), 96, 1.5, SignMethod::Auto, 1);
}

// An icosphere missing a cap and every `every`-th triangle.
Mesh shellWithHoles(int every) {
    const Mesh sphere = test::icosphere(1.0f, 3);
    std::vector<glm::uvec3> kept;
    for (std::size_t t = 0; t < sphere.triangleCount(); ++t) {
        const glm::vec3 centroid = (sphere.vertex(t, 0) + sphere.vertex(t, 1) + sphere.vertex(t, 2)) / 3.0f;
        if (t % std::size_t(every) != 0 && centroid.y <= 0.8f) kept.push_back(sphere.triangles[t]);
    }
    return buildMesh("shell with holes", sphere.worldPositions(), std::move(kept));
}

// Copies of a shell with many holes, one shifted a little: cubes clear of the surface but near the
// fans take their side from the winding number at their centre and a bound on its change over the
// cube, which must count every hole's loop. A bound that left out the loops whose fans' boxes the
// cube misses gave 633 wrong sides here.
TEST(BandBake, ShiftedCopiesOfAShellWithManyHoles) {
    const Mesh shell = shellWithHoles(7);
    const Mesh copies = test::combined("shifted holed shells", test::combined("copies", shell, shell), test::translated(shell, {0.02f, 0.01f, 0.015f}, false));
    expectMatchesDense("shifted holed shells", copies, 96, 2.0, SignMethod::Winding, 2);
}

// A short, wide tube open at both ends (radius 1, height 2 * halfHeight, n sides).
Mesh openRing(float halfHeight, int n) {
    std::vector<glm::dvec3> positions;
    std::vector<glm::uvec3> triangles;
    for (int i = 0; i < n; ++i) {
        const double a = 2.0 * M_PI * i / n;
        positions.emplace_back(std::cos(a), std::sin(a), -halfHeight);
        positions.emplace_back(std::cos(a), std::sin(a), halfHeight);
    }
    for (std::uint32_t i = 0; i < std::uint32_t(n); ++i) {
        const std::uint32_t next = (i + 1) % std::uint32_t(n);
        triangles.emplace_back(2 * i, 2 * next, 2 * next + 1);
        triangles.emplace_back(2 * i, 2 * next + 1, 2 * i + 1);
    }
    return buildMesh("open ring", positions, std::move(triangles));
}

// Inside an open ring the fans over its two ends are counted as a crossing ahead, yet they wind
// by 0.6-0.9 there, so |w| < 1/2 where the count is 1; a ball at its centre puts the surface there
// too. Cubes of several bricks that no fan meets are sided by their counts only where the fans'
// winding number is within 0.45 of 0, in the band and out of it: taking cubes whose fans wind by
// up to 1.5 gave 360k wrong sides here (41k where only cubes in the band were taken so).
TEST(BandBake, AnOpenRingWhoseFansWindByMoreThanAHalf) {
    const Mesh ring = openRing(0.4f, 48);
    expectMatchesDense("open ring", ring, 160, 2.0, SignMethod::Winding, 2);
    expectMatchesDense("open ring around a ball", test::combined("ring and ball", ring, test::icosphere(0.2f, 2)), 160, 2.0,
                       SignMethod::Winding, 2);
}

// A box with triangles inside whose vertices lie on samples and one of whose edges runs through the
// centre of a quarter of a brick (the exact kernel's blocks of 4³ samples): at such a centre a
// triangle's float offset is rounding noise in every direction, and a linear bound that trusted its
// direction once dropped the triangle holding a sample at distance 0 (the band then gave the
// background there). The dense bake's distances must equal brute force's too.
Mesh edgesThroughQuarterCentres(unsigned seed, const BakeSettings& settings) {
    const Mesh box = test::box({1.0f, 1.0f, 1.0f});
    const Grid grid = bakeGrid(box.worldBounds(), settings);
    std::vector<glm::dvec3> positions = box.worldPositions();
    std::vector<glm::uvec3> triangles = box.triangles;
    std::mt19937 random(seed);
    auto inside = [&](const glm::ivec3& s) {
        if (glm::any(glm::lessThan(s, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(s, grid.dims))) return false;
        const glm::dvec3 p = grid.position(s.x, s.y, s.z);
        return std::fabs(p.x) < 1.0 && std::fabs(p.y) < 1.0 && std::fabs(p.z) < 1.0;
    };
    auto sample = [&] { return glm::ivec3(int(random() % unsigned(grid.dims.x)), int(random() % unsigned(grid.dims.y)), int(random() % unsigned(grid.dims.z))); };
    while (triangles.size() < box.triangles.size() + 40) {
        // a and b = 2c - a about a quarter's centre c = lo + 1.5; d anywhere.
        const glm::ivec3 lo = sample() / 4 * 4, a = sample(), b = 2 * lo + 3 - a, d = sample();
        if (!inside(a) || !inside(b) || !inside(d) || a == b || a == d || b == d) continue;
        const auto first = std::uint32_t(positions.size());
        for (const glm::ivec3& s : {a, b, d}) positions.push_back(grid.position(s.x, s.y, s.z));
        triangles.emplace_back(first, first + 1, first + 2);
    }
    return buildMesh("edges through quarter centres " + std::to_string(seed), positions, triangles);
}

TEST(BandBake, EdgesThroughTheCentresOfTheKernelsQuarters) {
    BakeSettings settings;
    settings.res = 20;
    for (unsigned seed = 0; seed < 12; ++seed) {
        const Mesh mesh = edgesThroughQuarterCentres(seed, settings);
        expectMatchesDense(mesh.source, mesh, settings.res, 2.0, SignMethod::Winding, 1);
        const Field exact = test::bakeWith(mesh, settings.res, DistanceMethod::Exact, SignMethod::Winding, 1).field.dense();
        const Field brute = test::bakeWith(mesh, settings.res, DistanceMethod::Brute, SignMethod::Winding, 1).field.dense();
        std::size_t wrong = 0;
        for (std::size_t n = 0; n < exact.values.size(); ++n) wrong += std::fabs(std::fabs(exact.values[n]) - std::fabs(brute.values[n])) > 1e-5f;
        EXPECT_EQ(wrong, 0u) << mesh.source;
    }
}

TEST(BandBake, HugeAndTinyScales) {
    const Mesh sphere = test::icosphere(1.0f, 2);
    for (const float scale : {1e-6f, 1e6f}) {
        std::vector<glm::dvec3> positions = sphere.worldPositions();
        for (glm::dvec3& p : positions) p = p * double(scale) + glm::dvec3(3.0 * scale);
        const Mesh scaled = buildMesh("scaled sphere", positions, sphere.triangles);
        expectMatchesDense("sphere scaled by " + std::to_string(scale), scaled, 40, 3.0, SignMethod::Auto, 2);
    }
}

TEST(BandBake, SameOnAnyThreadCount) {
    const Mesh cup = test::cup(false);
    BakeSettings settings;
    settings.res = 64;
    settings.band = 3;
    settings.device = "cpu";
    const SparseField one = test::bakeMesh(cup, settings, 1).field.band(), two = test::bakeMesh(cup, settings, 2).field.band();
    EXPECT_EQ(one.bricks(), two.bricks());
    EXPECT_EQ(std::memcmp(one.values().data(), two.values().data(), one.values().size() * sizeof(float)), 0);
    EXPECT_EQ(one.insideBoxes(), two.insideBoxes());
}

TEST(BandBake, StoresOnlyBricksNearTheSurface) {
    // A sphere at res 128: the band's bricks are a shell, far fewer than the grid's 16³.
    BakeSettings settings;
    settings.res = 128;
    settings.band = 2;
    settings.device = "cpu";
    const SparseField s = test::bakeMesh(test::icosphere(1.0f, 3), settings).field.band();
    EXPECT_LT(s.bricks().size(), std::size_t(16 * 16 * 16) / 3);
    EXPECT_FALSE(s.insideBoxes().empty());
    EXPECT_LT(s.at(64, 64, 64), 0.0f); // the centre is inside
    EXPECT_GT(s.at(0, 0, 0), 0.0f);
}

// Empty space costs nothing: a box and a holed sphere (its fans near the surface) far inside huge
// grids of 2^48 and 2^36 samples bake in about the time of a small grid (searched from the grid's
// whole cube down, and each layer's empty rows skipped, where a brick-by-brick walk takes minutes),
// with their bricks on the surface only and the right sides.
TEST(BandBake, EmptySpaceCostsNothing) {
    struct Huge {
        const char* name;
        Mesh mesh;
        int res;
    };
    for (const Huge& c : {Huge{"box", test::box({0.5f, 0.4f, 0.3f}), 65536}, Huge{"holed sphere", test::holedSphere(1.0f), 4096}}) {
        BakeSettings settings;
        settings.res = c.res;
        settings.padding = 100;
        settings.band = 1;
        settings.device = "cpu";
        const SparseField s = test::bakeMesh(c.mesh, settings, 2).field.band();
        // A shell one or two bricks thick around the mesh (of the grid's 2^39 or 2^27 bricks).
        const glm::dvec3 across = glm::dvec3(c.mesh.bounds.extent()) / (s.grid().voxel * SparseField::kBrick) + 2.0;
        EXPECT_LT(double(s.bricks().size()), 4.0 * (across.x * across.y + across.y * across.z + across.z * across.x)) << c.name;
        const glm::ivec3 middle = s.grid().dims / 2;
        EXPECT_LT(s.at(middle.x, middle.y, middle.z), 0.0f) << c.name; // both are solid (|w| > 1/2 in the holed sphere)
        EXPECT_GT(s.at(0, 0, 0), 0.0f) << c.name;
        EXPECT_GT(s.at(s.grid().dims.x - 1, s.grid().dims.y - 1, s.grid().dims.z - 1), 0.0f) << c.name;
    }
}

// The process's resident bytes now (VmRSS) and at its peak (VmHWM), from /proc/self/status.
std::pair<double, double> residentBytes() {
    std::ifstream status("/proc/self/status");
    double now = 0.0, peak = 0.0;
    for (std::string line; std::getline(status, line);) {
        if (line.rfind("VmRSS:", 0) == 0) now = std::stod(line.substr(6)) * 1024.0;
        if (line.rfind("VmHWM:", 0) == 0) peak = std::stod(line.substr(6)) * 1024.0;
    }
    return {now, peak};
}

// The band's memory estimate (what bake and the viewer's panel refuse a band by) bounds the
// bake's peak resident memory from above, and by at most twice: on a sphere, a torus and an open
// cup (whose fans' bricks count too), at a size where the band's bricks are most of it.
TEST(BandBake, MemoryEstimateIsAnUpperBoundWithinTwice) {
#ifdef SDFGEN_TEST_ASAN
    GTEST_SKIP() << "AddressSanitizer's shadow memory and quarantine add to the resident memory; the release build runs this test";
#endif
    struct Shape {
        const char* name;
        Mesh mesh;
    };
    for (const Shape& c : {Shape{"sphere", test::icosphere(1.0f, 4)}, Shape{"torus", test::torus(1.0f, 0.3f, 64, 32)}, Shape{"cup", test::cup(false)}}) {
        BakeSettings settings;
        settings.res = 384;
        settings.band = 3;
        settings.device = "cpu";
        const Bvh tree(c.mesh);
        releaseFreedMemory();
        // Writing 5 to clear_refs sets the peak (VmHWM) back to the resident memory now.
        if (!(std::ofstream("/proc/self/clear_refs") << "5").flush()) GTEST_SKIP() << "/proc/self/clear_refs is not writable here";
        const double before = residentBytes().first;
        const BakeResult result = bake(c.mesh, tree, settings, RunControl{});
        const double peak = residentBytes().second - before;
        const double estimate = double(estimateBandBakeBytes(c.mesh, result.field.band().grid(), settings.band));
        EXPECT_GE(estimate, peak) << c.name << ": " << result.field.band().bricks().size() << " bricks";
        EXPECT_LE(estimate, 2.0 * peak) << c.name << ": " << result.field.band().bricks().size() << " bricks";
        std::printf("%s: %zu bricks, peak %.1f MiB, estimate %.1f MiB\n", c.name, result.field.band().bricks().size(), peak / 1048576.0,
                    estimate / 1048576.0);
    }
}

TEST(BandBake, RefusesWhatItCannotDo) {
    const Mesh sphere = test::icosphere(1.0f, 1);
    BakeSettings settings;
    settings.res = 16;
    settings.band = 0.5;
    EXPECT_NE(test::errorFrom([&] { test::bakeMesh(sphere, settings); }).find("band must be 0 (a dense field) or a finite number of voxels from 1"),
              std::string::npos);
    settings.band = 3;
    settings.method = DistanceMethod::Rays;
    EXPECT_NE(test::errorFrom([&] { test::bakeMesh(sphere, settings); }).find("exact"), std::string::npos);
    settings.method = DistanceMethod::Exact;
    const test::ScopedDevice device(test::standInDevice("stand-in", true));
    settings.device = "stand-in";
    EXPECT_CONTAINS(test::errorFrom([&] { test::bakeMesh(sphere, settings); }), "a band bake runs on the CPU only");
    settings.device = "cpu";
    settings.channels.add("gradient");
    EXPECT_NE(test::errorFrom([&] { test::bakeMesh(sphere, settings); }).find("dense bake only"), std::string::npos);
    settings.channels = {};
    settings.sign = SignMethod::Rays; // a vote per sample: out of the band there is none
    EXPECT_NE(test::errorFrom([&] { test::bakeMesh(sphere, settings); }).find("sign rays"), std::string::npos);
    settings.sign = SignMethod::Pseudonormal;
    EXPECT_NE(test::errorFrom([&] { test::bakeMesh(test::cup(false), settings); }).find("pseudonormal"), std::string::npos);
    // A resolution whose dense grid would never fit is fine for a band (refused here by the band's own estimate).
    settings.sign = SignMethod::Auto;
    settings.res = kMaxRes;
    const std::string error = test::errorFrom([&] { test::bakeMesh(sphere, settings); });
    EXPECT_NE(error.find("band"), std::string::npos) << error;
}

} // namespace
} // namespace sdfgen
