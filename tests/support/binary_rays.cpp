#include "support/binary_rays.hpp"
#include "core/accel/ray.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace sdfgen::test {

void intersect(const Mesh& mesh, const Bvh& tree, RayPacket& packet) {
    using namespace simd;
    const glm::vec3 d = packet.direction;
    // A zero component becomes a tiny one so slab distances stay finite (no 0 * inf).
    auto inverse = [](float x) { return 1.0f / (x != 0.0f ? x : std::copysign(1e-20f, x)); };
    const glm::vec3 invD(inverse(d.x), inverse(d.y), inverse(d.z));
    const bool negative[3] = {d.x < 0.0f, d.y < 0.0f, d.z < 0.0f};
    // Slab distances are rounded; widening the farCorner one by 2 gamma(3) keeps boxes that the ray
    // grazes exactly (Ize 2013), so the tree never misses a hit brute force would find.
    constexpr float kFarScale = 1.0f + 2.0f * (3.0f * 0x1p-24f) / (1.0f - 3.0f * 0x1p-24f);
    const f8 ox = packet.ox, oy = packet.oy, oz = packet.oz;
    f8 tMax = packet.tMax;
    i8 hit = splat(0), triangle = splat(0), backFace = splat(0);

    std::uint32_t stack[Bvh::kMaxDepth + 2];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Bvh::NodeView node = tree.node(stack[--top]);
        const glm::vec3 nearCorner(negative[0] ? node.box.max.x : node.box.min.x, negative[1] ? node.box.max.y : node.box.min.y,
                             negative[2] ? node.box.max.z : node.box.min.z);
        const glm::vec3 farCorner(negative[0] ? node.box.min.x : node.box.max.x, negative[1] ? node.box.min.y : node.box.max.y,
                            negative[2] ? node.box.min.z : node.box.max.z);
        const f8 tNear = max(max((nearCorner.x - ox) * invD.x, (nearCorner.y - oy) * invD.y), max((nearCorner.z - oz) * invD.z, splat(0.0f)));
        const f8 tFar = min(min((farCorner.x - ox) * invD.x, (farCorner.y - oy) * invD.y), (farCorner.z - oz) * invD.z);
        if (!any(tNear <= min(tFar * kFarScale, tMax))) continue;

        if (node.count > 0) {
            for (std::uint32_t i = 0; i < node.count; ++i) {
                const std::uint32_t id = node.triangles[i];
                const PreparedTriangle prepared = prepareTriangle(mesh.vertex(id, 0), mesh.vertex(id, 1), mesh.vertex(id, 2));
                f8 t;
                bool back;
                const i8 mask = intersectTriangle(ox, oy, oz, d, prepared, tMax, t, back);
                if (!any(mask)) continue;
                tMax = select(mask, t, tMax);
                triangle = select(mask, splat(std::int32_t(id)), triangle);
                backFace = select(mask, splat(back ? -1 : 0), backFace);
                hit |= mask;
            }
            continue;
        }
        // Visit the child on the ray's side of the split first so that early hits shrink tMax.
        if (negative[node.axis]) {
            stack[top++] = node.first;
            stack[top++] = node.second;
        } else {
            stack[top++] = node.second;
            stack[top++] = node.first;
        }
    }
    packet.tMax = select(hit, tMax, packet.tMax);
    packet.hit = hit;
    packet.triangle = triangle;
    packet.backFace = backFace;
}

bool intersect(const Mesh& mesh, const Bvh& tree, const glm::vec3& origin, const glm::vec3& direction, float tMax,
               RayHit& hit) {
    RayPacket packet;
    packet.ox = simd::splat(origin.x);
    packet.oy = simd::splat(origin.y);
    packet.oz = simd::splat(origin.z);
    packet.direction = direction;
    packet.tMax = simd::splat(-1.0f); // only lane 0 is active
    packet.tMax[0] = tMax;
    intersect(mesh, tree, packet);
    if (!packet.hit[0]) return false;
    hit.t = packet.tMax[0];
    hit.triangle = std::uint32_t(packet.triangle[0]);
    hit.backFace = packet.backFace[0] != 0;
    return true;
}

int treeDepth(const Bvh& tree) {
    int deepest = 0;
    std::vector<std::pair<std::uint32_t, int>> pending{{0, 0}};
    while (!pending.empty()) {
        const auto [index, depth] = pending.back();
        pending.pop_back();
        deepest = std::max(deepest, depth);
        const Bvh::NodeView n = tree.node(index);
        if (n.count == 0) pending.push_back({n.first, depth + 1}), pending.push_back({n.second, depth + 1});
    }
    return deepest;
}

} // namespace sdfgen::test
