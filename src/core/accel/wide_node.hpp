#pragma once
// The 8-wide node of the trees collapsed from the binary Bvh, core/accel/wide_bvh.hpp (distances) and
// core/accel/ray_tree.hpp (rays): its children's boxes as structure-of-arrays, so that one AVX2
// instruction tests all eight, and their slots. What a leaf slot points at is the tree's own.
#include "core/simd/simd.hpp"
#include "sdfgen/mesh.hpp"

#include <cstdint>
#include <limits>

namespace sdfgen {

struct alignas(32) WideNode {
    static constexpr int kWidth = 8;
    // A child slot: an inner node's index, or kLeaf | the index of a leaf in the tree's own array.
    static constexpr std::uint32_t kLeaf = 0x80000000u;
    static constexpr std::uint32_t kEmpty = 0xffffffffu;

    simd::f8 minX, minY, minZ, maxX, maxY, maxZ; // children's boxes
    std::uint32_t child[kWidth];

    // Every slot empty, with an empty box (min +inf, max -inf), which no box test passes.
    void clear() {
        const float inf = std::numeric_limits<float>::infinity();
        minX = minY = minZ = simd::splat(inf);
        maxX = maxY = maxZ = simd::splat(-inf);
        for (std::uint32_t& c : child) c = kEmpty;
    }
    void set(int slot, const Bounds& box, std::uint32_t target) {
        minX[slot] = box.min.x, minY[slot] = box.min.y, minZ[slot] = box.min.z;
        maxX[slot] = box.max.x, maxY[slot] = box.max.y, maxZ[slot] = box.max.z;
        child[slot] = target;
    }
};
static_assert(sizeof(WideNode) == 224, "a node is seven half cache lines");

} // namespace sdfgen
