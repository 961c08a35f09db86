#pragma once
// Ray queries over the binary Bvh, for the tests: the packet traversal that the ray method's wide
// tree (core/accel/ray_tree.hpp) must reproduce bit for bit, and the tree's depth.
#include "core/accel/bvh.hpp"
#include "core/simd/simd.hpp"
#include "sdfgen/mesh.hpp"

#include <glm/vec3.hpp>
#include <cstdint>

namespace sdfgen::test {

struct RayHit {
    float t = 0.0f;
    std::uint32_t triangle = 0; // index into Mesh::triangles
    bool backFace = false;
};

// Eight rays that share one direction. Lanes with tMax < 0 are inactive.
struct RayPacket {
    simd::f8 ox, oy, oz;
    glm::vec3 direction;
    simd::f8 tMax;     // in: farthest distance of interest; out: nearest hit where hit
    simd::i8 hit;      // out: all ones where the lane hit something closer than tMax
    simd::i8 triangle; // out: triangle index where hit
    simd::i8 backFace; // out: all ones where the nearest hit is a back face
};

// The nearest hits of the packet's rays over `tree` (built from `mesh`): depth-first, the child on
// the ray's side of each split first, each leaf's triangles in order.
void intersect(const Mesh& mesh, const Bvh& tree, RayPacket& packet);
// Nearest hit with 0 <= t < tMax along origin + t * direction; false when there is none.
bool intersect(const Mesh& mesh, const Bvh& tree, const glm::vec3& origin, const glm::vec3& direction, float tMax,
               RayHit& hit);

// Levels below the root of the deepest leaf.
int treeDepth(const Bvh& tree);

} // namespace sdfgen::test
