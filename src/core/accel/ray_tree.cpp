#include "core/accel/ray_tree.hpp"
#include "sdfgen/error.hpp"

#include <cstring>

namespace sdfgen {

RayTree::RayTree(const Mesh& mesh, const Bvh& tree) {
    const std::size_t leafCount = (tree.nodeCount() + 1) / 2;
    if (tree.triangleCount() + leafCount >= kLeaf) throw Error("too many triangles for the ray method's tree");
    records_.reserve(tree.triangleCount() + leafCount);

    auto makeLeaf = [&](const Bvh::NodeView& n) {
        const std::uint32_t at = std::uint32_t(records_.size());
        const Leaf leaf{n.count, {}};
        records_.emplace_back();
        std::memcpy(&records_.back(), &leaf, sizeof leaf);
        for (std::uint32_t i = 0; i < n.count; ++i) {
            const std::uint32_t id = n.triangles[i];
            records_.push_back(prepareTriangle(mesh.vertex(id, 0), mesh.vertex(id, 1), mesh.vertex(id, 2)));
        }
        return kLeaf | at;
    };
    // A wide node takes a binary subtree and opens its largest inner descendants until it has
    // eight children (binary leaves are never opened: they are the wide tree's leaves too).
    auto build = [&](auto& self, std::uint32_t binary) -> std::uint32_t {
        const std::uint32_t index = std::uint32_t(nodes_.size());
        nodes_.emplace_back();
        const Bvh::NodeView root = tree.node(binary);
        const std::vector<std::uint32_t> open = root.count > 0 ? std::vector<std::uint32_t>{binary} // a tree that is one leaf
                                                               : tree.widestDescendants(binary, kWidth, [](std::uint32_t) { return true; });
        std::uint32_t child[kWidth];
        for (std::size_t c = 0; c < open.size(); ++c) {
            const Bvh::NodeView n = tree.node(open[c]);
            child[c] = n.count > 0 ? makeLeaf(n) : self(self, open[c]);
        }
        Node& node = nodes_[index]; // after the recursion, which grows nodes_
        node.clear();
        for (std::size_t c = 0; c < open.size(); ++c) node.set(int(c), tree.node(open[c]).box, child[c]);
        // The binary traversal's order of the open children for each octant: it visits
        // `first` first unless the direction runs down the node's split axis. Empty slots go last.
        for (int octant = 0; octant < kWidth; ++octant) {
            std::uint32_t order = 0;
            int visited = 0;
            bool taken[kWidth] = {};
            auto visit = [&](auto& walk, std::uint32_t b) -> void {
                for (std::size_t c = 0; c < open.size(); ++c) {
                    if (open[c] != b) continue;
                    order |= std::uint32_t(c) << (4 * visited++);
                    taken[c] = true;
                    return;
                }
                const Bvh::NodeView n = tree.node(b);
                const bool down = (octant >> n.axis) & 1;
                walk(walk, down ? n.second : n.first);
                walk(walk, down ? n.first : n.second);
            };
            visit(visit, binary);
            for (int slot = 0; slot < kWidth; ++slot) {
                if (!taken[slot]) order |= std::uint32_t(slot) << (4 * visited++);
            }
            node.order[octant] = order;
        }
        return index;
    };
    build(build, 0);
}

} // namespace sdfgen
