#include "core/accel/wide_bvh.hpp"
#include "core/runtime/parallel.hpp"

#include <algorithm>
#include <array>
#include <limits>

namespace sdfgen {

namespace {

constexpr int kWidth = WideBvh::kWidth;
constexpr float kInf = std::numeric_limits<float>::infinity();
using PacketIds = std::array<std::uint32_t, kWidth>; // a packet's triangles, lane by lane

// The union of the boxes of a packet's triangles.
Bounds packetBox(const Mesh& mesh, const PacketIds& ids) {
    Bounds box{glm::vec3(kInf), glm::vec3(-kInf)};
    for (const std::uint32_t id : ids) {
        const glm::vec3 a = mesh.vertex(id, 0), b = mesh.vertex(id, 1), c = mesh.vertex(id, 2);
        box.min = glm::min(box.min, glm::min(a, glm::min(b, c)));
        box.max = glm::max(box.max, glm::max(a, glm::max(b, c)));
    }
    return box;
}

// Triangles under each binary node, to find the subtrees that fit one packet.
std::vector<std::uint32_t> trianglesBelow(const Bvh& tree) {
    std::vector<std::uint32_t> below(tree.nodeCount());
    for (std::size_t i = tree.nodeCount(); i-- > 0;) { // children follow their parent
        const Bvh::NodeView n = tree.node(std::uint32_t(i));
        below[i] = n.count > 0 ? n.count : below[n.first] + below[n.second];
    }
    return below;
}

// The layout pass: the wide nodes, each packet's triangles and box, children before their parent.
// Each wide node takes a binary subtree and opens its largest inner descendants until it has
// eight children. Subtrees of at most eight triangles become packets, several of them sharing one
// where they fit together (fuller packets: fewer lanes measured twice).
class WideLayout {
public:
    struct Child {
        Bounds box;
        std::uint32_t slot; // node index, or kLeaf | packet index
    };

    WideLayout(const Mesh& mesh, const Bvh& tree) : mesh_(mesh), tree_(tree), below_(trianglesBelow(tree)) {}

    // The wide subtree of binary node `binary`.
    Child build(std::uint32_t binary) {
        const Bvh::NodeView root = tree_.node(binary);
        if (root.count > std::uint32_t(kWidth)) return chunks(root.triangles, root.count);
        if (fits(binary)) {
            std::vector<std::uint32_t> ids;
            gather(binary, ids);
            return packet(ids.data(), ids.size());
        }
        const std::vector<std::uint32_t> open = tree_.widestDescendants(binary, kWidth, [&](std::uint32_t c) { return !fits(c); });
        std::vector<Child> children;
        std::vector<std::vector<std::uint32_t>> bins; // first fit, largest subtrees first
        std::vector<std::uint32_t> small;
        for (std::uint32_t c : open) {
            if (fits(c)) small.push_back(c);
            else children.push_back(build(c));
        }
        std::stable_sort(small.begin(), small.end(), [&](std::uint32_t l, std::uint32_t r) { return below_[l] > below_[r]; });
        for (std::uint32_t c : small) {
            std::vector<std::uint32_t>* bin = nullptr;
            for (auto& b : bins) {
                if (b.size() + below_[c] <= std::size_t(kWidth)) {
                    bin = &b;
                    break;
                }
            }
            if (!bin) bin = &bins.emplace_back();
            gather(c, *bin);
        }
        for (const auto& b : bins) children.push_back(packet(b.data(), b.size()));
        return node(children);
    }

    // A node over `children`; its box is the union of theirs.
    Child node(const std::vector<Child>& children) {
        WideNode made;
        made.clear();
        Bounds box{glm::vec3(kInf), glm::vec3(-kInf)};
        for (std::size_t c = 0; c < children.size(); ++c) {
            const Bounds& b = children[c].box;
            made.set(int(c), b, children[c].slot);
            box.min = glm::min(box.min, b.min);
            box.max = glm::max(box.max, b.max);
        }
        nodes.push_back(made);
        return Child{box, std::uint32_t(nodes.size() - 1)};
    }

    std::vector<WideNode> nodes;
    std::vector<PacketIds> packetIds;
    std::vector<Bounds> leafBounds; // per packet

private:
    bool fits(std::uint32_t binary) const { return below_[binary] <= std::uint32_t(kWidth); }

    // A packet of at most eight triangles (unused lanes repeat the first); its box is the union of
    // theirs. The lanes' SoA fields are filled once the tree is laid out (core/accel/wide_fill.inc).
    Child packet(const std::uint32_t* ids, std::size_t count) {
        PacketIds& lanes = packetIds.emplace_back();
        for (int lane = 0; lane < kWidth; ++lane) lanes[std::size_t(lane)] = ids[std::size_t(lane) < count ? std::size_t(lane) : 0];
        const Bounds box = packetBox(mesh_, lanes);
        leafBounds.push_back(box);
        return Child{box, WideBvh::kLeaf | std::uint32_t(packetIds.size() - 1)};
    }

    // A list of triangles of any length (a binary leaf at the depth limit may hold more than
    // eight): packets of eight under as many levels of nodes as it takes.
    Child chunks(const std::uint32_t* ids, std::size_t count) {
        if (count <= std::size_t(kWidth)) return packet(ids, count);
        std::size_t span = kWidth;
        while (span * kWidth < count) span *= kWidth;
        std::vector<Child> children;
        for (std::size_t at = 0; at < count; at += span) children.push_back(chunks(ids + at, std::min(span, count - at)));
        return node(children);
    }

    // The triangles of a binary subtree, in leaf order.
    void gather(std::uint32_t binary, std::vector<std::uint32_t>& ids) const {
        std::vector<std::uint32_t> pending{binary};
        while (!pending.empty()) {
            const Bvh::NodeView n = tree_.node(pending.back());
            pending.pop_back();
            if (n.count > 0) ids.insert(ids.end(), n.triangles, n.triangles + n.count);
            else pending.push_back(n.second), pending.push_back(n.first);
        }
    }

    const Mesh& mesh_;
    const Bvh& tree_;
    const std::vector<std::uint32_t> below_;
};

// Nodes were made children first, so the root is last: it moves to the front, where searches
// start, and every inner child index moves up by one with it.
void putRootFirst(std::vector<WideNode>& nodes) {
    std::rotate(nodes.begin(), nodes.end() - 1, nodes.end());
    for (WideNode& n : nodes) {
        for (std::uint32_t& c : n.child) {
            if (c != WideBvh::kEmpty && !(c & WideBvh::kLeaf)) ++c;
        }
    }
}

} // namespace

WideBvh::WideBvh(const Mesh& mesh, const Bvh& tree, const RunControl& control) {
    WideLayout layout(mesh, tree);
    const WideLayout::Child root = layout.build(0);
    if (root.slot & kLeaf) layout.node({root}); // a root that is one packet gets a node above it
    packets_.resize(layout.packetIds.size());
    constexpr std::size_t kPacketsPerItem = 1024;
    const wide::FillKernel fill = wide::activeFill();
    parallelFor((packets_.size() + kPacketsPerItem - 1) / kPacketsPerItem, quiet(control), [&](std::size_t item) {
        for (std::size_t i = item * kPacketsPerItem; i < std::min(packets_.size(), (item + 1) * kPacketsPerItem); ++i) {
            fill(mesh, layout.packetIds[i].data(), packets_[i]);
        }
    });
    nodes_ = std::move(layout.nodes);
    putRootFirst(nodes_);
    leafBounds_ = std::move(layout.leafBounds);
    packetIds_ = std::make_shared<const std::vector<PacketIds>>(std::move(layout.packetIds));
}

WideBvh::WideBvh(const WideBvh& previous, const Mesh& mesh, const RunControl& control, WideBvh* spare) : packetIds_(previous.packetIds_) {
    if (spare) { // its memory, every element written below
        nodes_ = std::move(spare->nodes_);
        packets_ = std::move(spare->packets_);
        leafBounds_ = std::move(spare->leafBounds_);
    }
    nodes_.assign(previous.nodes_.begin(), previous.nodes_.end());
    packets_.resize(previous.packets_.size());
    leafBounds_.resize(previous.leafBounds_.size());
    constexpr std::size_t kPacketsPerItem = 1024;
    const wide::FillKernel fill = wide::activeFill();
    parallelFor((packets_.size() + kPacketsPerItem - 1) / kPacketsPerItem, quiet(control), [&](std::size_t item) {
        for (std::size_t i = item * kPacketsPerItem; i < std::min(packets_.size(), (item + 1) * kPacketsPerItem); ++i) {
            const PacketIds& ids = (*packetIds_)[i];
            fill(mesh, ids.data(), packets_[i]);
            leafBounds_[i] = packetBox(mesh, ids);
        }
    });
    // The layout made children before their parents and putRootFirst moved the root (made last)
    // to the front: nodes 1, 2, ... come bottom-up, the root last.
    std::vector<Bounds> boxes(nodes_.size());
    auto refitNode = [&](std::size_t index) {
        Node& n = nodes_[index];
        Bounds box{glm::vec3(kInf), glm::vec3(-kInf)};
        for (int c = 0; c < kWidth; ++c) {
            const std::uint32_t child = n.child[c];
            if (child == kEmpty) continue;
            const Bounds& b = child & kLeaf ? leafBounds_[child & ~kLeaf] : boxes[child];
            n.set(c, b, child);
            box.min = glm::min(box.min, b.min);
            box.max = glm::max(box.max, b.max);
        }
        boxes[index] = box;
    };
    for (std::size_t i = 1; i < nodes_.size(); ++i) refitNode(i);
    refitNode(0);
}

std::uint32_t WideBvh::nearest(float px, float py, float pz, NearestSoFar& best) const {
    return wide::activeNearest()(*this, px, py, pz, best);
}

} // namespace sdfgen
