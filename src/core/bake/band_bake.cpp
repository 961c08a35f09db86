// The narrow-band bake: exact distances only in the bricks that hold a sample within the band,
// sides everywhere from the winding sign's crossing counts, and the dense grid never allocated.
#include "core/bake/band_bake.hpp"
#include "core/distance/exact.hpp"
#include "core/mesh/geometry.hpp"
#include "core/runtime/memory.hpp"
#include "core/runtime/parallel.hpp"
#include "core/mesh/sample_positions.hpp"
#include "core/sign/winding_sign.hpp"
#include "sdfgen/error.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>
#include <utility>
#include <vector>

namespace sdfgen {

namespace {

constexpr int kBrick = SparseField::kBrick;

// Finds, top-down over cubes of 2^n bricks, the bricks that may hold a sample within the band (a
// cube whose samples are all farther than the band, by one closest-point search from its centre,
// is skipped whole) and, out of the band, those that a fan closing a hole may reach (the winding
// sign decides their samples one by one; elsewhere one count decides a whole brick).
struct BrickFinder {
    const Mesh& mesh;
    const WideBvh& tree;
    const WindingCaps& caps;
    const Grid& grid;
    glm::ivec3 brickDims;
    double band; // local units

    const Bvh& rows; // for the count of crossings ahead of a cube's centre

    struct Found {
        std::vector<glm::ivec3> inBand, nearFans, clearInBand;
        std::vector<std::pair<glm::ivec3, std::uint8_t>> sided;
    };
    static constexpr int kTop = 16; // bricks per edge of the cubes searched in parallel

    // The corners of the cubes of kTop bricks that visit() must search: the others, found from
    // the grid's whole cube down, lie in a larger cube whose every point is farther than the band
    // by twice its ball's radius and whose doubled ball is clear of the fans (a cube of kTop
    // bricks inside has its ball within that, so its own tests would find nothing: empty space
    // costs nothing, in grids of any size).
    std::vector<glm::ivec3> topCubes() const {
        int size = kTop;
        while (size < brickDims.x || size < brickDims.y || size < brickDims.z) size *= 2;
        std::vector<glm::ivec3> tops;
        collect(glm::ivec3(0), size, tops);
        return tops;
    }
    void collect(const glm::ivec3& lo, int size, std::vector<glm::ivec3>& tops) const {
        const glm::ivec3 hi = glm::min(lo + size, brickDims);
        if (glm::any(glm::lessThanEqual(hi, lo))) return;
        if (size == kTop) {
            tops.push_back(lo);
            return;
        }
        const auto [centre, reach] = ball(lo, hi);
        const double d = nearestDistance(centre);
        const double magnitude = std::max({std::fabs(centre.x), std::fabs(centre.y), std::fabs(centre.z)}) + 4.0 * reach + d;
        if (d - 2.0 * reach - 3e-5 * magnitude > band * (1.0 + 1e-5) && caps.farFromEveryFan(centre, 2.0 * reach)) return;
        const int half = size / 2;
        for (int dz = 0; dz < size; dz += half)
            for (int dy = 0; dy < size; dy += half)
                for (int dx = 0; dx < size; dx += half) collect(lo + glm::ivec3(dx, dy, dz), half, tops);
    }
    // The ball around the samples of the bricks [lo, hi).
    std::pair<glm::dvec3, double> ball(const glm::ivec3& lo, const glm::ivec3& hi) const {
        const glm::ivec3 first = lo * kBrick, last = glm::min(hi * kBrick, grid.dims) - 1;
        const glm::dvec3 p0 = localPosition(mesh, grid, first.x, first.y, first.z), p1 = localPosition(mesh, grid, last.x, last.y, last.z);
        return {0.5 * (p0 + p1), 0.5 * glm::length(p1 - p0) * (1.0 + 1e-9)};
    }
    // The distance from p to the triangle the float search finds nearest (it may be a rounding
    // farther than the true nearest triangle: callers allow for that).
    double nearestDistance(const glm::dvec3& p) const {
        std::uint32_t hint = WideBvh::kEmpty;
        const std::uint32_t t = nearestTriangle(tree, glm::vec3(p), hint);
        return std::sqrt(closestPointOnTriangle(p, glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2)))
                             .distanceSquared);
    }
    // A cube of the search: `size` bricks from `lo`, and whether it is known to be out of the band.
    struct Cube {
        glm::ivec3 lo;
        int size;
        bool outOfBand;
        bool fansClear = false;
    };
    // Searches n <= 8 cubes (a cube's children, decided together). A cube out of the band and clear
    // of the fans is skipped; so is one whose ball no fan meets and where the fans' winding number
    // stays within 0.45 of 0 (estimated at its centre, to within its error and windingVariation's
    // bound on its change), for there every sample is inside exactly where its count of crossings
    // ahead is not 0 (as the dense bake decides) and the count is constant out of the band; such a
    // cube in the band is split with its bricks marked so (clearInBand). One near a fan but clear
    // of the surface, where the winding number is smooth, takes one side throughout where w at its
    // centre is off ±1/2 by more than the bound on its change (the dense bake decides every sample
    // so); the others are split, down to bricks. The centres' estimates and sides are made for the
    // cubes together (estimateFans, sidesBeyond).
    void visit(const Cube* cubes, int n, Found& found) const {
        constexpr double kMostVariation = 0.25; // beyond, the centre's w rarely decides the cube
        Cube kept[8];
        glm::dvec3 centres[8];
        double variations[8];
        int split = 0, estimated[8], estimates = 0;
        bool clearCandidate[8];
        glm::dvec3 estimateCentres[8];
        for (int c = 0; c < n; ++c) {
            Cube cube = cubes[c];
            const glm::ivec3 hi = glm::min(cube.lo + cube.size, brickDims);
            if (glm::any(glm::lessThanEqual(hi, cube.lo))) continue;
            const auto [centre, reach] = ball(cube.lo, hi);
            if (!cube.outOfBand) {
                const double d = nearestDistance(centre);
                // The float search's answer may be a rounding farther than the true nearest triangle.
                const double magnitude = std::max({std::fabs(centre.x), std::fabs(centre.y), std::fabs(centre.z)}) + reach + d;
                cube.outOfBand = d - reach - 1e-5 * magnitude > band * (1.0 + 1e-5);
            }
            if (cube.outOfBand && (cube.fansClear || caps.farFromEveryFan(centre, reach))) continue;
            // A brick in the band takes its estimate with its row's (BandSides::bricks).
            const bool tryClear = !cube.fansClear && (cube.outOfBand || cube.size > 1) && !caps.caps().empty() && caps.fansMiss(centre, reach);
            variations[split] = tryClear || cube.outOfBand ? caps.windingVariation(centre, reach, tryClear ? WindingCaps::kMostEstimateVariation : kMostVariation)
                                                           : std::numeric_limits<double>::infinity();
            clearCandidate[split] = tryClear && variations[split] < WindingCaps::kMostEstimateVariation;
            if (clearCandidate[split] || (cube.outOfBand && variations[split] < kMostVariation)) {
                estimated[split] = estimates, estimateCentres[estimates++] = centre;
            }
            centres[split] = centre;
            kept[split++] = cube;
        }
        // The centres' fans estimated together: for the clear cubes, and the first of sidesBeyond's.
        WindingCaps::FansEstimate fans[8], sideFans[8];
        if (estimates > 0) caps.estimateFans(estimateCentres, estimates, WindingCaps::kSideNodeErrors[0], fans);
        glm::dvec3 sideCentres[8];
        int ahead[8], sides[8], sided[8], candidates = 0;
        double margins[8];
        for (int c = 0; c < split; ++c) {
            sided[c] = -1;
            Cube& cube = kept[c];
            if (clearCandidate[c]) {
                cube.fansClear = fans[estimated[c]].countsDecide(variations[c]);
            }
            if (!cube.outOfBand || cube.fansClear || !(variations[c] < kMostVariation)) continue;
            sideCentres[candidates] = centres[c], ahead[candidates] = crossingsAhead(mesh, rows, caps, centres[c]);
            margins[candidates] = variations[c] * (1.0 + 1e-9) + 1e-6;
            sideFans[candidates] = fans[estimated[c]];
            sided[c] = candidates++;
        }
        if (candidates > 0) caps.sidesBeyond(sideCentres, ahead, margins, candidates, sides, sideFans);
        for (int c = 0; c < split; ++c) {
            const Cube& cube = kept[c];
            if (cube.outOfBand && cube.fansClear) continue;
            const glm::ivec3 hi = glm::min(cube.lo + cube.size, brickDims);
            if (sided[c] >= 0 && sides[sided[c]] >= 0) {
                for (int z = cube.lo.z; z < hi.z; ++z)
                    for (int y = cube.lo.y; y < hi.y; ++y)
                        for (int x = cube.lo.x; x < hi.x; ++x) found.sided.emplace_back(glm::ivec3(x, y, z), std::uint8_t(sides[sided[c]]));
                continue;
            }
            if (cube.size == 1) {
                (cube.outOfBand ? found.nearFans : found.inBand).push_back(cube.lo);
                if (cube.fansClear) found.clearInBand.push_back(cube.lo);
                continue;
            }
            const int half = cube.size / 2;
            Cube children[8];
            int count = 0;
            for (int dz = 0; dz < cube.size; dz += half)
                for (int dy = 0; dy < cube.size; dy += half)
                    for (int dx = 0; dx < cube.size; dx += half) children[count++] = {cube.lo + glm::ivec3(dx, dy, dz), half, cube.outOfBand, cube.fansClear};
            visit(children, count, found);
        }
    }
};

} // namespace

namespace {
// The area of the fans that close the mesh's holes, as if each boundary loop (edges of one
// triangle, by vertex index) were closed by a fan from its centroid: where a fan crosses bricks out
// of the band whose samples lie on both of its sides, the band bake stores those bricks too.
double holesArea(const Mesh& mesh) {
    std::vector<std::pair<std::uint64_t, std::uint32_t>> edges; // (undirected key, triangle*3 + corner)
    edges.reserve(3 * mesh.triangleCount());
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t)
        for (int c = 0; c < 3; ++c) {
            const std::uint64_t a = mesh.triangles[t][c], b = mesh.triangles[t][(c + 1) % 3];
            edges.emplace_back(std::min(a, b) << 32 | std::max(a, b), std::uint32_t(3 * t + std::size_t(c)));
        }
    std::sort(edges.begin(), edges.end());
    std::vector<std::pair<std::uint32_t, std::uint32_t>> boundary; // directed, as their triangle winds them
    for (std::size_t e = 0; e < edges.size(); ++e) {
        const bool shared = (e > 0 && edges[e - 1].first == edges[e].first) || (e + 1 < edges.size() && edges[e + 1].first == edges[e].first);
        if (shared) continue;
        const std::size_t t = edges[e].second / 3;
        const int c = int(edges[e].second % 3);
        boundary.emplace_back(mesh.triangles[t][c], mesh.triangles[t][(c + 1) % 3]);
    }
    std::sort(boundary.begin(), boundary.end());
    std::vector<bool> used(boundary.size(), false);
    double area = 0.0;
    std::vector<glm::dvec3> loop;
    for (std::size_t start = 0; start < boundary.size(); ++start) {
        if (used[start]) continue;
        loop.clear();
        for (std::size_t e = start; e < boundary.size() && !used[e];) { // follows the loop until it closes or breaks
            used[e] = true;
            loop.emplace_back(mesh.positions[boundary[e].first]);
            auto next = std::lower_bound(boundary.begin(), boundary.end(), std::pair<std::uint32_t, std::uint32_t>(boundary[e].second, 0));
            while (next != boundary.end() && next->first == boundary[e].second && used[std::size_t(next - boundary.begin())]) ++next;
            e = next != boundary.end() && next->first == boundary[e].second ? std::size_t(next - boundary.begin()) : boundary.size();
        }
        glm::dvec3 centre(0.0);
        for (const glm::dvec3& p : loop) centre += p / double(loop.size());
        for (std::size_t i = 0; i < loop.size(); ++i) area += 0.5 * glm::length(glm::cross(loop[i] - centre, loop[(i + 1) % loop.size()] - centre));
    }
    return area;
}
} // namespace

std::uint64_t estimateBandBakeBytes(const Mesh& mesh, const Grid& grid, double band) {
    // The band's bricks from the surface's area: a sheet of area A with unit normal n crosses
    // A / (8h)² brick columns, each (2 band + 8 |n|₁) / 8 bricks deep on average (|n|₁ at most √3:
    // the worst orientation), half as many again for curvature and corners (the bunny's bricks
    // are 2.27 columns deep at band 3, this 2.48 × 1.5); and the bricks the holes' fans cross,
    // 8 |n|₁ / 8 deep, out of the band.
    double area = 0.0;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const glm::dvec3 a(mesh.vertex(t, 0)), b(mesh.vertex(t, 1)), c(mesh.vertex(t, 2));
        area += 0.5 * glm::length(glm::cross(b - a, c - a));
    }
    const double h = grid.voxel / mesh.unit, brickArea = double(kBrick * kBrick) * h * h;
    const glm::dvec3 brickDims = glm::ceil(glm::dvec3(grid.dims) / double(kBrick));
    const double allBricks = brickDims.x * brickDims.y * brickDims.z;
    const double bandBricks = 1.5 * area / brickArea * (2.0 * band + kBrick * std::sqrt(3.0)) / kBrick + 64.0;
    const double fanBricks = 1.5 * holesArea(mesh) / brickArea * std::sqrt(3.0);
    // Per brick its values (never copied: the fans' bricks, kept as a byte a sample until then,
    // are merged in place) and its coordinates, found, gathered and kept; the crossings of a layer
    // of rows per thread; the tree's and the scan's tables per triangle.
    const double perBrick = SparseField::kBrickSamples * sizeof(float) + 3.0 * sizeof(glm::ivec3);
    const double perFanBrick = perBrick + 2.0 * SparseField::kBrickSamples;
    const double rows = double(grid.dims.y) * kBrick * 64.0 * double(std::max(1u, std::thread::hardware_concurrency()));
    return std::uint64_t(std::min(allBricks, bandBricks) * perBrick + std::min(allBricks, fanBricks) * perFanBrick + rows +
                         double(mesh.triangleCount()) * 160.0);
}

SparseField bakeBand(const BakeContext& context, BakeResult& result, const RunControl& control) {
    const DistanceMethodPlugin& method = distanceMethod(context.settings.method);
    const SignMethodPlugin& sign = signMethod(context.sign);
    const Mesh& mesh = context.mesh;
    const Grid& grid = context.grid;
    const double band = context.settings.band;
    using Clock = std::chrono::steady_clock;
    auto since = [](Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); };

    FieldHeader header;
    header.grid = grid;
    header.source = mesh.source;
    header.background = float(band * grid.voxel);
    if (!(header.background > 0.0f) || !std::isfinite(header.background)) {
        throw Error(mesh.source + ": a band of " + std::to_string(band) + " voxels is beyond single precision at this grid's scale");
    }
    const glm::ivec3 brickDims = (grid.dims + (kBrick - 1)) / kBrick;

    // 1. The bricks in the band, and those near the fans, ordered by z, y, x.
    Clock::time_point start = Clock::now();
    const WindingCaps caps(context.topology());
    const BrickFinder finder{mesh, context.wide(), caps, grid, brickDims, band * grid.voxel / mesh.unit, context.tree};
    const std::vector<glm::ivec3> tops = finder.topCubes();
    std::vector<BrickFinder::Found> found(tops.size());
    parallelFor(tops.size(), control.phase(0.0, 0.05), [&](std::size_t n) {
        const BrickFinder::Cube top{tops[n], BrickFinder::kTop, false};
        finder.visit(&top, 1, found[n]);
    });
    BandSides sides;
    sides.background = header.background;
    for (BrickFinder::Found& f : found) {
        sides.bricks.insert(sides.bricks.end(), f.inBand.begin(), f.inBand.end());
        sides.fanBricks.insert(sides.fanBricks.end(), f.nearFans.begin(), f.nearFans.end());
        sides.sidedBricks.insert(sides.sidedBricks.end(), f.sided.begin(), f.sided.end());
        sides.clearBricks.insert(sides.clearBricks.end(), f.clearInBand.begin(), f.clearInBand.end());
        f = {};
    }
    std::sort(sides.bricks.begin(), sides.bricks.end(), brickBefore);
    std::sort(sides.fanBricks.begin(), sides.fanBricks.end(), brickBefore);
    std::sort(sides.clearBricks.begin(), sides.clearBricks.end(), brickBefore);
    std::sort(sides.sidedBricks.begin(), sides.sidedBricks.end(), [](const auto& a, const auto& b) { return brickBefore(a.first, b.first); });
    result.searchSeconds = since(start);
    result.signSeconds += result.searchSeconds;

    // 2. Their exact distances, as the dense bake measures them (samples past the grid's end: +background).
    start = Clock::now();
    // Room for the fan bricks that bandWindingSigns may add: merged in place, never moved.
    sides.bricks.reserve(sides.bricks.size() + sides.fanBricks.size());
    sides.values.reserve((sides.bricks.size() + sides.fanBricks.size()) * SparseField::kBrickSamples);
    populatePages(sides.values.data(), sides.bricks.size() * SparseField::kBrickSamples * sizeof(float), quiet(control));
    sides.values.assign(sides.bricks.size() * SparseField::kBrickSamples, header.background);
    const bool signedAsMeasured = method.bricks(context, sides.bricks.data(), sides.bricks.size(), finder.band * (1.0 + 1e-5),
                                                sides.values.data(), control.phase(0.05, 0.75));
    result.distanceSeconds = since(start);

    // 3. Sides: the band's samples (by the sign's own pass, if it has one for bricks) and every other brick's.
    start = Clock::now();
    if (!signedAsMeasured && sign.bricks) sign.bricks(context, sides.bricks.data(), sides.bricks.size(), sides.values.data(), quiet(control));
    sides.signBricks = !signedAsMeasured && !sign.bricks;
    bandWindingSigns(mesh, context.topology(), caps, grid, sides, control.phase(0.75, 1.0));
    result.signSeconds += since(start);
    return SparseField(header, {std::move(sides.bricks), std::move(sides.values), std::move(sides.insideBoxes)}, mesh.source);
}

} // namespace sdfgen
