#pragma once
// The ray method's tree: the binary Bvh collapsed into 8-wide nodes (core/accel/wide_node.hpp) whose
// leaves are the binary tree's own leaves (same boxes, same triangles in the same order). Each node
// also stores, for each of the eight direction octants, the order in which the binary tree's
// depth-first ray traversal (the child on the ray's side of each split first) reaches its
// children, so a traversal over this tree meets the binary leaves in exactly the binary order and,
// testing each leaf's box as that traversal does, finds bit for bit the same hits (see
// core/accel/ray_kernel.inc for why). The kernel is compiled twice, for AVX2 (ray_avx2.cpp) and baseline
// x86-64 (ray_baseline.cpp), and dispatched here (rays::activeTrace).
#include "core/accel/bvh.hpp"
#include "core/accel/ray.hpp"
#include "core/simd/path.hpp"
#include "core/simd/simd.hpp"
#include "core/accel/wide_node.hpp"
#include "sdfgen/mesh.hpp"

#include <cstdint>
#include <vector>

namespace sdfgen {

class RayTree {
public:
    static constexpr int kWidth = WideNode::kWidth;
    // A child slot: an inner node's index, or kLeaf | the index of a leaf's record; empty slots
    // have empty boxes, which no ray's slab test passes.
    static constexpr std::uint32_t kLeaf = WideNode::kLeaf;
    static constexpr std::uint32_t kEmpty = WideNode::kEmpty;

    struct alignas(32) Node : WideNode {
        // order[octant] holds the eight slots, four bits each, first visited in the lowest bits;
        // octant bit a is set where the direction's component a is negative.
        std::uint32_t order[kWidth];
    };
    static_assert(sizeof(Node) == 256, "a node is four cache lines");

    // A binary leaf's triangle count, in the record just before its triangles (its box is its
    // parent's slot, the binary tree's box); copy it out with memcpy.
    struct Leaf {
        std::uint32_t count;
        std::uint8_t unused[32];
    };
    static_assert(sizeof(Leaf) == sizeof(PreparedTriangle), "a leaf takes one record");

    RayTree(const Mesh& mesh, const Bvh& tree);

    const std::vector<Node>& nodes() const { return nodes_; }
    // Each leaf's Leaf record followed by its triangles, in the binary leaf's order.
    const std::vector<PreparedTriangle>& records() const { return records_; }

    // Traversal stack entries: a wide node is at least one binary level below its parent and pushes
    // at most eight children, seven of them left for later.
    static constexpr int kStackSize = (kWidth - 1) * (Bvh::kMaxDepth + 2) + kWidth;

private:
    std::vector<Node> nodes_; // nodes_[0] is the root
    std::vector<PreparedTriangle> records_;
};

// Eight samples (a 2x2x2 block) traced in every direction; see generateRayField.
struct RayBlock {
    simd::f8 ox, oy, oz; // in: the origins
    simd::i8 active;     // in: all ones for the lanes that are samples of the grid
    simd::f8 nearest;    // out: nearest hit of any ray (infinity where none hit)
    simd::i8 hits;       // out: rays that hit something, while the vote was open
    simd::i8 backs;      // out: of those, the ones whose nearest hit was a back face
};

// The ray kernel's compiled copies (core/accel/ray_kernel.inc: ray_avx2.cpp, ray_baseline.cpp): the
// block's rays traced in every direction. This stage's own dispatch: the copy for simdPath()
// (core/simd/path.hpp).
namespace rays {
namespace baseline {
void traceBlock(const RayTree& tree, const glm::vec3* directions, int rays, RayBlock& block);
}
#if defined(__x86_64__) || defined(__i386__)
namespace avx2 {
void traceBlock(const RayTree& tree, const glm::vec3* directions, int rays, RayBlock& block);
}
#endif
using TraceKernel = void (*)(const RayTree&, const glm::vec3*, int, RayBlock&);
inline TraceKernel activeTrace() {
#if defined(__x86_64__) || defined(__i386__)
    if (simdPath() >= SimdPath::Avx2) return avx2::traceBlock;
#endif
    return baseline::traceBlock;
}
} // namespace rays
} // namespace sdfgen
