#include "core/accel/bvh.hpp"
#include "core/mesh/triangle_copies.hpp"
#include "core/runtime/parallel.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <algorithm>
#include <cmath>
#include <limits>

namespace sdfgen {

namespace {

constexpr int kBins = 16;
constexpr std::size_t kParallelBuild = 4096; // triangles below which a subtree is built serially
// Triangles from which a node's own bounds, bins and partition are computed in parallel: near the
// root one node spans the whole mesh and would otherwise hold up every thread but one.
constexpr std::size_t kParallelNode = std::size_t(1) << 15;
constexpr std::size_t kGrain = 8192; // elements per parallel chunk (fixed: the schedule never shows in results)
constexpr double kTraversalCost = 1.0; // relative to one ray/triangle test

// The build's records: a triangle's box and centroid as four float lanes (x, y, z and an unused
// one, kept 0), so that a box grows by two vector operations instead of six scalar ones.
typedef float float4 __attribute__((vector_size(16)));
typedef double double2 __attribute__((vector_size(16)));
constexpr float kMax = std::numeric_limits<float>::max();
constexpr float4 kEmptyMin = {kMax, kMax, kMax, 0.0f}, kEmptyMax = {-kMax, -kMax, -kMax, 0.0f};
// std::min and std::max per lane (the first operand kept on ties, as glm::min/max do).
inline float4 lanesMin(const float4& a, const float4& b) { return b < a ? b : a; }
inline float4 lanesMax(const float4& a, const float4& b) { return a < b ? b : a; }

struct BuildBox {
    float4 min = kEmptyMin, max = kEmptyMax;
    // Growing the empty box by a finite box gives that box exactly.
    void grow(const BuildBox& other) {
        min = lanesMin(min, other.min);
        max = lanesMax(max, other.max);
    }
    Bounds bounds() const { return {{min[0], min[1], min[2]}, {max[0], max[1], max[2]}}; }
};

// halfArea(box.bounds()), without the copy.
inline double halfArea(const BuildBox& b) {
    double2 xy = double2{double(b.max[0]), double(b.max[1])} - double2{double(b.min[0]), double(b.min[1])};
    xy = xy < 0.0 ? double2{} : xy; // std::max(extent, 0.0)
    const double x = xy[0], y = xy[1], z = std::max(double(b.max[2]) - double(b.min[2]), 0.0);
    return x * y + y * z + z * x;
}

// Bins in double, clamped before the conversion to int: at any float span (subnormal extents
// included) a bin index is always a valid one, never int(inf) or int(NaN) (NaN > 0 is false).
inline double clampBin(double bin) {
    bin = bin > 0.0 ? bin : 0.0;
    return bin < double(kBins - 1) ? bin : double(kBins - 1);
}
inline int binOf(float centroid, float lo, double scale) { return int(clampBin((double(centroid) - double(lo)) * scale)); }

struct NodeBounds {
    BuildBox box, centroidBox;
    void add(const BuildBox& triangleBox, const float4& centroid) {
        box.grow(triangleBox);
        centroidBox.grow({centroid, centroid});
    }
    void merge(const NodeBounds& other) {
        box.grow(other.box);
        centroidBox.grow(other.centroidBox);
    }
};

// Bins of all three axes, computed for every axis without a branch (an axis whose scale is 0 is
// binned all into bin 0 and not searched). Every box starts empty and grows without a branch:
// most nodes hold a few triangles, and a first-in-bin test would mispredict for nearly each of
// theirs.
struct Bins {
    BuildBox box[3][kBins];
    std::uint32_t count[3][kBins] = {}; // a tree holds fewer than 2^32 triangles (32-bit ids)
    struct Scale {
        double2 loXY, scaleXY;
        double loZ, scaleZ;
    };
    void add(const BuildBox& triangleBox, const float4& centroid, const Scale& s) {
        // (double(centroid) - double(lo)) * scale per axis, x and y in one vector.
        double2 xy = (double2{double(centroid[0]), double(centroid[1])} - s.loXY) * s.scaleXY;
        xy = xy > 0.0 ? xy : double2{};
        xy = xy < double(kBins - 1) ? xy : double2{} + double(kBins - 1);
        const int bin[3] = {int(xy[0]), int(xy[1]), int(clampBin((double(centroid[2]) - s.loZ) * s.scaleZ))};
        for (int axis = 0; axis < 3; ++axis) {
            ++count[axis][bin[axis]];
            box[axis][bin[axis]].grow(triangleBox);
        }
    }
    void merge(const Bins& other) {
        for (int axis = 0; axis < 3; ++axis) {
            for (int b = 0; b < kBins; ++b) {
                box[axis][b].grow(other.box[axis][b]);
                count[axis][b] += other.count[axis][b];
            }
        }
    }
};

} // namespace

struct BvhBuildRecords {
    std::vector<BuildBox> boxes;
    std::vector<float4> centroids;
};

namespace {

// Min, max and sums are exact and order-free, so the parallel reductions equal the serial loop.
// One named result (returned in place: Bins is 1.7 kB and most nodes are small).
template <class Stats, class Add>
Stats reduceRange(std::size_t begin, std::size_t end, Add add) {
    Stats stats;
    if (end - begin < kParallelNode) {
        for (std::size_t i = begin; i < end; ++i) add(stats, i);
        return stats;
    }
    stats = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(begin, end, kGrain), Stats(),
        [&](const tbb::blocked_range<std::size_t>& r, Stats stats) {
            for (std::size_t i = r.begin(); i < r.end(); ++i) add(stats, i);
            return stats;
        },
        [](Stats a, const Stats& b) {
            a.merge(b);
            return a;
        });
    return stats;
}

// Stable partition of [begin, end) in fixed chunks: each chunk counts its left items, a prefix sum
// places every chunk, and the items are scattered; the result is one order for any thread count.
template <class Left>
std::size_t partitionStable(std::vector<std::uint32_t>& order, std::size_t begin, std::size_t end, Left left) {
    const std::size_t chunks = (end - begin + kGrain - 1) / kGrain;
    std::vector<std::size_t> leftCount(chunks);
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
        const std::size_t from = begin + c * kGrain, to = std::min(end, from + kGrain);
        std::size_t k = 0;
        for (std::size_t i = from; i < to; ++i) k += left(order[i]) ? 1 : 0;
        leftCount[c] = k;
    });
    std::vector<std::size_t> leftStart(chunks), rightStart(chunks);
    std::size_t totalLeft = 0;
    for (std::size_t c = 0; c < chunks; ++c) {
        leftStart[c] = totalLeft;
        totalLeft += leftCount[c];
    }
    for (std::size_t c = 0; c < chunks; ++c) rightStart[c] = totalLeft + c * kGrain - leftStart[c];
    std::vector<std::uint32_t> sorted(end - begin);
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
        const std::size_t from = begin + c * kGrain, to = std::min(end, from + kGrain);
        std::size_t l = leftStart[c], r = rightStart[c];
        for (std::size_t i = from; i < to; ++i) sorted[left(order[i]) ? l++ : r++] = order[i];
    });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, sorted.size(), kGrain), [&](const tbb::blocked_range<std::size_t>& r) {
        std::copy(sorted.begin() + std::ptrdiff_t(r.begin()), sorted.begin() + std::ptrdiff_t(r.end()), order.begin() + std::ptrdiff_t(begin + r.begin()));
    });
    return begin + totalLeft;
}

} // namespace

Bvh::Bvh(const Mesh& mesh, const RunControl& control) {
    // Exact copies of a triangle have the same distance and the same hits, and a stack of them
    // would make every query that reaches it visit each one: the tree holds the first copy only
    // (the lowest index, so the wide tree built from it keeps the lower-index tie rule).
    tbb::task_arena arena(arenaSize(control));
    TriangleCopies copies;
    arena.execute([&] { copies = findTriangleCopies(mesh); });
    const std::size_t n = copies.unique.size();
    BvhBuildRecords records{std::vector<BuildBox>(n), std::vector<float4>(n)};
    std::vector<std::uint32_t> order(n);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kGrain), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i < r.end(); ++i) {
                const std::uint32_t t = copies.unique[i];
                const glm::vec3 a = mesh.vertex(t, 0), b = mesh.vertex(t, 1), c = mesh.vertex(t, 2);
                const glm::vec3 lo = glm::min(a, glm::min(b, c)), hi = glm::max(a, glm::max(b, c));
                // Half of each before adding: the sum of two coordinates near the float limit overflows.
                const glm::vec3 centroid = lo * 0.5f + hi * 0.5f;
                records.boxes[i].min = float4{lo.x, lo.y, lo.z, 0.0f};
                records.boxes[i].max = float4{hi.x, hi.y, hi.z, 0.0f};
                records.centroids[i] = float4{centroid.x, centroid.y, centroid.z, 0.0f};
                order[i] = std::uint32_t(i);
            }
        });
    });
    Subtree tree;
    tree.nodes.reserve(2 * n);
    tree.ids.reserve(n);
    ProgressCounter progress(control, n);
    const BuildInput input{records, progress};
    arena.execute([&] { build(tree, order, 0, n, input, 0); });
    progress.finish();
    nodes_ = std::move(tree.nodes);
    triangleIds_ = std::move(tree.ids);
    bounds_ = {glm::vec3(nodes_[0].min[0], nodes_[0].min[1], nodes_[0].min[2]),
               glm::vec3(nodes_[0].max[0], nodes_[0].max[1], nodes_[0].max[2])};
    triangles_.resize(n);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kGrain), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i < r.end(); ++i) {
                const std::uint32_t id = triangleIds_[i] = copies.unique[triangleIds_[i]];
                triangles_[i] = prepareTriangle(mesh.vertex(id, 0), mesh.vertex(id, 1), mesh.vertex(id, 2));
            }
        });
    });
    copies_.assign(mesh.triangleCount(), 0);
    for (std::size_t i = 0; i < n; ++i) copies_[copies.unique[i]] = copies.count[i];
}

Bvh::Bvh(const Bvh& previous, const Mesh& mesh, const RunControl& control, Bvh* spare) {
    if (spare) { // its memory, every element written below
        nodes_ = std::move(spare->nodes_);
        triangles_ = std::move(spare->triangles_);
        triangleIds_ = std::move(spare->triangleIds_);
        copies_ = std::move(spare->copies_);
    }
    nodes_.assign(previous.nodes_.begin(), previous.nodes_.end());
    triangles_.resize(previous.triangles_.size());
    triangleIds_.assign(previous.triangleIds_.begin(), previous.triangleIds_.end());
    copies_.assign(previous.copies_.begin(), previous.copies_.end());
    // The leaves in parallel (their triangles set up and boxed: one read of each triangle's corners),
    // then the inner nodes bottom-up: children follow their parent in the depth-first layout, so in
    // reverse every child is done first.
    auto boxOf = [](const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, glm::vec3& lo, glm::vec3& hi) {
        lo = glm::min(lo, glm::min(a, glm::min(b, c)));
        hi = glm::max(hi, glm::max(a, glm::max(b, c)));
    };
    auto setBox = [](Node& n, const glm::vec3& lo, const glm::vec3& hi) {
        for (int a = 0; a < 3; ++a) n.min[a] = lo[a], n.max[a] = hi[a];
    };
    constexpr std::size_t kNodesPerItem = 2048;
    parallelFor((nodes_.size() + kNodesPerItem - 1) / kNodesPerItem, quiet(control), [&](std::size_t item) {
        for (std::size_t i = item * kNodesPerItem; i < std::min(nodes_.size(), (item + 1) * kNodesPerItem); ++i) {
            Node& n = nodes_[i];
            if (n.count == 0) continue;
            glm::vec3 lo(kMax), hi(-kMax);
            for (std::uint32_t slot = n.index; slot < n.index + n.count; ++slot) {
                const std::uint32_t id = triangleIds_[slot];
                const glm::vec3 a = mesh.vertex(id, 0), b = mesh.vertex(id, 1), c = mesh.vertex(id, 2);
                triangles_[slot] = prepareTriangle(a, b, c);
                boxOf(a, b, c, lo, hi);
            }
            setBox(n, lo, hi);
        }
    });
    for (std::size_t i = nodes_.size(); i-- > 0;) {
        Node& n = nodes_[i];
        if (n.count > 0) continue;
        const Node &first = nodes_[i + 1], &second = nodes_[n.index];
        setBox(n, glm::min(glm::vec3(first.min[0], first.min[1], first.min[2]), glm::vec3(second.min[0], second.min[1], second.min[2])),
               glm::max(glm::vec3(first.max[0], first.max[1], first.max[2]), glm::vec3(second.max[0], second.max[1], second.max[2])));
    }
    bounds_ = {glm::vec3(nodes_[0].min[0], nodes_[0].min[1], nodes_[0].min[2]),
               glm::vec3(nodes_[0].max[0], nodes_[0].max[1], nodes_[0].max[2])};
}

std::uint32_t Bvh::build(Subtree& out, std::vector<std::uint32_t>& order, std::size_t begin, std::size_t end,
                         const BuildInput& input, int depth) {
    const std::vector<float4>& centroids = input.records.centroids;
    const std::vector<BuildBox>& boxes = input.records.boxes;
    input.progress.checkCancel();
    std::vector<Node>& nodes = out.nodes;
    std::vector<std::uint32_t>& ids = out.ids;
    const NodeBounds nodeBounds = reduceRange<NodeBounds>(begin, end, [&](NodeBounds& b, std::size_t i) {
        b.add(boxes[order[i]], centroids[order[i]]);
    });
    const Bounds box = nodeBounds.box.bounds(), centroidBox = nodeBounds.centroidBox.bounds();
    const std::uint32_t nodeIndex = std::uint32_t(nodes.size());
    nodes.push_back({{box.min.x, box.min.y, box.min.z}, {box.max.x, box.max.y, box.max.z}, 0, 0, 0});
    const std::size_t count = end - begin;

    auto makeLeaf = [&] {
        nodes[nodeIndex].index = std::uint32_t(ids.size());
        nodes[nodeIndex].count = std::uint16_t(count);
        ids.insert(ids.end(), order.begin() + std::ptrdiff_t(begin), order.begin() + std::ptrdiff_t(end));
        input.progress.add(count);
        return nodeIndex;
    };
    auto children = [&](std::size_t middle, int axis) {
        nodes[nodeIndex].axis = std::uint16_t(axis);
        if (count < kParallelBuild) {
            build(out, order, begin, middle, input, depth + 1);
            nodes[nodeIndex].index = build(out, order, middle, end, input, depth + 1);
            return nodeIndex;
        }
        // The halves touch disjoint ranges of `order`; the second is built apart and appended.
        Subtree second;
        tbb::parallel_invoke([&] { build(out, order, begin, middle, input, depth + 1); },
                             [&] { build(second, order, middle, end, input, depth + 1); });
        const std::uint32_t nodeBase = std::uint32_t(nodes.size()), idBase = std::uint32_t(ids.size());
        for (Node node : second.nodes) {
            node.index += node.count == 0 ? nodeBase : idBase;
            nodes.push_back(node);
        }
        ids.insert(ids.end(), second.ids.begin(), second.ids.end());
        nodes[nodeIndex].index = nodeBase;
        return nodeIndex;
    };
    auto buildMedian = [&] {
        if (count <= std::size_t(kMaxLeafSize)) return makeLeaf();
        int axis = 0;
        for (int a = 1; a < 3; ++a) {
            if (double(centroidBox.max[a]) - centroidBox.min[a] > double(centroidBox.max[axis]) - centroidBox.min[axis]) axis = a;
        }
        const std::size_t middle = begin + count / 2;
        std::nth_element(order.begin() + std::ptrdiff_t(begin), order.begin() + std::ptrdiff_t(middle),
                         order.begin() + std::ptrdiff_t(end), [&](std::uint32_t l, std::uint32_t r) {
                             return centroids[l][axis] != centroids[r][axis] ? centroids[l][axis] < centroids[r][axis] : l < r;
                         });
        return children(middle, axis);
    };
    if (count <= 1) return makeLeaf();
    // The SAH may peel off one triangle per level (exponentially spaced centroids do that), so once
    // halving at every level left is just enough to reach kMaxLeafSize before kMaxDepth, the node
    // splits at the median instead: depth and leaf size stay bounded on any input.
    int levelsNeeded = 0;
    while ((std::size_t(kMaxLeafSize) << levelsNeeded) < count) ++levelsNeeded;
    if (levelsNeeded >= kMaxDepth - depth - 1) return buildMedian();

    // Binned SAH: try kBins - 1 planes on each axis, keep the cheapest split.
    int bestAxis = -1, bestPlane = 0;
    double bestCost = std::numeric_limits<double>::max();
    const glm::dvec3 centroidExtent = glm::dvec3(centroidBox.max) - glm::dvec3(centroidBox.min); // no float overflow
    glm::dvec3 scales(0.0);
    for (int axis = 0; axis < 3; ++axis) {
        const double scale = kBins / centroidExtent[axis];
        if (centroidExtent[axis] > 0.0 && std::isfinite(scale)) scales[axis] = scale;
    }
    const Bins::Scale binScale{{double(centroidBox.min.x), double(centroidBox.min.y)}, {scales.x, scales.y},
                               double(centroidBox.min.z), scales.z};
    const Bins bins = reduceRange<Bins>(begin, end, [&](Bins& b, std::size_t i) {
        const std::uint32_t t = order[i];
        b.add(boxes[t], centroids[t], binScale);
    });
    for (int axis = 0; axis < 3; ++axis) {
        if (scales[axis] == 0.0) continue;
        const BuildBox* binBox = bins.box[axis];
        const std::uint32_t* binCount = bins.count[axis];
        double rightArea[kBins];
        std::size_t rightCount[kBins];
        // Empty bins are skipped: they change no box or count, and a plane right after one costs
        // exactly what the plane before it did, which the strict comparison below already keeps.
        BuildBox acc;
        std::size_t accCount = 0;
        double accArea = 0.0;
        for (int b = kBins - 1; b > 0; --b) {
            if (binCount[b] > 0) {
                acc.grow(binBox[b]);
                accCount += binCount[b];
                accArea = halfArea(acc);
            }
            rightArea[b] = accArea;
            rightCount[b] = accCount;
        }
        acc = BuildBox();
        accCount = 0;
        for (int plane = 1; plane < kBins; ++plane) {
            if (binCount[plane - 1] == 0) continue;
            acc.grow(binBox[plane - 1]);
            accCount += binCount[plane - 1];
            if (rightCount[plane] == 0) continue;
            const double cost = halfArea(acc) * double(accCount) + rightArea[plane] * double(rightCount[plane]);
            if (cost < bestCost) {
                bestCost = cost;
                bestAxis = axis;
                bestPlane = plane;
            }
        }
    }

    if (bestAxis < 0) return buildMedian(); // all centroids coincide: no plane separates them
    // A box of zero area (all triangles in one axis-aligned plane segment) splits by count alone.
    const double area = halfArea(box);
    const double splitCost = area > 0.0 ? kTraversalCost + bestCost / area : kTraversalCost;
    if (splitCost >= double(count) && count <= std::size_t(kMaxLeafSize)) return makeLeaf();
    const double scale = kBins / centroidExtent[bestAxis];
    const float lo = centroidBox.min[bestAxis];
    auto left = [&](std::uint32_t t) { return binOf(centroids[t][bestAxis], lo, scale) < bestPlane; };
    if (count >= kParallelNode) return children(partitionStable(order, begin, end, left), bestAxis);
    auto* split = std::partition(order.data() + begin, order.data() + end, left);
    return children(std::size_t(split - order.data()), bestAxis);
}

} // namespace sdfgen
