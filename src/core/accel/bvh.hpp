#pragma once
#include "sdfgen/mesh.hpp"
#include "core/runtime/parallel.hpp"
#include "core/accel/ray.hpp"
#include "sdfgen/run_control.hpp"

#include <glm/common.hpp>
#include <algorithm>
#include <cstdint>
#include <vector>

namespace sdfgen {

// Half the surface area of a box, in double: float extents overflow for coordinates beyond
// ±1.7e38 and products underflow below 1e-19, and the surface area heuristic must still compare
// them. Inline: the tree build's split search calls it for every plane of every node.
inline double halfArea(const Bounds& b) {
    const double x = std::max(double(b.max.x) - double(b.min.x), 0.0);
    const double y = std::max(double(b.max.y) - double(b.min.y), 0.0);
    const double z = std::max(double(b.max.z) - double(b.min.z), 0.0);
    return x * y + y * z + z * x;
}

struct BvhBuildRecords; // the triangles' boxes and centroids as the tree's build reads them (core/accel/bvh.cpp)

// The acceleration structure over a mesh's triangles: a binary bounding volume hierarchy of
// axis-aligned boxes (each inner node splits its triangles along one axis), built with the binned
// surface area heuristic and stored as a flat depth-first node array. Exact copies of a triangle
// are held once, as their first copy (the lowest index: queries report it, as brute force would).
// Any finite float input builds: binning works in double, and skewed inputs fall back to median
// splits, so depth stays below kMaxDepth and leaves within kMaxLeafSize.
class Bvh {
public:
    static constexpr int kMaxLeafSize = 8;
    static constexpr int kMaxDepth = 48;

    // Built on control.threads threads, reporting progress (triangles placed in leaves); throws
    // Cancelled soon after control.cancel is raised.
    explicit Bvh(const Mesh& mesh, const RunControl& control = {});

    // The tree `previous` over `mesh`, its mesh with the vertices moved: the same triangles, whose
    // exact copies are the same (the vertices group as before, VertexGroups::holdFor). Every box is
    // refit bottom-up to the new positions in linear time; the search answers as a tree built on
    // `mesh` does (the nearest triangle, ties to the lower index, whatever the tree's shape).
    // `spare`, when given, is a dead tree of the same mesh (a refit chain's): its arrays' memory is
    // reused, already mapped, instead of fresh memory the system must zero and map in page by page.
    Bvh(const Bvh& previous, const Mesh& mesh, const RunControl& control = {}, Bvh* spare = nullptr);

    // Calls visit(triangle) for every triangle whose bounding box overlaps `box`.
    template <class Visit>
    void forEachOverlap(const Bounds& box, Visit&& visit) const;

    // The tree's shape, read by structures derived from it (core/accel/wide_bvh.hpp). Node 0 is the root;
    // an inner node's children are `first` and `second`, a leaf holds `count` Mesh triangle indices.
    struct NodeView {
        Bounds box;
        std::uint32_t first, second;
        const std::uint32_t* triangles;
        std::uint32_t count; // 0 for an inner node
        int axis;            // an inner node's split axis: a ray traversal visits `first` first where the ray runs up it
        std::uint32_t slot;  // a leaf's first position in leaf order (0 ... triangleCount() - 1)
    };
    NodeView node(std::uint32_t index) const {
        const Node& n = nodes_[index];
        const Bounds box{{n.min[0], n.min[1], n.min[2]}, {n.max[0], n.max[1], n.max[2]}};
        if (n.count == 0) return {box, index + 1, n.index, nullptr, 0, n.axis, 0};
        return {box, 0, 0, triangleIds_.data() + n.index, n.count, 0, n.index};
    }

    // The binary nodes a wide node over inner node `index` takes as its children, for trees
    // collapsed from this one (core/accel/wide_bvh.hpp, core/accel/ray_tree.hpp): its two children, then
    // repeatedly the open inner node with the largest box (half area; the first of equals)
    // replaced by its two children, until there are `width` or none left that mayOpen(node) allows.
    template <class MayOpen>
    std::vector<std::uint32_t> widestDescendants(std::uint32_t index, int width, MayOpen&& mayOpen) const;

    std::size_t nodeCount() const { return nodes_.size(); }
    // Distinct triangles held: exact copies of a triangle are stored once (see TriangleCopies).
    std::size_t triangleCount() const { return triangleIds_.size(); }
    // The mesh triangle at each position of leaf order (a leaf's triangles start at its `slot`).
    const std::vector<std::uint32_t>& leafTriangles() const { return triangleIds_; }
    // How often a triangle the tree reports (a first copy) occurs in the mesh: what a visit
    // stands for. 0 for the later copies, which the tree never reports.
    std::uint32_t copies(std::uint32_t triangle) const { return copies_[triangle]; }
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

    // Nodes in depth-first order with node and triangle indices relative to the subtree; big
    // subtrees are built in parallel and spliced, which gives the serial layout exactly.
    struct Subtree {
        std::vector<Node> nodes;
        std::vector<std::uint32_t> ids;
    };
    struct BuildInput {
        const BvhBuildRecords& records;
        ProgressCounter& progress;
    };
    static std::uint32_t build(Subtree& out, std::vector<std::uint32_t>& order, std::size_t begin, std::size_t end,
                               const BuildInput& input, int depth);

    std::vector<Node> nodes_;

    std::vector<PreparedTriangle> triangles_; // in leaf order
    std::vector<std::uint32_t> triangleIds_;  // leaf order -> Mesh triangle index
    std::vector<std::uint32_t> copies_;       // Mesh triangle index -> its count if a first copy, else 0
    Bounds bounds_;
};

template <class MayOpen>
std::vector<std::uint32_t> Bvh::widestDescendants(std::uint32_t index, int width, MayOpen&& mayOpen) const {
    const NodeView root = node(index);
    std::vector<std::uint32_t> open{root.first, root.second};
    while (open.size() < std::size_t(width)) {
        int widest = -1;
        float largest = -1.0f;
        for (std::size_t c = 0; c < open.size(); ++c) {
            const NodeView n = node(open[c]);
            if (n.count > 0 || !mayOpen(open[c])) continue;
            const glm::vec3 e = glm::max(n.box.max - n.box.min, glm::vec3(0.0f));
            const float area = e.x * e.y + e.y * e.z + e.z * e.x;
            if (area > largest) largest = area, widest = int(c);
        }
        if (widest < 0) break;
        const NodeView n = node(open[std::size_t(widest)]);
        open[std::size_t(widest)] = n.first;
        open.push_back(n.second);
    }
    return open;
}

template <class Visit>
void Bvh::forEachOverlap(const Bounds& box, Visit&& visit) const {
    auto overlaps = [&](const float* lo, const float* hi) {
        return lo[0] <= box.max.x && hi[0] >= box.min.x && lo[1] <= box.max.y && hi[1] >= box.min.y &&
               lo[2] <= box.max.z && hi[2] >= box.min.z;
    };
    std::uint32_t stack[kMaxDepth + 2];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const std::uint32_t index = stack[--top];
        const Node& node = nodes_[index];
        if (!overlaps(node.min, node.max)) continue;
        if (node.count == 0) {
            stack[top++] = node.index;
            stack[top++] = index + 1;
            continue;
        }
        for (std::uint32_t i = node.index; i < node.index + node.count; ++i) {
            const PreparedTriangle& t = triangles_[i];
            const glm::vec3 p1 = t.v0 + t.e1, p2 = t.v0 + t.e2;
            const float lo[3] = {std::min({t.v0.x, p1.x, p2.x}), std::min({t.v0.y, p1.y, p2.y}), std::min({t.v0.z, p1.z, p2.z})};
            const float hi[3] = {std::max({t.v0.x, p1.x, p2.x}), std::max({t.v0.y, p1.y, p2.y}), std::max({t.v0.z, p1.z, p2.z})};
            if (overlaps(lo, hi)) visit(triangleIds_[i]);
        }
    }
}

} // namespace sdfgen
