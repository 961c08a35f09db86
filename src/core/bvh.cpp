#include "core/bvh.hpp"
#include "core/duplicates.hpp"

#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <algorithm>
#include <cmath>
#include <limits>

namespace sdfgen {

namespace {

constexpr int kBins = 16;
constexpr std::size_t kParallelBuild = 4096; // triangles below which a subtree is built serially
constexpr double kTraversalCost = 1.0; // relative to one ray/triangle test

Bounds emptyBounds() {
    return {glm::vec3(std::numeric_limits<float>::max()), glm::vec3(-std::numeric_limits<float>::max())};
}
void grow(Bounds& b, const Bounds& other) {
    b.min = glm::min(b.min, other.min);
    b.max = glm::max(b.max, other.max);
}
// In double: float extents overflow for coordinates beyond ±1.7e38 and products underflow below
// 1e-19, and the surface area heuristic must still compare them.
double halfArea(const Bounds& b) {
    const glm::dvec3 e = glm::max(glm::dvec3(b.max) - glm::dvec3(b.min), glm::dvec3(0.0));
    return e.x * e.y + e.y * e.z + e.z * e.x;
}

} // namespace

Bvh::Bvh(const Mesh& mesh, const RunControl& control) {
    // Exact copies of a triangle have the same distance and the same hits, and a stack of them
    // would make every query that reaches it visit each one: the tree holds the first copy only
    // (the lowest index, so the tie rule of nearest() is unchanged).
    const TriangleCopies copies = findTriangleCopies(mesh);
    const std::size_t n = copies.unique.size();
    std::vector<Bounds> boxes(n);
    std::vector<glm::vec3> centroids(n);
    std::vector<std::uint32_t> order(n);
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t t = copies.unique[i];
        const glm::vec3 a = mesh.vertex(t, 0), b = mesh.vertex(t, 1), c = mesh.vertex(t, 2);
        boxes[i] = {glm::min(a, glm::min(b, c)), glm::max(a, glm::max(b, c))};
        // Half of each before adding: the sum of two coordinates near the float limit overflows.
        centroids[i] = boxes[i].min * 0.5f + boxes[i].max * 0.5f;
        order[i] = std::uint32_t(i);
    }
    Subtree tree;
    tree.nodes.reserve(2 * n);
    tree.ids.reserve(n);
    ProgressCounter progress(control, n);
    const BuildInput input{centroids, boxes, progress};
    tbb::task_arena(control.threads > 0 ? control.threads : tbb::task_arena::automatic).execute([&] {
        build(tree, order, 0, n, input, 0);
    });
    progress.finish();
    nodes_ = std::move(tree.nodes);
    triangleIds_ = std::move(tree.ids);
    depth_ = tree.depth;
    triangles_.reserve(n);
    for (std::uint32_t& id : triangleIds_) id = copies.unique[id];
    bounds_ = {glm::vec3(nodes_[0].min[0], nodes_[0].min[1], nodes_[0].min[2]),
               glm::vec3(nodes_[0].max[0], nodes_[0].max[1], nodes_[0].max[2])};
    leafSlot_.resize(mesh.triangleCount());
    distanceTriangles_.reserve(n);
    for (std::size_t slot = 0; slot < n; ++slot) {
        const std::uint32_t id = triangleIds_[slot];
        leafSlot_[id] = std::uint32_t(slot);
        const glm::vec3 a = mesh.vertex(id, 0), b = mesh.vertex(id, 1), c = mesh.vertex(id, 2);
        triangles_.push_back(prepareTriangle(a, b, c));
        const glm::vec3 ab = b - a, ac = c - a, bc = c - b, ca = a - c;
        const glm::vec3 normal = mesh.faceNormals[id];
        auto inverse = [](const glm::vec3& e) {
            const float len2 = glm::dot(e, e);
            return len2 > 0.0f ? 1.0f / len2 : 0.0f;
        };
        distanceTriangles_.push_back({a, ab, ac, normal, glm::cross(normal, ab), glm::cross(normal, bc),
                                      glm::cross(normal, ca), inverse(ab), inverse(bc), inverse(ca)});
    }
    copies_.assign(mesh.triangleCount(), 0);
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) leafSlot_[t] = leafSlot_[copies.first[t]];
    for (std::size_t i = 0; i < n; ++i) copies_[copies.unique[i]] = copies.count[i];
}

std::uint32_t Bvh::build(Subtree& out, std::vector<std::uint32_t>& order, std::size_t begin, std::size_t end,
                         const BuildInput& input, int depth) {
    const std::vector<glm::vec3>& centroids = input.centroids;
    const std::vector<Bounds>& boxes = input.boxes;
    input.progress.checkCancel();
    std::vector<Node>& nodes = out.nodes;
    std::vector<std::uint32_t>& ids = out.ids;
    out.depth = std::max(out.depth, depth);
    Bounds box = emptyBounds(), centroidBox = emptyBounds();
    for (std::size_t i = begin; i < end; ++i) {
        grow(box, boxes[order[i]]);
        grow(centroidBox, {centroids[order[i]], centroids[order[i]]});
    }
    const std::uint32_t nodeIndex = std::uint32_t(nodes.size());
    nodes.push_back({{box.min.x, box.min.y, box.min.z}, {box.max.x, box.max.y, box.max.z}, 0, 0, 0});
    const std::size_t count = end - begin;

    auto makeLeaf = [&] {
        nodes[nodeIndex].index = std::uint32_t(ids.size());
        nodes[nodeIndex].count = std::uint16_t(count);
        ids.insert(ids.end(), order.begin() + std::ptrdiff_t(begin), order.begin() + std::ptrdiff_t(end));
        input.progress.add(count);
        return nodeIndex;
    };
    auto children = [&](std::size_t middle, int axis) {
        nodes[nodeIndex].axis = std::uint16_t(axis);
        if (count < kParallelBuild) {
            build(out, order, begin, middle, input, depth + 1);
            nodes[nodeIndex].index = build(out, order, middle, end, input, depth + 1);
            return nodeIndex;
        }
        // The halves touch disjoint ranges of `order`; the second is built apart and appended.
        Subtree second;
        tbb::parallel_invoke([&] { build(out, order, begin, middle, input, depth + 1); },
                             [&] { build(second, order, middle, end, input, depth + 1); });
        const std::uint32_t nodeBase = std::uint32_t(nodes.size()), idBase = std::uint32_t(ids.size());
        for (Node node : second.nodes) {
            node.index += node.count == 0 ? nodeBase : idBase;
            nodes.push_back(node);
        }
        ids.insert(ids.end(), second.ids.begin(), second.ids.end());
        out.depth = std::max(out.depth, second.depth);
        nodes[nodeIndex].index = nodeBase;
        return nodeIndex;
    };
    auto buildMedian = [&] {
        if (count <= std::size_t(kMaxLeafSize)) return makeLeaf();
        int axis = 0;
        for (int a = 1; a < 3; ++a) {
            if (double(centroidBox.max[a]) - centroidBox.min[a] > double(centroidBox.max[axis]) - centroidBox.min[axis]) axis = a;
        }
        const std::size_t middle = begin + count / 2;
        std::nth_element(order.begin() + std::ptrdiff_t(begin), order.begin() + std::ptrdiff_t(middle),
                         order.begin() + std::ptrdiff_t(end), [&](std::uint32_t l, std::uint32_t r) {
                             return centroids[l][axis] != centroids[r][axis] ? centroids[l][axis] < centroids[r][axis] : l < r;
                         });
        return children(middle, axis);
    };
    if (count <= 1) return makeLeaf();
    // The SAH may peel off one triangle per level (exponentially spaced centroids do that), so once
    // halving at every level left is just enough to reach kMaxLeafSize before kMaxDepth, the node
    // splits at the median instead: depth and leaf size stay bounded on any input.
    int levelsNeeded = 0;
    while ((std::size_t(kMaxLeafSize) << levelsNeeded) < count) ++levelsNeeded;
    if (levelsNeeded >= kMaxDepth - depth - 1) return buildMedian();

    // Binned SAH: try kBins - 1 planes on each axis, keep the cheapest split.
    int bestAxis = -1, bestPlane = 0;
    double bestCost = std::numeric_limits<double>::max();
    const glm::dvec3 centroidExtent = glm::dvec3(centroidBox.max) - glm::dvec3(centroidBox.min); // no float overflow
    // Bins in double, clamped before the conversion to int: at any float span (subnormal extents
    // included) a bin index is always a valid one, never int(inf) or int(NaN).
    auto binOf = [&](float centroid, float lo, double scale) {
        const double bin = (double(centroid) - double(lo)) * scale;
        return bin >= double(kBins - 1) ? kBins - 1 : bin > 0.0 ? int(bin) : 0;
    };
    for (int axis = 0; axis < 3; ++axis) {
        if (!(centroidExtent[axis] > 0.0)) continue;
        const double scale = kBins / centroidExtent[axis];
        if (!std::isfinite(scale)) continue;
        Bounds binBox[kBins];
        std::size_t binCount[kBins] = {};
        for (Bounds& b : binBox) b = emptyBounds();
        for (std::size_t i = begin; i < end; ++i) {
            const std::uint32_t t = order[i];
            const int bin = binOf(centroids[t][axis], centroidBox.min[axis], scale);
            ++binCount[bin];
            grow(binBox[bin], boxes[t]);
        }
        double rightArea[kBins];
        std::size_t rightCount[kBins];
        Bounds acc = emptyBounds();
        std::size_t accCount = 0;
        for (int b = kBins - 1; b > 0; --b) {
            grow(acc, binBox[b]);
            accCount += binCount[b];
            rightArea[b] = halfArea(acc);
            rightCount[b] = accCount;
        }
        acc = emptyBounds();
        accCount = 0;
        for (int plane = 1; plane < kBins; ++plane) {
            grow(acc, binBox[plane - 1]);
            accCount += binCount[plane - 1];
            if (accCount == 0 || rightCount[plane] == 0) continue;
            const double cost = halfArea(acc) * double(accCount) + rightArea[plane] * double(rightCount[plane]);
            if (cost < bestCost) {
                bestCost = cost;
                bestAxis = axis;
                bestPlane = plane;
            }
        }
    }

    if (bestAxis < 0) return buildMedian(); // all centroids coincide: no plane separates them
    // A box of zero area (all triangles in one axis-aligned plane segment) splits by count alone.
    const double area = halfArea(box);
    const double splitCost = area > 0.0 ? kTraversalCost + bestCost / area : kTraversalCost;
    if (splitCost >= double(count) && count <= std::size_t(kMaxLeafSize)) return makeLeaf();
    const double scale = kBins / centroidExtent[bestAxis];
    const float lo = centroidBox.min[bestAxis];
    auto* split = std::partition(order.data() + begin, order.data() + end,
                                 [&](std::uint32_t t) { return binOf(centroids[t][bestAxis], lo, scale) < bestPlane; });
    return children(std::size_t(split - order.data()), bestAxis);
}

// The ray method's hot loop, compiled twice by GCC (AVX2 and baseline) and picked when the library
// loads, so the portable build keeps AVX2 speed (Clang refuses the baseline clone's eight-lane
// arguments, so it compiles one copy for the build's flags). Same IEEE operations, same bits.
#if defined(__GNUC__) && !defined(__clang__) && (defined(__x86_64__) || defined(__i386__)) && !defined(__AVX2__)
__attribute__((target_clones("avx2", "default")))
#endif
void Bvh::intersect(RayPacket& packet) const {
    using namespace simd;
    const glm::vec3 d = packet.direction;
    // A zero component becomes a tiny one so slab distances stay finite (no 0 * inf).
    auto inverse = [](float x) { return 1.0f / (x != 0.0f ? x : std::copysign(1e-20f, x)); };
    const glm::vec3 invD(inverse(d.x), inverse(d.y), inverse(d.z));
    const bool negative[3] = {d.x < 0.0f, d.y < 0.0f, d.z < 0.0f};
    // Slab distances are rounded; widening the far one by 2 gamma(3) keeps boxes that the ray
    // grazes exactly (Ize 2013), so the tree never misses a hit brute force would find.
    constexpr float kFarScale = 1.0f + 2.0f * (3.0f * 0x1p-24f) / (1.0f - 3.0f * 0x1p-24f);
    const f8 ox = packet.ox, oy = packet.oy, oz = packet.oz;
    f8 tMax = packet.tMax;
    i8 hit = splat(0), triangle = splat(0), backFace = splat(0);

    std::uint32_t stack[kMaxDepth + 2];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node& node = nodes_[stack[--top]];
        const float* nearX = negative[0] ? node.max : node.min;
        const float* farX = negative[0] ? node.min : node.max;
        const float* nearY = negative[1] ? node.max : node.min;
        const float* farY = negative[1] ? node.min : node.max;
        const float* nearZ = negative[2] ? node.max : node.min;
        const float* farZ = negative[2] ? node.min : node.max;
        const f8 tNear = max(max((nearX[0] - ox) * invD.x, (nearY[1] - oy) * invD.y),
                             max((nearZ[2] - oz) * invD.z, splat(0.0f)));
        const f8 tFar = min(min((farX[0] - ox) * invD.x, (farY[1] - oy) * invD.y), (farZ[2] - oz) * invD.z);
        if (!any(tNear <= min(tFar * kFarScale, tMax))) continue;

        if (node.count > 0) {
            for (std::uint32_t i = node.index, last = node.index + node.count; i < last; ++i) {
                f8 t;
                bool back;
                const i8 mask = intersectTriangle(ox, oy, oz, d, triangles_[i], tMax, t, back);
                if (!any(mask)) continue;
                tMax = select(mask, t, tMax);
                triangle = select(mask, splat(std::int32_t(triangleIds_[i])), triangle);
                backFace = select(mask, splat(back ? -1 : 0), backFace);
                hit |= mask;
            }
            continue;
        }
        const std::uint32_t first = std::uint32_t(&node - nodes_.data()) + 1;
        const std::uint32_t second = node.index;
        // Visit the child on the ray's side of the split first so that early hits shrink tMax.
        if (negative[node.axis]) {
            stack[top++] = first;
            stack[top++] = second;
        } else {
            stack[top++] = second;
            stack[top++] = first;
        }
    }
    packet.tMax = select(hit, tMax, packet.tMax);
    packet.hit = hit;
    packet.triangle = triangle;
    packet.backFace = backFace;
}

bool Bvh::intersect(const glm::vec3& origin, const glm::vec3& direction, float tMax, RayHit& hit) const {
    RayPacket packet;
    packet.ox = simd::splat(origin.x);
    packet.oy = simd::splat(origin.y);
    packet.oz = simd::splat(origin.z);
    packet.direction = direction;
    packet.tMax = simd::splat(-1.0f); // only lane 0 is active
    packet.tMax[0] = tMax;
    intersect(packet);
    if (!packet.hit[0]) return false;
    hit.t = packet.tMax[0];
    hit.triangle = std::uint32_t(packet.triangle[0]);
    hit.backFace = packet.backFace[0] != 0;
    return true;
}


simd::f8 Bvh::distanceSquared(const simd::f8& px, const simd::f8& py, const simd::f8& pz, const DistanceTriangle& t) const {
    using namespace simd;
    auto dot = [](const f8& x, const f8& y, const f8& z, const glm::vec3& v) { return x * v.x + y * v.y + z * v.z; };
    auto clamp01 = [](const f8& x) { return min(max(x, splat(0.0f)), splat(1.0f)); };
    // Vectors from the corners a, b, c to the points.
    const f8 ax = px - t.a.x, ay = py - t.a.y, az = pz - t.a.z;
    const f8 bx = ax - t.ab.x, by = ay - t.ab.y, bz = az - t.ab.z;
    const f8 cx = ax - t.ac.x, cy = ay - t.ac.y, cz = az - t.ac.z;
    // Inside the prism over the face: the distance is the height above the plane.
    const i8 inside = (dot(ax, ay, az, t.inAB) >= 0.0f) & (dot(bx, by, bz, t.inBC) >= 0.0f) & (dot(cx, cy, cz, t.inCA) >= 0.0f);
    const f8 height = dot(ax, ay, az, t.normal);
    // Otherwise the nearest of the three edges (as segments).
    const glm::vec3 bc = t.ac - t.ab, ca = -t.ac;
    auto segment = [&](const f8& x, const f8& y, const f8& z, const glm::vec3& e, float invLength2) {
        const f8 s = clamp01(dot(x, y, z, e) * invLength2);
        const f8 dx = x - s * e.x, dy = y - s * e.y, dz = z - s * e.z;
        return dx * dx + dy * dy + dz * dz;
    };
    const f8 edges = min(segment(ax, ay, az, t.ab, t.invAB), min(segment(bx, by, bz, bc, t.invBC), segment(cx, cy, cz, ca, t.invCA)));
    return select(inside, height * height, edges);
}

simd::f8 Bvh::distanceSquared(const simd::f8& px, const simd::f8& py, const simd::f8& pz, std::uint32_t triangle) const {
    return distanceSquared(px, py, pz, distanceTriangles_[leafSlot_[triangle]]);
}

void Bvh::nearest(PointPacket& packet) const {
    using namespace simd;
    const f8 px = packet.px, py = packet.py, pz = packet.pz;
    f8 best = packet.bestSquared;
    i8 triangle = packet.triangle;
    auto boxDistanceSquared = [&](const Node& node) {
        const f8 dx = max(max(node.min[0] - px, px - node.max[0]), splat(0.0f));
        const f8 dy = max(max(node.min[1] - py, py - node.max[1]), splat(0.0f));
        const f8 dz = max(max(node.min[2] - pz, pz - node.max[2]), splat(0.0f));
        return dx * dx + dy * dy + dz * dz;
    };
    auto lowest = [](const f8& v) {
        float m = v[0];
        for (int lane = 1; lane < 8; ++lane) m = std::min(m, v[lane]);
        return m;
    };

    // Each entry keeps its box distances so a pop re-checks them against the shrunken bounds.
    struct Entry {
        f8 distance;
        std::uint32_t node;
    };
    Entry stack[kMaxDepth + 2];
    int top = 0;
    stack[top++] = {boxDistanceSquared(nodes_[0]), 0};
    while (top > 0) {
        const Entry entry = stack[--top];
        // Ties are explored and go to the lower triangle index, so the answer is the same whatever
        // the seeds and the traversal order: a point query at a sample's position finds the sample's
        // triangle.
        if (!any(entry.distance <= best)) continue;
        const Node& node = nodes_[entry.node];
        if (node.count > 0) {
            for (std::uint32_t i = node.index, last = node.index + node.count; i < last; ++i) {
                const f8 d = distanceSquared(px, py, pz, distanceTriangles_[i]);
                const i8 id = splat(std::int32_t(triangleIds_[i]));
                const i8 closer = (d < best) | ((d == best) & (id < triangle));
                if (!any(closer)) continue;
                best = select(closer, d, best);
                triangle = select(closer, id, triangle);
            }
            continue;
        }
        const std::uint32_t first = entry.node + 1, second = node.index;
        const f8 dFirst = boxDistanceSquared(nodes_[first]), dSecond = boxDistanceSquared(nodes_[second]);
        // Nearer child on top of the stack: its triangles tighten the bounds before the other is tried.
        if (lowest(dFirst) <= lowest(dSecond)) {
            stack[top++] = {dSecond, second};
            stack[top++] = {dFirst, first};
        } else {
            stack[top++] = {dFirst, first};
            stack[top++] = {dSecond, second};
        }
    }
    packet.bestSquared = best;
    packet.triangle = triangle;
}

} // namespace sdfgen
