#pragma once
// The closest-point structure of the exact distance: the binary Bvh collapsed into 8-wide nodes
// whose children's boxes are stored as structure-of-arrays (one AVX2 instruction tests all eight),
// with every subtree of at most eight triangles flattened into one leaf packet of eight triangles
// in structure-of-arrays form (one point against eight triangles at once).
//
// Every search returns the nearest triangle by the float distance of `packetDistanceSquared`,
// ties going to the LOWER triangle index: the minimum of (float squared distance, index) over all
// triangles, whatever the traversal order, the seeds or the candidate lists. A point query and a
// baked sample at the same position therefore always find the same triangle.
#include "core/bvh.hpp"
#include "core/simd.hpp"
#include "sdfgen/mesh.hpp"

#include <cstdint>
#include <vector>

namespace sdfgen {

// Eight triangles set up for branch-free point distance: corner a, the edges ab, ac, bc, the unit
// normal, the in-plane normals of the edges (pointing inwards) and the inverse squared edge
// lengths (0 for a zero-length edge). Lanes past a leaf's triangles repeat its first triangle.
struct alignas(32) TrianglePacket {
    simd::f8 ax, ay, az;
    simd::f8 abx, aby, abz, acx, acy, acz, bcx, bcy, bcz;
    simd::f8 nx, ny, nz;
    simd::f8 inABx, inABy, inABz, inBCx, inBCy, inBCz, inCAx, inCAy, inCAz;
    simd::f8 invAB, invBC, invCA;
    simd::i8 id; // Mesh triangle index of each lane
};

// Squared float distances from one point to the eight triangles of a packet.
inline simd::f8 packetDistanceSquared(const TrianglePacket& t, float px, float py, float pz) {
    using namespace simd;
    auto clamp01 = [](const f8& x) { return min(max(x, splat(0.0f)), splat(1.0f)); };
    // Vectors from the corners a, b, c to the point.
    const f8 ax = px - t.ax, ay = py - t.ay, az = pz - t.az;
    const f8 bx = ax - t.abx, by = ay - t.aby, bz = az - t.abz;
    const f8 cx = ax - t.acx, cy = ay - t.acy, cz = az - t.acz;
    // Inside the prism over the face: the distance is the height above the plane.
    const i8 inside = ((ax * t.inABx + ay * t.inABy + az * t.inABz) >= 0.0f) & ((bx * t.inBCx + by * t.inBCy + bz * t.inBCz) >= 0.0f) &
                      ((cx * t.inCAx + cy * t.inCAy + cz * t.inCAz) >= 0.0f);
    const f8 height = ax * t.nx + ay * t.ny + az * t.nz;
    // Otherwise the nearest of the three edges (as segments): from a along ab, b along bc, c along -ac.
    const f8 sAB = clamp01((ax * t.abx + ay * t.aby + az * t.abz) * t.invAB);
    const f8 sBC = clamp01((bx * t.bcx + by * t.bcy + bz * t.bcz) * t.invBC);
    const f8 sCA = clamp01(-(cx * t.acx + cy * t.acy + cz * t.acz) * t.invCA);
    const f8 dABx = ax - sAB * t.abx, dABy = ay - sAB * t.aby, dABz = az - sAB * t.abz;
    const f8 dBCx = bx - sBC * t.bcx, dBCy = by - sBC * t.bcy, dBCz = bz - sBC * t.bcz;
    const f8 dCAx = cx + sCA * t.acx, dCAy = cy + sCA * t.acy, dCAz = cz + sCA * t.acz;
    const f8 edges = min(dABx * dABx + dABy * dABy + dABz * dABz,
                         min(dBCx * dBCx + dBCy * dBCy + dBCz * dBCz, dCAx * dCAx + dCAy * dCAy + dCAz * dCAz));
    return select(inside, height * height, edges);
}

// The vectors from the closest points of a packet's eight triangles to p (for bounds; rounded
// like packetDistanceSquared, not bit-equal to it).
inline void packetClosestOffset(const TrianglePacket& t, float px, float py, float pz, simd::f8& vx, simd::f8& vy, simd::f8& vz) {
    using namespace simd;
    auto clamp01 = [](const f8& x) { return min(max(x, splat(0.0f)), splat(1.0f)); };
    const f8 ax = px - t.ax, ay = py - t.ay, az = pz - t.az;
    const f8 bx = ax - t.abx, by = ay - t.aby, bz = az - t.abz;
    const f8 cx = ax - t.acx, cy = ay - t.acy, cz = az - t.acz;
    const i8 inside = ((ax * t.inABx + ay * t.inABy + az * t.inABz) >= 0.0f) & ((bx * t.inBCx + by * t.inBCy + bz * t.inBCz) >= 0.0f) &
                      ((cx * t.inCAx + cy * t.inCAy + cz * t.inCAz) >= 0.0f);
    const f8 height = ax * t.nx + ay * t.ny + az * t.nz;
    const f8 sAB = clamp01((ax * t.abx + ay * t.aby + az * t.abz) * t.invAB);
    const f8 sBC = clamp01((bx * t.bcx + by * t.bcy + bz * t.bcz) * t.invBC);
    const f8 sCA = clamp01(-(cx * t.acx + cy * t.acy + cz * t.acz) * t.invCA);
    const f8 dABx = ax - sAB * t.abx, dABy = ay - sAB * t.aby, dABz = az - sAB * t.abz;
    const f8 dBCx = bx - sBC * t.bcx, dBCy = by - sBC * t.bcy, dBCz = bz - sBC * t.bcz;
    const f8 dCAx = cx + sCA * t.acx, dCAy = cy + sCA * t.acy, dCAz = cz + sCA * t.acz;
    const f8 lAB = dABx * dABx + dABy * dABy + dABz * dABz, lBC = dBCx * dBCx + dBCy * dBCy + dBCz * dBCz;
    const f8 lCA = dCAx * dCAx + dCAy * dCAy + dCAz * dCAz;
    const i8 useAB = (lAB <= lBC) & (lAB <= lCA), useBC = ~useAB & (lBC <= lCA);
    vx = select(inside, height * t.nx, select(useAB, dABx, select(useBC, dBCx, dCAx)));
    vy = select(inside, height * t.ny, select(useAB, dABy, select(useBC, dBCy, dCAy)));
    vz = select(inside, height * t.nz, select(useAB, dABz, select(useBC, dBCz, dCAz)));
}

// The running answer of a nearest-triangle search: the lowest (squared distance, triangle) pair.
struct NearestSoFar {
    float distanceSquared;
    std::uint32_t triangle;
};

// Folds one packet into `best`: the lowest (distance, index) pair of its lanes, if lower.
inline void scanPacket(const TrianglePacket& packet, float px, float py, float pz, NearestSoFar& best) {
    using namespace simd;
    const f8 d = packetDistanceSquared(packet, px, py, pz);
    const unsigned candidates = mask(d <= best.distanceSquared);
    if (candidates == 0) return;
    for (unsigned bits = candidates; bits != 0; bits &= bits - 1) {
        const int lane = __builtin_ctz(bits);
        const std::uint32_t id = std::uint32_t(packet.id[lane]);
        if (d[lane] < best.distanceSquared || (d[lane] == best.distanceSquared && id < best.triangle)) best = {d[lane], id};
    }
}

class WideBvh {
public:
    static constexpr int kWidth = 8;
    // A child slot: an inner node's index, or kLeaf | packet index; empty slots have empty boxes.
    static constexpr std::uint32_t kLeaf = 0x80000000u;
    static constexpr std::uint32_t kEmpty = 0xffffffffu;

    struct alignas(32) Node {
        simd::f8 minX, minY, minZ, maxX, maxY, maxZ; // children's boxes (empty: min +inf, max -inf)
        std::uint32_t child[kWidth];
    };

    WideBvh(const Mesh& mesh, const Bvh& tree);

    // The nearest triangle to p (local coordinates), starting from `best` (an upper bound that a
    // real triangle attains, or {FLT_MAX, any}). Explores everything within the bound, ties included.
    // Returns the packet that holds the answer, or kEmpty when the starting `best` stood.
    std::uint32_t nearest(float px, float py, float pz, NearestSoFar& best) const;

    // Appends to `packets` every leaf packet whose box is within `reach` of the box [lo, hi]
    // (reach in the same units; boxes touching count), in the tree's order.
    void collectLeaves(const float lo[3], const float hi[3], float reach, std::vector<std::uint32_t>& packets) const;

    const std::vector<TrianglePacket>& packets() const { return packets_; }
    const Bounds& leafBounds(std::uint32_t packet) const { return leafBounds_[packet]; }
    const std::vector<Node>& nodes() const { return nodes_; }

    // Pruning slack: a box whose float distance exceeds the bound by less than this relative
    // amount is still explored, so that rounding of box and triangle distances (a few ulps each)
    // can never prune a triangle whose float distance ties or beats the bound.
    static constexpr float kSlack = 1.0f + 0x1p-16f;

private:
    // A wide node is at least one binary level below its parent, except under a binary leaf of
    // more than eight triangles (at most 65535: five more levels of packets of eight).
    static constexpr int kStackSize = (kWidth - 1) * (Bvh::kMaxDepth + 8) + 1;

    std::vector<Node> nodes_; // nodes_[0] is the root
    std::vector<TrianglePacket> packets_;
    std::vector<Bounds> leafBounds_; // per packet
};

} // namespace sdfgen
