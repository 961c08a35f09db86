#pragma once
#include "core/mesh.hpp"
#include "core/ray.hpp"
#include "core/simd.hpp"

#include <cstdint>
#include <vector>

namespace sdfgen {

struct RayHit {
    float t = 0.0f;
    std::uint32_t triangle = 0; // index into Mesh::triangles
    bool backFace = false;
};

// Eight rays that share one direction (the generator traces each sample direction for eight
// neighbouring samples at once). Lanes with tMax < 0 are inactive.
struct RayPacket {
    simd::f8 ox, oy, oz;
    glm::vec3 direction;
    simd::f8 tMax;         // in: farthest distance of interest; out: nearest hit where hit
    simd::i8 hit;          // out: all ones where the lane hit something closer than tMax
    simd::i8 triangle;     // out: triangle index where hit
    simd::i8 backFace;     // out: all ones where the nearest hit is a back face
};

// The acceleration structure over a mesh's triangles: a tree of axis-aligned bounding boxes in
// which every inner node splits its triangles along one axis (an object-partitioning kd-tree, a.k.a.
// BVH), built with the binned surface area heuristic and stored as a flat depth-first node array.
class KdTree {
public:
    static constexpr int kMaxLeafSize = 8;
    static constexpr int kMaxDepth = 48;

    explicit KdTree(const Mesh& mesh);

    // Nearest hit with 0 <= t < tMax along origin + t * direction; false when there is none.
    bool intersect(const glm::vec3& origin, const glm::vec3& direction, float tMax, RayHit& hit) const;
    // The same for a packet of eight rays with a common direction.
    void intersect(RayPacket& packet) const;

    std::size_t nodeCount() const { return nodes_.size(); }
    int depth() const { return depth_; }
    const Bounds& bounds() const { return bounds_; }

private:
    struct Node {
        float min[3];
        float max[3];
        std::uint32_t index; // inner: second child (first child is the next node); leaf: first triangle
        std::uint16_t count; // triangles in a leaf, 0 for an inner node
        std::uint16_t axis;  // split axis of an inner node
    };
    static_assert(sizeof(Node) == 32, "nodes are half a cache line");

    std::uint32_t build(std::vector<std::uint32_t>& order, std::size_t begin, std::size_t end,
                        const std::vector<glm::vec3>& centroids, const std::vector<Bounds>& boxes, int depth);

    std::vector<Node> nodes_;
    std::vector<PreparedTriangle> triangles_; // in leaf order
    std::vector<std::uint32_t> triangleIds_;  // leaf order -> Mesh triangle index
    Bounds bounds_;
    int depth_ = 0;
};

} // namespace sdfgen
