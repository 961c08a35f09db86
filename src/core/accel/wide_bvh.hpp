#pragma once
// The closest-point structure of the exact distance: the binary Bvh collapsed into 8-wide nodes
// (core/accel/wide_node.hpp), with every subtree of at most eight triangles flattened into one leaf packet of eight triangles
// in structure-of-arrays form (one point against eight triangles at once).
//
// Every search returns the nearest triangle by the float distance of `packetDistanceSquared`,
// ties going to the LOWER triangle index: the minimum of (float squared distance, index) over all
// triangles, whatever the traversal order, the seeds or the candidate lists. A point query and a
// baked sample at the same position therefore always find the same triangle.
#include "core/accel/bvh.hpp"
#include "core/simd/path.hpp"
#include "core/simd/simd.hpp"
#include "core/accel/wide_node.hpp"
#include "sdfgen/mesh.hpp"
#include "sdfgen/run_control.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace sdfgen {

// Eight triangles set up for branch-free point distance, each in a frame of its own: corner a,
// the unit vector e1 along its longest edge (from a), the unit normal n and e2 = n x e1. In that
// frame the triangle is (0, 0), (length, 0), (cu, cv) with cv >= 0 (up to rounding), so a point's
// distance is its height along n and its distance within the plane to a triangle in two
// dimensions: a third fewer operations than in three, on a smaller packet. invAC and invBC are the
// inverse squared lengths of the other two edges (0 for a zero-length one); bcu = cu - length.
// Lanes past a leaf's triangles repeat its first triangle.
struct alignas(32) TrianglePacket {
    simd::f8 ax, ay, az;
    simd::f8 e1x, e1y, e1z, e2x, e2y, e2z, nx, ny, nz;
    simd::f8 length, cu, cv, bcu, invAC, invBC;
    simd::i8 id; // Mesh triangle index of each lane
};

// The running answer of a nearest-triangle search: the lowest (squared distance, triangle) pair.
struct NearestSoFar {
    float distanceSquared;
    std::uint32_t triangle;
};

// In a namespace of their own, found by sdfgen's code through the using-directive but not by
// argument-dependent lookup, so that the kernel's own copies (core/distance/exact_kernel.inc) never
// compete with them.
namespace packet {
#include "core/accel/packet_ops.inc"
} // namespace packet
using namespace packet;

class WideBvh {
public:
    static constexpr int kWidth = WideNode::kWidth;
    // A child slot: an inner node's index, or kLeaf | packet index; empty slots have empty boxes.
    static constexpr std::uint32_t kLeaf = WideNode::kLeaf;
    static constexpr std::uint32_t kEmpty = WideNode::kEmpty;
    using Node = WideNode;

    // The SoA packets are filled on control.threads threads; the tree is the same for any count.
    WideBvh(const Mesh& mesh, const Bvh& tree, const RunControl& control = {});
    // The tree `previous` over `mesh`, its mesh with the vertices moved (the same triangles, the
    // same exact copies; its binary tree refit by Bvh's refit constructor): the same nodes and
    // packets, their boxes and frames measured again, in linear time.
    // `spare`: as Bvh's refit constructor's, a dead tree of the same mesh whose memory is reused.
    WideBvh(const WideBvh& previous, const Mesh& mesh, const RunControl& control = {}, WideBvh* spare = nullptr);

    // The search runs in this stage's copy for this CPU (core/accel/wide_nearest.inc).
    // The nearest triangle to p (local coordinates), starting from `best` (an upper bound that a
    // real triangle attains, or {FLT_MAX, any}). Explores everything within the bound, ties included.
    // Returns the packet that holds the answer, or kEmpty when the starting `best` stood.
    std::uint32_t nearest(float px, float py, float pz, NearestSoFar& best) const;

    // Which part of a row a walk covers (core/accel/wide_row.inc): at or ahead of x (+x), or at or behind it.
    enum class RowSide { Ahead, Behind };

    const std::vector<TrianglePacket>& packets() const { return packets_; }
    const Bounds& leafBounds(std::uint32_t packet) const { return leafBounds_[packet]; }
    const std::vector<Node>& nodes() const { return nodes_; }

    // Pruning slack: a box whose float distance exceeds the bound by less than this relative
    // amount is still explored, so that rounding of box and triangle distances (a few ulps each)
    // can never prune a triangle whose float distance ties or beats the bound.
    static constexpr float kSlack = 1.0f + 0x1p-16f;

    // The searches' stack: a wide node is at least one binary level below its parent, except
    // under a binary leaf of more than eight triangles (at most 65535: five more levels of
    // packets of eight).
    static constexpr int kStackSize = (kWidth - 1) * (Bvh::kMaxDepth + 8) + 1;

private:
    std::vector<Node> nodes_; // nodes_[0] is the root
    std::vector<TrianglePacket> packets_;
    std::vector<Bounds> leafBounds_; // per packet
    // Each packet's triangles, lane by lane, shared along a chain of refits: the refit reads them
    // here, 32 bytes a packet, rather than from the packets' lanes spread over 608.
    std::shared_ptr<const std::vector<std::array<std::uint32_t, kWidth>>> packetIds_;
};

// The nearest-triangle search's and the packet fill's compiled copies (core/accel/wide_nearest.inc,
// core/accel/wide_fill.inc: wide_avx2.cpp, wide_baseline.cpp): this stage's own dispatch, the copy
// for simdPath() (core/simd/path.hpp).
namespace wide {
using NearestKernel = std::uint32_t (*)(const WideBvh&, float, float, float, NearestSoFar&);
using FillKernel = void (*)(const Mesh&, const std::uint32_t*, TrianglePacket&);
namespace baseline {
std::uint32_t nearest(const WideBvh& tree, float px, float py, float pz, NearestSoFar& best);
void fillPacket(const Mesh& mesh, const std::uint32_t* ids, TrianglePacket& p);
}
#if defined(__x86_64__) || defined(__i386__)
namespace avx2 {
std::uint32_t nearest(const WideBvh& tree, float px, float py, float pz, NearestSoFar& best);
void fillPacket(const Mesh& mesh, const std::uint32_t* ids, TrianglePacket& p);
}
#endif
inline NearestKernel activeNearest() {
#if defined(__x86_64__) || defined(__i386__)
    if (simdPath() >= SimdPath::Avx2) return avx2::nearest;
#endif
    return baseline::nearest;
}
inline FillKernel activeFill() {
#if defined(__x86_64__) || defined(__i386__)
    if (simdPath() >= SimdPath::Avx2) return avx2::fillPacket;
#endif
    return baseline::fillPacket;
}
} // namespace wide

} // namespace sdfgen
