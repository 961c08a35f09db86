#include "core/accel/wide_bvh.hpp"
#include "core/runtime/parallel.hpp"

#include <glm/geometric.hpp>
#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
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
    // theirs. The lanes' SoA fields are filled once the tree is laid out (fillPacket).
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

// 1 / length2 rounded once to float, 0 for a zero-length (or overflowing) edge.
float inverse(double length2) {
    const float inv = float(1.0 / length2);
    return length2 > 0.0 && std::isfinite(inv) ? inv : 0.0f;
}

// The fill pass, one packet: each lane's frame in double, from the float corners every other step
// uses, rounded once.
void fillPacket(const Mesh& mesh, const PacketIds& ids, TrianglePacket& p) {
    for (int lane = 0; lane < kWidth; ++lane) {
        const std::uint32_t id = ids[std::size_t(lane)];
        if (lane > 0 && id == ids[0]) { // a lane past the leaf's triangles: the first one's values
            for (simd::f8* field : {&p.ax, &p.ay, &p.az, &p.e1x, &p.e1y, &p.e1z, &p.e2x, &p.e2y, &p.e2z, &p.nx, &p.ny, &p.nz, &p.length,
                                    &p.cu, &p.cv, &p.bcu, &p.invAC, &p.invBC}) {
                (*field)[lane] = (*field)[0];
            }
            p.id[lane] = p.id[0];
            continue;
        }
        glm::dvec3 corner[3] = {glm::dvec3(mesh.vertex(id, 0)), glm::dvec3(mesh.vertex(id, 1)), glm::dvec3(mesh.vertex(id, 2))};
        // The longest edge as the base (a cyclic rotation keeps the orientation): the frame of a
        // sliver or a needle is then as accurate as its longest side allows.
        int base = 0;
        double longest = -1.0;
        for (int e = 0; e < 3; ++e) {
            const glm::dvec3 edge = corner[(e + 1) % 3] - corner[e];
            const double length2 = glm::dot(edge, edge);
            if (length2 > longest) longest = length2, base = e;
        }
        const glm::dvec3 a = corner[base], b = corner[(base + 1) % 3], c = corner[(base + 2) % 3];
        const double length = std::sqrt(longest);
        const glm::dvec3 e1 = (b - a) / length;
        // The mesh keeps only triangles whose normal has a length (mesh.cpp); its own normal stands
        // in should the rotated corners' cross product still vanish.
        const glm::dvec3 cross = glm::cross(b - a, c - a);
        const double area = glm::length(cross);
        glm::dvec3 n = area > 0.0 ? cross / area : glm::dvec3(mesh.faceNormals[id]);
        n = glm::normalize(n - glm::dot(n, e1) * e1);
        const glm::dvec3 e2 = glm::cross(n, e1);
        const double cu = glm::dot(c - a, e1), cv = glm::dot(c - a, e2), bcu = cu - length;
        p.ax[lane] = float(a.x), p.ay[lane] = float(a.y), p.az[lane] = float(a.z);
        p.e1x[lane] = float(e1.x), p.e1y[lane] = float(e1.y), p.e1z[lane] = float(e1.z);
        p.e2x[lane] = float(e2.x), p.e2y[lane] = float(e2.y), p.e2z[lane] = float(e2.z);
        p.nx[lane] = float(n.x), p.ny[lane] = float(n.y), p.nz[lane] = float(n.z);
        p.length[lane] = float(length), p.cu[lane] = float(cu), p.cv[lane] = float(cv), p.bcu[lane] = float(bcu);
        p.invAC[lane] = inverse(cu * cu + cv * cv), p.invBC[lane] = inverse(bcu * bcu + cv * cv);
        p.id[lane] = std::int32_t(id);
    }
}

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
    parallelFor((packets_.size() + kPacketsPerItem - 1) / kPacketsPerItem, quiet(control), [&](std::size_t item) {
        for (std::size_t i = item * kPacketsPerItem; i < std::min(packets_.size(), (item + 1) * kPacketsPerItem); ++i) {
            fillPacket(mesh, layout.packetIds[i], packets_[i]);
        }
    });
    nodes_ = std::move(layout.nodes);
    putRootFirst(nodes_);
    leafBounds_ = std::move(layout.leafBounds);
}

WideBvh::WideBvh(const WideBvh& previous, const Mesh& mesh, const RunControl& control, WideBvh* spare) {
    if (spare) { // its memory, every element written below
        nodes_ = std::move(spare->nodes_);
        packets_ = std::move(spare->packets_);
        leafBounds_ = std::move(spare->leafBounds_);
    }
    nodes_.assign(previous.nodes_.begin(), previous.nodes_.end());
    packets_.resize(previous.packets_.size());
    leafBounds_.resize(previous.leafBounds_.size());
    constexpr std::size_t kPacketsPerItem = 1024;
    parallelFor((packets_.size() + kPacketsPerItem - 1) / kPacketsPerItem, quiet(control), [&](std::size_t item) {
        for (std::size_t i = item * kPacketsPerItem; i < std::min(packets_.size(), (item + 1) * kPacketsPerItem); ++i) {
            PacketIds ids;
            for (int lane = 0; lane < kWidth; ++lane) ids[std::size_t(lane)] = std::uint32_t(previous.packets_[i].id[lane]);
            fillPacket(mesh, ids, packets_[i]);
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
