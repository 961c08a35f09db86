#include "core/kdtree.hpp"

#include <glm/common.hpp>
#include <algorithm>
#include <cmath>
#include <limits>

namespace sdfgen {

namespace {

constexpr int kBins = 16;
constexpr float kTraversalCost = 1.0f; // relative to one ray/triangle test

Bounds emptyBounds() {
    return {glm::vec3(std::numeric_limits<float>::max()), glm::vec3(-std::numeric_limits<float>::max())};
}
void grow(Bounds& b, const Bounds& other) {
    b.min = glm::min(b.min, other.min);
    b.max = glm::max(b.max, other.max);
}
float halfArea(const Bounds& b) {
    const glm::vec3 e = glm::max(b.max - b.min, glm::vec3(0.0f));
    return e.x * e.y + e.y * e.z + e.z * e.x;
}

} // namespace

KdTree::KdTree(const Mesh& mesh) {
    const std::size_t n = mesh.triangleCount();
    std::vector<Bounds> boxes(n);
    std::vector<glm::vec3> centroids(n);
    std::vector<std::uint32_t> order(n);
    for (std::size_t i = 0; i < n; ++i) {
        const glm::vec3 a = mesh.vertex(i, 0), b = mesh.vertex(i, 1), c = mesh.vertex(i, 2);
        boxes[i] = {glm::min(a, glm::min(b, c)), glm::max(a, glm::max(b, c))};
        centroids[i] = (boxes[i].min + boxes[i].max) * 0.5f;
        order[i] = std::uint32_t(i);
    }
    nodes_.reserve(2 * n);
    triangles_.reserve(n);
    triangleIds_.reserve(n);
    build(order, 0, n, centroids, boxes, 0);
    bounds_ = {glm::vec3(nodes_[0].min[0], nodes_[0].min[1], nodes_[0].min[2]),
               glm::vec3(nodes_[0].max[0], nodes_[0].max[1], nodes_[0].max[2])};
    for (std::uint32_t id : triangleIds_) {
        triangles_.push_back(prepareTriangle(mesh.vertex(id, 0), mesh.vertex(id, 1), mesh.vertex(id, 2)));
    }
}

std::uint32_t KdTree::build(std::vector<std::uint32_t>& order, std::size_t begin, std::size_t end,
                            const std::vector<glm::vec3>& centroids, const std::vector<Bounds>& boxes, int depth) {
    depth_ = std::max(depth_, depth);
    Bounds box = emptyBounds(), centroidBox = emptyBounds();
    for (std::size_t i = begin; i < end; ++i) {
        grow(box, boxes[order[i]]);
        grow(centroidBox, {centroids[order[i]], centroids[order[i]]});
    }
    const std::uint32_t nodeIndex = std::uint32_t(nodes_.size());
    nodes_.push_back({{box.min.x, box.min.y, box.min.z}, {box.max.x, box.max.y, box.max.z}, 0, 0, 0});
    const std::size_t count = end - begin;

    auto makeLeaf = [&] {
        nodes_[nodeIndex].index = std::uint32_t(triangleIds_.size());
        nodes_[nodeIndex].count = std::uint16_t(count);
        triangleIds_.insert(triangleIds_.end(), order.begin() + std::ptrdiff_t(begin), order.begin() + std::ptrdiff_t(end));
        return nodeIndex;
    };
    if (count <= 1 || depth >= kMaxDepth) return makeLeaf();

    // Binned SAH: try kBins - 1 planes on each axis, keep the cheapest split.
    int bestAxis = -1, bestPlane = 0;
    float bestCost = std::numeric_limits<float>::max();
    const glm::vec3 centroidExtent = centroidBox.max - centroidBox.min;
    for (int axis = 0; axis < 3; ++axis) {
        if (!(centroidExtent[axis] > 0.0f)) continue;
        const float scale = kBins / centroidExtent[axis];
        Bounds binBox[kBins];
        std::size_t binCount[kBins] = {};
        for (Bounds& b : binBox) b = emptyBounds();
        for (std::size_t i = begin; i < end; ++i) {
            const std::uint32_t t = order[i];
            const int bin = std::min(kBins - 1, int((centroids[t][axis] - centroidBox.min[axis]) * scale));
            ++binCount[bin];
            grow(binBox[bin], boxes[t]);
        }
        float rightArea[kBins];
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
            const float cost = halfArea(acc) * float(accCount) + rightArea[plane] * float(rightCount[plane]);
            if (cost < bestCost) {
                bestCost = cost;
                bestAxis = axis;
                bestPlane = plane;
            }
        }
    }

    std::size_t middle;
    int splitAxis;
    if (bestAxis >= 0) {
        const float leafCost = float(count);
        const float splitCost = kTraversalCost + bestCost / halfArea(box);
        if (splitCost >= leafCost && count <= std::size_t(kMaxLeafSize)) return makeLeaf();
        const float scale = kBins / centroidExtent[bestAxis];
        const float lo = centroidBox.min[bestAxis];
        auto* split = std::partition(order.data() + begin, order.data() + end, [&](std::uint32_t t) {
            return std::min(kBins - 1, int((centroids[t][bestAxis] - lo) * scale)) < bestPlane;
        });
        middle = std::size_t(split - order.data());
        splitAxis = bestAxis;
    } else {
        // All centroids coincide: no plane separates them, so halve the list to bound the leaf size.
        if (count <= std::size_t(kMaxLeafSize)) return makeLeaf();
        middle = begin + count / 2;
        splitAxis = 0;
    }
    build(order, begin, middle, centroids, boxes, depth + 1);
    const std::uint32_t second = build(order, middle, end, centroids, boxes, depth + 1);
    nodes_[nodeIndex].index = second;
    nodes_[nodeIndex].axis = std::uint16_t(splitAxis);
    return nodeIndex;
}

void KdTree::intersect(RayPacket& packet) const {
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

bool KdTree::intersect(const glm::vec3& origin, const glm::vec3& direction, float tMax, RayHit& hit) const {
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

} // namespace sdfgen
