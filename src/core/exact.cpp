#include "core/exact.hpp"
#include "core/geometry.hpp"
#include "core/parallel.hpp"
#include "core/topology.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>

namespace sdfgen {

namespace {

constexpr int kBrick = 8;   // samples per edge of a brick: one tree search each
constexpr int kQuarter = 4; // samples per edge of a brick's eighth: one candidate list each
// Where the mesh is dense at the grid's scale (many triangles per voxel), a quarter's list this
// long (packets) costs more to bound and sort than a seeded tree search per sample, which gives the
// same answer (the 1.1M-triangle subdivided bunny at res 128: distance pass 7.3 s -> 4.1 s; lists
// on the 69k-triangle bunny stay below it, and lower limits slowed it by up to 1.7x).
constexpr std::size_t kMaxCandidates = 1024;

// A candidate packet with, for each of its triangles, a lower bound of the distance that is linear
// in the sample's position: the distance to a triangle is convex, so d(p) >= d(c) + g·(p - c) with
// g the unit vector from the triangle's closest point to the centre c (the gradient there). Far
// from the surface that bound is nearly the distance itself, so a sample measures few triangles.
struct alignas(32) CandidateBound {
    simd::f8 a, gx, gy, gz; // bound(p) = a + g·p
    float key;              // bound(p) >= key + u·(p - c) on the quarter, u the field's gradient at c
    std::uint32_t packet;
};

// The samples [lo, hi) of a grid as a float box in local coordinates, with its centre and the
// distance from the centre to its farthest corner (rounded up). Sample positions grow with their
// indices and float rounding keeps that order, so the box is spanned by the corner samples.
struct SampleBox {
    Bounds box;
    glm::vec3 centre;
    double radius;
};
SampleBox sampleBox(const Mesh& mesh, const Grid& grid, const glm::ivec3& lo, const glm::ivec3& hi) {
    SampleBox s;
    s.box.min = glm::vec3(localPosition(mesh, grid, lo.x, lo.y, lo.z));
    s.box.max = glm::vec3(localPosition(mesh, grid, hi.x - 1, hi.y - 1, hi.z - 1));
    s.centre = 0.5f * (s.box.min + s.box.max);
    const glm::dvec3 half = glm::max(glm::dvec3(s.box.max) - glm::dvec3(s.centre), glm::dvec3(s.centre) - glm::dvec3(s.box.min));
    s.radius = glm::length(half) * (1.0 + 1e-6);
    return s;
}

// How far from a box of samples the nearest triangle of any of them can be, given a triangle at
// float squared distance `centreSquared` from its centre: the distance plus the radius, widened
// for the rounding of float distances (relative, and absolute near the coordinates' magnitude) so
// that no triangle that ties or beats a sample's answer in float terms is left out.
float reach(const SampleBox& s, float centreSquared) {
    const double r = std::sqrt(double(centreSquared)) + s.radius;
    const double magnitude = std::max({std::fabs(s.centre.x), std::fabs(s.centre.y), std::fabs(s.centre.z)}) + r;
    return float(r * (1.0 + 1e-5) + magnitude * 1e-6);
}

// Scans a quarter's candidates (by key) for p: the packets whose bound may reach below the best
// so far, until none can. `along` is u·(p - c); `margin` absorbs the rounding of the bounds.
// Returns the packet that holds the answer (or `seed` when it stood).
std::uint32_t scanCandidates(const WideBvh& tree, const std::vector<CandidateBound>& candidates, const glm::vec3& p, float along,
                             float margin, NearestSoFar& best, std::uint32_t seed) {
    using namespace simd;
    std::uint32_t winner = seed;
    float bound = std::sqrt(best.distanceSquared) * (1.0f + 1e-5f) + margin;
    for (const CandidateBound& c : candidates) {
        if (c.key + along > bound) break;
        const f8 lower = c.a + c.gx * p.x + c.gy * p.y + c.gz * p.z;
        if (!any(lower <= bound)) continue;
        const NearestSoFar before = best;
        scanPacket(tree.packets()[c.packet], p.x, p.y, p.z, best);
        if (best.triangle != before.triangle || best.distanceSquared != before.distanceSquared) {
            winner = c.packet;
            bound = std::sqrt(best.distanceSquared) * (1.0f + 1e-5f) + margin;
        }
    }
    return winner;
}

// The linear bounds of a packet's triangles from centre c; returns their distances from c.
simd::f8 linearBounds(const TrianglePacket& packet, const glm::vec3& c, CandidateBound& bound) {
    using namespace simd;
    f8 vx, vy, vz;
    packetClosestOffset(packet, c.x, c.y, c.z, vx, vy, vz);
    const f8 d = simd::sqrt(vx * vx + vy * vy + vz * vz);
    const f8 inverse = select(d > 0.0f, 1.0f / d, splat(0.0f));
    bound.gx = vx * inverse, bound.gy = vy * inverse, bound.gz = vz * inverse;
    bound.a = d - (bound.gx * c.x + bound.gy * c.y + bound.gz * c.z);
    return d;
}

inline simd::f8 absolute(const simd::f8& x) { return simd::max(x, -x); }
inline float lowestLane(const simd::f8& x) {
    float m = x[0];
    for (int lane = 1; lane < 8; ++lane) m = std::min(m, x[lane]);
    return m;
}

ClosestPoint closestOnTriangle(const Mesh& mesh, const glm::dvec3& p, std::uint32_t t) {
    return closestPointOnTriangle(p, glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2)));
}

// Calls store(index, i, j, k, triangle) for every sample with its nearest triangle; see computeNearest.
template <class Store>
void forEachNearest(const WideBvh& tree, const Mesh& mesh, const Grid& grid, const RunControl& control, const Store& store) {
    const glm::ivec3 dims = grid.dims;
    const glm::ivec3 bricks = (dims + (kBrick - 1)) / kBrick;
    parallelFor(std::size_t(bricks.x) * std::size_t(bricks.y) * std::size_t(bricks.z), control, [&](std::size_t b) {
        thread_local std::vector<std::uint32_t> brickList, inReach;
        thread_local std::vector<CandidateBound> unsorted, candidates;
        thread_local std::vector<std::pair<float, std::uint32_t>> byKey;
        const glm::ivec3 brick(int(b % std::size_t(bricks.x)), int(b / std::size_t(bricks.x) % std::size_t(bricks.y)),
                               int(b / (std::size_t(bricks.x) * std::size_t(bricks.y))));
        const glm::ivec3 lo = brick * kBrick, hi = glm::min(lo + kBrick, dims);
        // The brick: its centre's nearest triangle bounds every sample's distance; the packets
        // within that reach of its box.
        const SampleBox whole = sampleBox(mesh, grid, lo, hi);
        NearestSoFar centre{FLT_MAX, 0};
        const std::uint32_t centrePacket = tree.nearest(whole.centre.x, whole.centre.y, whole.centre.z, centre);
        brickList.clear();
        const float lower[3] = {whole.box.min.x, whole.box.min.y, whole.box.min.z};
        const float upper[3] = {whole.box.max.x, whole.box.max.y, whole.box.max.z};
        tree.collectLeaves(lower, upper, reach(whole, centre.distanceSquared), brickList);

        std::uint32_t seed = WideBvh::kEmpty; // the packet of the previous sample's answer
        // One seeded tree search per sample of a region.
        auto searchEach = [&](const glm::ivec3& from, const glm::ivec3& to) {
            for (int k = from.z; k < to.z; ++k) {
                for (int j = from.y; j < to.y; ++j) {
                    for (int i = from.x; i < to.x; ++i) {
                        const glm::vec3 p(localPosition(mesh, grid, i, j, k));
                        NearestSoFar best{FLT_MAX, 0};
                        if (seed != WideBvh::kEmpty) scanPacket(tree.packets()[seed], p.x, p.y, p.z, best);
                        const std::uint32_t found = tree.nearest(p.x, p.y, p.z, best);
                        if (found != WideBvh::kEmpty) seed = found;
                        store(grid.index(i, j, k), i, j, k, best.triangle);
                    }
                }
            }
        };
        for (int qz = lo.z; qz < hi.z; qz += kQuarter) {
            for (int qy = lo.y; qy < hi.y; qy += kQuarter) {
                for (int qx = lo.x; qx < hi.x; qx += kQuarter) {
                    using namespace simd;
                    const glm::ivec3 qlo(qx, qy, qz), qhi = glm::min(qlo + kQuarter, hi);
                    const SampleBox quarter = sampleBox(mesh, grid, qlo, qhi);
                    const glm::vec3 c = quarter.centre, half = 0.5f * (quarter.box.max - quarter.box.min);
                    // The quarter's centre from the tree (seeded by the brick centre's answer); then
                    // the brick's packets within the quarter's reach of its box.
                    NearestSoFar q{FLT_MAX, 0};
                    if (centrePacket != WideBvh::kEmpty) scanPacket(tree.packets()[centrePacket], c.x, c.y, c.z, q);
                    tree.nearest(c.x, c.y, c.z, q);
                    const float r = reach(quarter, q.distanceSquared);
                    // Rounding of the bounds: a few ulps of the coordinates' and the distances' magnitude.
                    const float margin = 1e-6f * (std::max({std::fabs(c.x), std::fabs(c.y), std::fabs(c.z)}) + r);
                    const float reachSquared = std::min(r * r * WideBvh::kSlack, FLT_MAX);
                    inReach.clear();
                    for (std::uint32_t packet : brickList) {
                        const Bounds& box = tree.leafBounds(packet);
                        const glm::vec3 gap = glm::max(glm::max(box.min - quarter.box.max, quarter.box.min - box.max), glm::vec3(0.0f));
                        if (glm::dot(gap, gap) <= reachSquared) inReach.push_back(packet);
                    }
                    if (inReach.size() > kMaxCandidates) {
                        searchEach(qlo, qhi);
                        continue;
                    }
                    // Their bounds from the quarter's centre, sorted by key: far from the surface the
                    // gradients of the near triangles' distances are all nearly u, the field's
                    // gradient at the centre, so a sample stops soon after the triangles that can
                    // be its nearest.
                    const ClosestPoint toCentre = closestOnTriangle(mesh, glm::dvec3(c), q.triangle);
                    const double centreDistance = std::sqrt(toCentre.distanceSquared);
                    const glm::vec3 u = centreDistance > 0.0 ? glm::vec3((glm::dvec3(c) - toCentre.point) / centreDistance) : glm::vec3(0.0f);
                    unsorted.resize(inReach.size());
                    candidates.resize(inReach.size());
                    byKey.resize(inReach.size());
                    for (std::size_t n = 0; n < inReach.size(); ++n) {
                        CandidateBound& bound = unsorted[n];
                        const f8 d = linearBounds(tree.packets()[inReach[n]], c, bound);
                        // min over the quarter of d + (g - u)·(p - c), lowest lane
                        bound.key = lowestLane(d - (absolute(bound.gx - u.x) * half.x + absolute(bound.gy - u.y) * half.y +
                                                    absolute(bound.gz - u.z) * half.z));
                        bound.packet = inReach[n];
                        byKey[n] = {bound.key, std::uint32_t(n)};
                    }
                    std::sort(byKey.begin(), byKey.end());
                    for (std::size_t n = 0; n < byKey.size(); ++n) candidates[n] = unsorted[byKey[n].second];
                    for (int k = qlo.z; k < qhi.z; ++k) {
                        for (int j = qlo.y; j < qhi.y; ++j) {
                            for (int i = qlo.x; i < qhi.x; ++i) {
                                const glm::vec3 p(localPosition(mesh, grid, i, j, k));
                                NearestSoFar best{FLT_MAX, 0};
                                if (seed != WideBvh::kEmpty) scanPacket(tree.packets()[seed], p.x, p.y, p.z, best);
                                const float along = u.x * (p.x - c.x) + u.y * (p.y - c.y) + u.z * (p.z - c.z);
                                seed = scanCandidates(tree, candidates, p, along, margin, best, seed);
                                store(grid.index(i, j, k), i, j, k, best.triangle);
                            }
                        }
                    }
                }
            }
        }
    });
}

// The distance (world units) from p to triangle t, negated where the pseudonormal of its closest
// feature points away from p (the other way round when flipped), when `pseudonormal` is given.
float sampleValue(const Mesh& mesh, const MeshTopology* pseudonormal, bool flipped, const glm::dvec3& p, std::uint32_t t) {
    const ClosestPoint closest = closestOnTriangle(mesh, p, t);
    const float distance = float(std::sqrt(closest.distanceSquared) * mesh.unit);
    const bool inside = pseudonormal && (glm::dot(p - closest.point, pseudonormal->pseudonormal(t, closest.feature)) < 0.0) != flipped;
    return inside ? -distance : distance;
}

} // namespace

NearestField computeNearest(const Mesh& mesh, const WideBvh& tree, const Grid& grid, const RunControl& control) {
    NearestField result;
    result.distance.resize(grid.sampleCount());
    result.triangle.resize(grid.sampleCount());
    forEachNearest(tree, mesh, grid, control, [&](std::size_t index, int i, int j, int k, std::uint32_t t) {
        const ClosestPoint closest = closestOnTriangle(mesh, localPosition(mesh, grid, i, j, k), t);
        result.distance[index] = float(std::sqrt(closest.distanceSquared) * mesh.unit);
        result.triangle[index] = t;
    });
    return result;
}

NearestField computeNearest(const Mesh& mesh, const Bvh& tree, const Grid& grid, const RunControl& control) {
    return computeNearest(mesh, WideBvh(mesh, tree), grid, control);
}

void computeExactField(const Mesh& mesh, const WideBvh& tree, const Grid& grid, const MeshTopology* pseudonormal, bool flipped,
                       float* values, const RunControl& control) {
    forEachNearest(tree, mesh, grid, control, [&](std::size_t index, int i, int j, int k, std::uint32_t t) {
        values[index] = sampleValue(mesh, pseudonormal, flipped, localPosition(mesh, grid, i, j, k), t);
    });
}

float exactSignedSample(const Mesh& mesh, const WideBvh& tree, const MeshTopology& topology, bool flipped, const glm::dvec3& p,
                        std::uint32_t& hint) {
    return sampleValue(mesh, &topology, flipped, p, nearestTriangle(tree, glm::vec3(p), hint));
}

std::vector<std::uint8_t> insideByClosestFeature(const Mesh& mesh, const WideBvh& tree, const Grid& grid, const MeshTopology& topology,
                                                 bool flipped, const RunControl& control) {
    std::vector<std::uint8_t> inside(grid.sampleCount());
    forEachNearest(tree, mesh, grid, control, [&](std::size_t index, int i, int j, int k, std::uint32_t t) {
        const glm::dvec3 p = localPosition(mesh, grid, i, j, k);
        const ClosestPoint closest = closestOnTriangle(mesh, p, t);
        inside[index] = (glm::dot(p - closest.point, topology.pseudonormal(t, closest.feature)) < 0.0) != flipped;
    });
    return inside;
}

std::uint32_t nearestTriangle(const WideBvh& tree, const glm::vec3& p, std::uint32_t& hint) {
    NearestSoFar best{FLT_MAX, 0};
    if (hint != WideBvh::kEmpty) scanPacket(tree.packets()[hint], p.x, p.y, p.z, best);
    const std::uint32_t winner = tree.nearest(p.x, p.y, p.z, best);
    if (winner != WideBvh::kEmpty) hint = winner;
    return best.triangle;
}

Field computeBruteForce(const Mesh& mesh, const Grid& grid, const RunControl& control) {
    Field field;
    field.source = mesh.source;
    field.grid = grid;
    field.values.resize(grid.sampleCount());
    std::vector<glm::dvec3> corners(3 * mesh.triangleCount());
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        for (int c = 0; c < 3; ++c) corners[3 * t + std::size_t(c)] = glm::dvec3(mesh.vertex(t, c));
    }
    const std::size_t rows = std::size_t(grid.dims.y) * std::size_t(grid.dims.z);
    parallelFor(rows, control, [&](std::size_t row) {
        const int j = int(row % std::size_t(grid.dims.y)), k = int(row / std::size_t(grid.dims.y));
        for (int i = 0; i < grid.dims.x; ++i) {
            const glm::dvec3 p = localPosition(mesh, grid, i, j, k);
            double nearest = std::numeric_limits<double>::infinity(), angle = 0.0;
            for (std::size_t c = 0; c < corners.size(); c += 3) {
                nearest = std::min(nearest, closestPointOnTriangle(p, corners[c], corners[c + 1], corners[c + 2]).distanceSquared);
                angle += solidAngle(p, corners[c], corners[c + 1], corners[c + 2]);
            }
            const double distance = std::sqrt(nearest) * mesh.unit;
            field.values[grid.index(i, j, k)] = float(angle / (4.0 * M_PI) > 0.5 ? -distance : distance);
        }
    });
    return field;
}

} // namespace sdfgen
