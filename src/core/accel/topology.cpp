#include "core/accel/topology.hpp"
#include "core/mesh/triangle_copies.hpp"
#include "core/runtime/parallel.hpp"
#include "core/mesh/predicates.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <numeric>
#include <tuple>
#include <unordered_map>

namespace sdfgen {

namespace {

// Whether the vertices of triangle p (indices pi) that triangle q (indices qi) lacks all lie
// strictly on one side of q's plane; never for a degenerate q, whose orientations are all zero.
bool strictlyOnOneSide(const glm::vec3 (&p)[3], const glm::uvec3& pi, const glm::vec3 (&q)[3], const glm::uvec3& qi) {
    int side = 0;
    for (int i = 0; i < 3; ++i) {
        if (qi[0] == pi[i] || qi[1] == pi[i] || qi[2] == pi[i]) continue;
        const int s = orient3d(q[0], q[1], q[2], p[i]);
        if (s == 0 || (side != 0 && s != side)) return false;
        side = s;
    }
    return side != 0;
}

// Whether a plane through an edge of triangle p along direction m proves that p and q meet at
// shared vertices at most: p's third vertex strictly on one side, q's vertices off that edge
// strictly on the other (so q touches the plane at shared edge ends only, and p lies on its own
// side). In double with a rounding-error bound, no exact fallback: false when in doubt. Each
// monomial of the side value det(end - start, m, x - start) passes through at most 8 roundings
// for an exact m, so orient3d's bound, (8 + 256u) u times the computed permanent, holds here too.
// A far cheaper proof than the exact predicates for the nearly coplanar pairs of a finely
// tessellated surface (two triangles of one vertex fan, say), where orient3d needs its exact sums.
bool separatedByEdgePlane(const glm::vec3 (&p)[3], const glm::uvec3& pi, const glm::vec3 (&q)[3], const glm::uvec3& qi,
                          const glm::dvec3& m) {
    constexpr double u = DBL_EPSILON / 2;
    constexpr double kBound = (8.0 + 256.0 * u) * u;
    for (int e = 0; e < 3; ++e) {
        const int f = (e + 1) % 3;
        const glm::dvec3 start(p[e]), edge = glm::dvec3(p[f]) - start;
        const double nx1 = edge.y * m.z, nx2 = edge.z * m.y, ny1 = edge.z * m.x, ny2 = edge.x * m.z, nz1 = edge.x * m.y,
                     nz2 = edge.y * m.x;
        const glm::dvec3 normal(nx1 - nx2, ny1 - ny2, nz1 - nz2);
        const glm::dvec3 magnitude(std::fabs(nx1) + std::fabs(nx2), std::fabs(ny1) + std::fabs(ny2), std::fabs(nz1) + std::fabs(nz2));
        const auto side = [&](const glm::vec3& x) {
            const glm::dvec3 d = glm::dvec3(x) - start;
            const double value = d.x * normal.x + d.y * normal.y + d.z * normal.z;
            const double bound = kBound * (std::fabs(d.x) * magnitude.x + std::fabs(d.y) * magnitude.y + std::fabs(d.z) * magnitude.z);
            return value > bound ? 1 : value < -bound ? -1 : 0;
        };
        const int own = side(p[(e + 2) % 3]);
        if (own == 0) continue;
        bool apart = true;
        for (int k = 0; k < 3 && apart; ++k) {
            if (qi[k] == pi[e] || qi[k] == pi[f]) continue; // on the edge, in the plane exactly
            apart = side(q[k]) == -own;
        }
        if (apart) return true;
    }
    return false;
}

constexpr std::size_t kCornerChunk = 4096; // triangles per parallel chunk (fixed: results never depend on it)
constexpr std::size_t kAngleBlock = std::size_t(1) << 16; // triangles whose corner angles are held at once

std::uint32_t findRoot(std::vector<std::uint32_t>& parent, std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

} // namespace

std::string MeshCheck::describe() const {
    return std::to_string(boundaryEdges) + " boundary edges, " + std::to_string(nonManifoldEdges) + " non-manifold edges, " +
           std::to_string(inconsistentEdges) + " inconsistently oriented edges, " + std::to_string(nonManifoldVertices) +
           " non-manifold vertices, " +
           (selfIntersectionsSearched ? std::to_string(selfIntersections) + " self-intersecting triangle pairs"
                                      : std::string("self-intersections not searched")) +
           (misorientedShells ? ", " + std::to_string(misorientedShells) + " closed shells facing against their nesting" : "") +
           (insideOut ? ", inside out (negative volume)" : "");
}

namespace {

std::vector<std::uint32_t> copiesOf(const Mesh& mesh) {
    const TriangleCopies copies = findTriangleCopies(mesh);
    std::vector<std::uint32_t> counts(mesh.triangleCount(), 0);
    for (std::size_t i = 0; i < copies.unique.size(); ++i) counts[copies.unique[i]] = copies.count[i];
    return counts;
}

std::vector<std::uint32_t> copiesOf(const Mesh& mesh, const Bvh& tree) {
    std::vector<std::uint32_t> counts(mesh.triangleCount());
    for (std::uint32_t t = 0; t < mesh.triangleCount(); ++t) counts[t] = tree.copies(t);
    return counts;
}

} // namespace

MeshTopology::MeshTopology(const Mesh& mesh, const RunControl& control) : MeshTopology(mesh, copiesOf(mesh), control) {}

MeshTopology::MeshTopology(const Mesh& mesh, const Bvh& tree, const RunControl& control)
    : MeshTopology(mesh, copiesOf(mesh, tree), control) {}

namespace {

// Every triangle edge as (low vertex, high vertex, triangle, which edge, runs low->high).
struct EdgeUse {
    std::uint32_t lo, hi, triangle;
    std::uint8_t edge;
    bool forward;
};

// The edge pass: every edge of the triangles over merged vertices (edges collapsed by merging left
// out), sorted by (lo, hi, triangle, edge), a total order (each triangle's edge is used once):
// placed by their low vertex in triangle order (a counting sort, linear), then each vertex's few
// uses sorted by the high vertex, in parallel; the one list any sort gives, for any thread count.
std::vector<EdgeUse> sortedEdgeUses(const std::vector<glm::uvec3>& corners, std::size_t vertexCount, const RunControl& control) {
    const std::size_t n = corners.size();
    std::vector<std::size_t> firstUse(vertexCount + 1, 0);
    for (std::uint32_t t = 0; t < n; ++t) {
        for (std::uint8_t e = 0; e < 3; ++e) {
            const std::uint32_t u = corners[t][e], v = corners[t][(e + 1) % 3];
            if (u != v) ++firstUse[std::min(u, v) + 1];
        }
    }
    std::partial_sum(firstUse.begin(), firstUse.end(), firstUse.begin());
    std::vector<EdgeUse> uses(firstUse.back());
    {
        std::vector<std::size_t> next(firstUse.begin(), firstUse.end() - 1);
        for (std::uint32_t t = 0; t < n; ++t) {
            for (std::uint8_t e = 0; e < 3; ++e) {
                const std::uint32_t u = corners[t][e], v = corners[t][(e + 1) % 3];
                if (u != v) uses[next[std::min(u, v)]++] = {std::min(u, v), std::max(u, v), t, e, u < v};
            }
        }
    }
    constexpr std::size_t kVerticesPerItem = 4096;
    parallelFor((vertexCount + kVerticesPerItem - 1) / kVerticesPerItem, quiet(control), [&](std::size_t item) {
        const std::size_t from = item * kVerticesPerItem, to = std::min(vertexCount, from + kVerticesPerItem);
        for (std::size_t vertex = from; vertex < to; ++vertex) {
            std::sort(uses.begin() + std::ptrdiff_t(firstUse[vertex]), uses.begin() + std::ptrdiff_t(firstUse[vertex + 1]),
                      [](const EdgeUse& x, const EdgeUse& y) { return std::tie(x.hi, x.triangle, x.edge) < std::tie(y.hi, y.triangle, y.edge); });
        }
    });
    return uses;
}

// What the pairing pass leaves for the later ones.
struct EdgePairing {
    // Corners (3 per triangle) around a vertex joined across manifold edges (a union-find forest):
    // more than one group at a vertex means its triangles form separate fans.
    std::vector<std::uint32_t> cornerParent;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> boundary; // directed edges, with multiplicity
};

// The pairing pass: each run of uses of one edge counted (boundary, non-manifold, inconsistent),
// the two triangles of a manifold edge made neighbours and their corners joined, and the uses
// that do not cancel out kept as boundary edges.
EdgePairing pairEdges(const std::vector<EdgeUse>& uses, MeshTopology::Links& links) {
    const std::vector<glm::uvec3>& corners = links.corners;
    links.edgeNeighbours.assign(3 * corners.size(), MeshTopology::kNoNeighbour);
    EdgePairing pairing;
    pairing.cornerParent.resize(3 * corners.size());
    std::iota(pairing.cornerParent.begin(), pairing.cornerParent.end(), 0u);
    auto cornerOf = [&](std::uint32_t t, std::uint32_t vertex) {
        for (std::uint32_t c = 0; c < 3; ++c) {
            if (corners[t][c] == vertex) return 3 * t + c;
        }
        return 3 * t;
    };
    MeshCheck& counts = links.edgeCounts;
    for (std::size_t begin = 0; begin < uses.size();) {
        std::size_t end = begin;
        int net = 0;
        while (end < uses.size() && uses[end].lo == uses[begin].lo && uses[end].hi == uses[begin].hi) {
            net += uses[end].forward ? 1 : -1;
            ++end;
        }
        const std::size_t count = end - begin;
        const EdgeUse& first = uses[begin];
        if (count == 1) ++counts.boundaryEdges;
        if (count > 2) ++counts.nonManifoldEdges;
        if (count == 2) {
            const EdgeUse& second = uses[begin + 1];
            if (first.forward == second.forward) ++counts.inconsistentEdges;
            // The edge's pseudonormal is the sum of its two face normals (each face's angle is π).
            links.edgeNeighbours[3 * first.triangle + first.edge] = second.triangle;
            links.edgeNeighbours[3 * second.triangle + second.edge] = first.triangle;
            for (std::uint32_t vertex : {first.lo, first.hi}) {
                const std::uint32_t a = findRoot(pairing.cornerParent, cornerOf(first.triangle, vertex));
                const std::uint32_t b = findRoot(pairing.cornerParent, cornerOf(second.triangle, vertex));
                pairing.cornerParent[a] = b;
            }
        }
        for (int k = 0; k < std::abs(net); ++k) {
            pairing.boundary.emplace_back(net > 0 ? first.lo : first.hi, net > 0 ? first.hi : first.lo);
        }
        begin = end;
    }
    return pairing;
}

// The vertices whose corners form more than one fan (see EdgePairing::cornerParent).
std::size_t countPinchedVertices(const std::vector<glm::uvec3>& corners, std::vector<std::uint32_t>& cornerParent, std::size_t vertexCount) {
    std::vector<std::uint32_t> fanRoot(vertexCount, UINT32_MAX);
    std::vector<bool> pinched(vertexCount, false);
    for (std::uint32_t t = 0; t < corners.size(); ++t) {
        for (std::uint32_t c = 0; c < 3; ++c) {
            const std::uint32_t v = corners[t][c];
            const std::uint32_t root = findRoot(cornerParent, 3 * t + c);
            if (fanRoot[v] == UINT32_MAX) fanRoot[v] = root;
            else if (fanRoot[v] != root) pinched[v] = true;
        }
    }
    return std::size_t(std::count(pinched.begin(), pinched.end(), true));
}

// The loops pass: the boundary edges split into closed loops (a boundary is a cycle, so every
// walk returns). Each vertex keeps a cursor to its first possibly unused outgoing edge, so many
// copies of one edge (a stack of duplicated open triangles) cost linear time, not quadratic.
std::vector<std::vector<std::uint32_t>> boundaryLoopsOf(std::vector<std::pair<std::uint32_t, std::uint32_t>> boundary) {
    std::sort(boundary.begin(), boundary.end());
    std::vector<bool> used(boundary.size(), false);
    std::unordered_map<std::uint32_t, std::size_t> nextOut; // vertex -> its first outgoing edge not known used
    for (std::size_t e = boundary.size(); e-- > 0;) nextOut[boundary[e].first] = e;
    auto takeOut = [&](std::uint32_t vertex) {
        const auto it = nextOut.find(vertex);
        if (it == nextOut.end()) return boundary.size();
        std::size_t& next = it->second;
        while (next < boundary.size() && boundary[next].first == vertex && used[next]) ++next;
        return next < boundary.size() && boundary[next].first == vertex ? next : boundary.size();
    };
    std::vector<std::vector<std::uint32_t>> loops;
    for (std::size_t start = 0; start < boundary.size(); ++start) {
        if (used[start]) continue;
        std::vector<std::uint32_t> loop;
        std::size_t edge = start;
        while (true) {
            used[edge] = true;
            loop.push_back(boundary[edge].first);
            const std::uint32_t head = boundary[edge].second;
            if (head == boundary[start].first) break;
            edge = takeOut(head);
            if (edge >= boundary.size()) break; // cannot happen for a cycle
        }
        loops.push_back(std::move(loop));
    }
    return loops;
}

} // namespace

MeshTopology::MeshTopology(const Mesh& mesh, std::vector<std::uint32_t> copies, const RunControl& control) {
    // Serial stages, each about as long as a pass over the triangles: progress and cancel between them.
    constexpr std::size_t kStages = 5;
    ProgressCounter progress(control, kStages);
    groups_ = std::make_shared<const VertexGroups>(mesh.positions, control);
    auto links = std::make_shared<Links>();
    links->copies = std::move(copies);
    links->corners.resize(mesh.triangleCount());
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        for (int c = 0; c < 3; ++c) links->corners[t][c] = groups_->groupOf(mesh.triangles[t][c]);
    }
    takePositions(mesh);
    progress.add(1);
    const std::vector<EdgeUse> uses = sortedEdgeUses(links->corners, groups_->count(), control);
    progress.add(1);
    EdgePairing pairing = pairEdges(uses, *links);
    progress.add(1);
    links->edgeCounts.nonManifoldVertices = countPinchedVertices(links->corners, pairing.cornerParent, groups_->count());
    links->edgeCounts.selfIntersectionsSearched = false;
    links->loops = boundaryLoopsOf(std::move(pairing.boundary));
    progress.add(1);
    links_ = std::move(links);
    edgeCheck_ = links_->edgeCounts;
    measurePositions(control, true);
    progress.add(1);
    progress.finish();
}

MeshTopology::MeshTopology(const MeshTopology& previous, const Mesh& mesh, const RunControl& control)
    : groups_(previous.groups_), links_(previous.links_), edgeCheck_(previous.links_->edgeCounts) {
    takePositions(mesh);
    vertexCorners_ = previous.vertexCorners_;
    if (!vertexCorners_) { // the chain's first refit: each vertex's corners, by a counting sort in triangle order
        auto corners = std::make_shared<VertexCorners>();
        const std::vector<glm::uvec3>& triangles = links_->corners;
        corners->start.assign(positions_.size() + 1, 0);
        for (const glm::uvec3& t : triangles) {
            for (int c = 0; c < 3; ++c) ++corners->start[t[c] + 1];
        }
        std::partial_sum(corners->start.begin(), corners->start.end(), corners->start.begin());
        corners->corner.resize(3 * triangles.size());
        std::vector<std::uint32_t> next(corners->start.begin(), corners->start.end() - 1);
        for (std::size_t t = 0; t < triangles.size(); ++t) {
            for (std::uint32_t c = 0; c < 3; ++c) corners->corner[next[triangles[t][c]]++] = std::uint32_t(3 * t + c);
        }
        vertexCorners_ = std::move(corners);
    }
    vertexNormals_.resize(positions_.size());
    vertexNormalState_.reset(new std::atomic<std::uint8_t>[positions_.size()]());
    measurePositions(control, false);
}

void MeshTopology::takePositions(const Mesh& mesh) {
    positions_.resize(groups_->count());
    for (std::size_t g = 0; g < positions_.size(); ++g) positions_[g] = glm::dvec3(mesh.positions[groups_->firstVertex(g)] + glm::vec3(0.0f));
    faceNormals_.assign(mesh.faceNormals.begin(), mesh.faceNormals.end());
}

void MeshTopology::measurePositions(const RunControl& control, bool eagerNormals) {
    // Signed volume by the divergence theorem, about the first vertex to keep the sum precise.
    double volume = 0.0;
    for (const glm::uvec3& t : links_->corners) {
        const glm::dvec3 o = positions_.front();
        volume += glm::dot(positions_[t[0]] - o, glm::cross(positions_[t[1]] - o, positions_[t[2]] - o));
    }
    edgeCheck_.signedVolume = volume / 6.0;
    edgeCheck_.insideOut = edgeCheck_.boundaryEdges == 0 && edgeCheck_.nonManifoldEdges == 0 &&
                           edgeCheck_.inconsistentEdges == 0 && edgeCheck_.signedVolume < 0.0;
    // The vertex normals serve the pseudonormal sign only, which auto picks only for meshes whose
    // edges are clean: built now for those, on first use for others (a forced --sign pseudonormal).
    if (eagerNormals && edgeCheck_.closedAndClean()) buildVertexNormals(&control);
}

bool MeshTopology::trianglesCross(std::uint32_t t, std::uint32_t u) const {
    const glm::uvec3 a = links_->corners[t], b = links_->corners[u];
    int shared = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) shared += a[i] == b[j];
    if (shared >= 2) return false; // neighbours across an edge can only overlap if coplanar
    // The merged positions are the mesh's floats, which the exact predicates take.
    const glm::vec3 pa[3] = {glm::vec3(positions_[a[0]]), glm::vec3(positions_[a[1]]), glm::vec3(positions_[a[2]])};
    const glm::vec3 pb[3] = {glm::vec3(positions_[b[0]]), glm::vec3(positions_[b[1]]), glm::vec3(positions_[b[2]])};
    // A plane through an edge of either, along their mean normal, often separates them (all in
    // double: the cheapest proof, when it holds).
    const glm::dvec3 meanNormal = glm::dvec3(faceNormals_[t]) + glm::dvec3(faceNormals_[u]);
    if (separatedByEdgePlane(pa, a, pb, b, meanNormal) || separatedByEdgePlane(pb, b, pa, a, meanNormal)) return false;
    // Then exact rejection: when one triangle's vertices (shared ones aside) lie strictly on one
    // side of the other's plane, the pair meets at shared vertices at most, so none of the edge
    // tests below could find a crossing.
    if (strictlyOnOneSide(pa, a, pb, b) || strictlyOnOneSide(pb, b, pa, a)) return false;
    // An edge from a shared vertex meets the other triangle there, so only edges away from shared
    // vertices are tested: any other common point makes the pair self-intersecting.
    for (int e = 0; e < 3; ++e) {
        const std::uint32_t u0 = a[e], u1 = a[(e + 1) % 3];
        if (!(b[0] == u0 || b[1] == u0 || b[2] == u0 || b[0] == u1 || b[1] == u1 || b[2] == u1) &&
            segmentMeetsTriangle(pa[e], pa[(e + 1) % 3], pb[0], pb[1], pb[2])) {
            return true;
        }
        const std::uint32_t v0 = b[e], v1 = b[(e + 1) % 3];
        if (!(a[0] == v0 || a[1] == v0 || a[2] == v0 || a[0] == v1 || a[1] == v1 || a[2] == v1) &&
            segmentMeetsTriangle(pb[e], pb[(e + 1) % 3], pa[0], pa[1], pa[2])) {
            return true;
        }
    }
    return false;
}

namespace {

bool overlap(const Bounds& a, const Bounds& b) {
    return a.min.x <= b.max.x && a.max.x >= b.min.x && a.min.y <= b.max.y && a.max.y >= b.min.y && a.min.z <= b.max.z &&
           a.max.z >= b.min.z;
}

// A pair of tree nodes whose triangle pairs are to be visited: one from each, or, where both are
// the same node, the pairs within it.
struct NodePair {
    std::uint32_t a, b;
};

// Replaces a node pair by the pairs of children that may hold overlapping triangles: a node with
// itself by its two children with themselves and with each other; two nodes by the children of
// the larger inner one (by box area) with the other, or by nothing when their boxes are apart.
// False, adding nothing, when there is nothing to open: a leaf with itself, two leaves.
bool openPair(const Bvh& tree, NodePair pair, std::vector<NodePair>& into) {
    const Bvh::NodeView a = tree.node(pair.a);
    if (pair.a == pair.b) {
        if (a.count > 0) return false;
        into.push_back({a.first, a.first});
        into.push_back({a.second, a.second});
        into.push_back({a.first, a.second});
        return true;
    }
    const Bvh::NodeView b = tree.node(pair.b);
    if (!overlap(a.box, b.box)) return true;
    if (a.count > 0 && b.count > 0) return false;
    if (b.count > 0 || (a.count == 0 && halfArea(a.box) >= halfArea(b.box))) {
        into.push_back({a.first, pair.b});
        into.push_back({a.second, pair.b});
    } else {
        into.push_back({pair.a, b.first});
        into.push_back({pair.a, b.second});
    }
    return true;
}

} // namespace

MeshCheck MeshTopology::check(const Mesh& mesh, const Bvh& tree, const RunControl& control) const {
    MeshCheck result = edgeCheck_;
    result.selfIntersectionsSearched = true;
    const std::size_t held = tree.triangleCount();
    if (held == 0) return result;
    // Every pair of held triangles (first copies; each crossing pair of them stands for
    // copies(t) x copies(u) pairs) whose boxes overlap is tested once, found by one traversal of
    // the tree against itself: node pairs whose boxes overlap are opened down to pairs of leaves.
    // The triangles' boxes, in the tree's leaf order.
    const std::vector<std::uint32_t>& leafTriangles = tree.leafTriangles();
    std::vector<Bounds> boxes(held);
    parallelFor((held + kCornerChunk - 1) / kCornerChunk, quiet(control), [&](std::size_t chunk) {
        for (std::size_t i = chunk * kCornerChunk; i < std::min(held, (chunk + 1) * kCornerChunk); ++i) {
            const std::uint32_t t = leafTriangles[i];
            const glm::vec3 p0 = mesh.vertex(t, 0), p1 = mesh.vertex(t, 1), p2 = mesh.vertex(t, 2);
            boxes[i] = {glm::min(glm::min(p0, p1), p2), glm::max(glm::max(p0, p1), p2)};
        }
    });
    // Node pairs opened level by level into independent jobs, a few per thousand triangles (a
    // fixed split; each job counts its own crossings into its own slot, so the sum is the same for
    // any thread count).
    std::vector<NodePair> jobs{{0, 0}}, next;
    for (std::size_t level = 0; (std::size_t(4096) << level) < held; ++level) {
        next.clear();
        for (const NodePair& pair : jobs) {
            if (!openPair(tree, pair, next)) next.push_back(pair);
        }
        jobs.swap(next);
    }
    std::vector<std::size_t> crossings(jobs.size(), 0);
    parallelFor(jobs.size(), control, [&](std::size_t job) {
        std::size_t found = 0;
        const auto testPair = [&](std::uint32_t i, std::uint32_t j) {
            if (!overlap(boxes[i], boxes[j])) return;
            const std::uint32_t t = std::min(leafTriangles[i], leafTriangles[j]), u = std::max(leafTriangles[i], leafTriangles[j]);
            if (trianglesCross(t, u)) found += std::size_t(tree.copies(t)) * tree.copies(u);
        };
        std::vector<NodePair> stack{jobs[job]};
        while (!stack.empty()) {
            const NodePair pair = stack.back();
            stack.pop_back();
            if (openPair(tree, pair, stack)) continue;
            const Bvh::NodeView a = tree.node(pair.a);
            if (pair.a == pair.b) {
                for (std::uint32_t i = a.slot; i < a.slot + a.count; ++i)
                    for (std::uint32_t j = i + 1; j < a.slot + a.count; ++j) testPair(i, j);
                continue;
            }
            const Bvh::NodeView b = tree.node(pair.b);
            for (std::uint32_t i = a.slot; i < a.slot + a.count; ++i)
                for (std::uint32_t j = b.slot; j < b.slot + b.count; ++j) testPair(i, j);
        }
        crossings[job] = found;
    });
    for (std::size_t count : crossings) result.selfIntersections += count;
    if (result.closedAndClean()) result.misorientedShells = countMisorientedShells(mesh, tree, result.signedVolume < 0.0 ? -1 : 1, control);
    return result;
}

std::size_t MeshTopology::countMisorientedShells(const Mesh& mesh, const Bvh& tree, int outward, const RunControl& control) const {
    // Shells: the triangles' connected parts over merged vertices, numbered by their first triangle.
    const std::vector<glm::uvec3>& corners = links_->corners;
    std::vector<std::uint32_t> parent(positions_.size());
    std::iota(parent.begin(), parent.end(), 0u);
    for (const glm::uvec3& t : corners) {
        for (int c = 1; c < 3; ++c) {
            const std::uint32_t a = findRoot(parent, t[0]), b = findRoot(parent, t[c]);
            if (a != b) parent[std::max(a, b)] = std::min(a, b);
        }
    }
    std::vector<std::uint32_t> shellOfRoot(positions_.size(), UINT32_MAX), shellOf(corners.size());
    std::vector<std::uint32_t> anchor; // per shell: a vertex of it
    for (std::size_t t = 0; t < corners.size(); ++t) {
        std::uint32_t& shell = shellOfRoot[findRoot(parent, corners[t][0])];
        if (shell == UINT32_MAX) {
            shell = std::uint32_t(anchor.size());
            anchor.push_back(corners[t][0]);
        }
        shellOf[t] = shell;
    }
    if (anchor.size() < 2) return 0; // one closed shell faces as its volume says
    std::vector<double> volume(anchor.size(), 0.0); // six times each shell's, about its anchor
    for (std::size_t t = 0; t < corners.size(); ++t) {
        const glm::uvec3& c = corners[t];
        const glm::dvec3& o = positions_[anchor[shellOf[t]]];
        volume[shellOf[t]] += glm::dot(positions_[c[0]] - o, glm::cross(positions_[c[1]] - o, positions_[c[2]] - o));
    }
    // At a vertex of each shell, the other shells' winding number: their signed crossings along +x,
    // counted as the winding sign counts a row's (no other shell meets the vertex: the mesh has no
    // self-intersections). Just outside the shell w is that count, just inside the count plus the
    // shell's facing; the pseudonormal's inside (flipped as a whole when `outward` is -1) is |w| > 1/2
    // only where w is 0 or `outward` on both sides.
    std::vector<std::uint8_t> misoriented(anchor.size(), 0);
    parallelFor(anchor.size(), quiet(control), [&](std::size_t shell) {
        const glm::dvec3 p = positions_[anchor[shell]];
        int around = 0;
        Bounds ray;
        ray.min = glm::vec3(std::nextafter(float(p.x), -FLT_MAX), float(p.y), float(p.z));
        ray.max = glm::vec3(FLT_MAX, float(p.y), float(p.z));
        tree.forEachOverlap(ray, [&](std::uint32_t t) {
            if (shellOf[t] == shell) return;
            const glm::dvec3 a(mesh.vertex(t, 0)), b(mesh.vertex(t, 1)), c(mesh.vertex(t, 2));
            int orientation;
            glm::dvec3 w;
            if (!pointInTriangle2d({p.y, p.z}, {a.y, a.z}, {b.y, b.z}, {c.y, c.z}, orientation, w)) return;
            if (w.x * a.x + w.y * b.x + w.z * c.x > p.x) around += orientation * int(tree.copies(t));
        });
        const int facing = volume[shell] > 0.0 ? 1 : volume[shell] < 0.0 ? -1 : 0;
        misoriented[shell] = !((around == 0 && facing == outward) || (around == outward && facing == -outward));
    });
    return std::size_t(std::count(misoriented.begin(), misoriented.end(), std::uint8_t(1)));
}

glm::dvec3 MeshTopology::pseudonormal(std::uint32_t triangle, TriangleFeature feature) const {
    switch (feature) {
    case TriangleFeature::Face: return glm::dvec3(faceNormals_[triangle]);
    case TriangleFeature::EdgeAB: return edgeNormal(triangle, 0);
    case TriangleFeature::EdgeBC: return edgeNormal(triangle, 1);
    case TriangleFeature::EdgeCA: return edgeNormal(triangle, 2);
    case TriangleFeature::VertexA: return vertexNormal(links_->corners[triangle][0]);
    case TriangleFeature::VertexB: return vertexNormal(links_->corners[triangle][1]);
    case TriangleFeature::VertexC: return vertexNormal(links_->corners[triangle][2]);
    }
    return glm::dvec3(faceNormals_[triangle]);
}

void MeshTopology::buildVertexNormals(const RunControl* control) const {
    std::call_once(vertexNormalsOnce_, [&] {
        const std::vector<glm::uvec3>& corners = links_->corners;
        const std::size_t n = corners.size();
        vertexNormals_.assign(positions_.size(), glm::dvec3(0.0));
        // The corners' angles (the costly part) in parallel, a block of triangles at a time, then
        // summed per vertex in triangle order. Built on first use (no control) they are measured
        // serially: that use may be a parallel loop's task, which must not wait on nested tasks.
        std::vector<double> angle(3 * std::min(n, kAngleBlock));
        for (std::size_t block = 0; block < n; block += kAngleBlock) {
            const std::size_t blockEnd = std::min(n, block + kAngleBlock);
            const auto measure = [&](std::size_t chunk) {
                const std::size_t from = block + chunk * kCornerChunk, to = std::min(blockEnd, from + kCornerChunk);
                for (std::size_t t = from; t < to; ++t) {
                    for (std::uint32_t c = 0; c < 3; ++c) angle[3 * (t - block) + c] = cornerAngle(t, c);
                }
            };
            const std::size_t chunks = (blockEnd - block + kCornerChunk - 1) / kCornerChunk;
            if (control) {
                parallelFor(chunks, quiet(*control), measure);
            } else {
                for (std::size_t chunk = 0; chunk < chunks; ++chunk) measure(chunk);
            }
            for (std::size_t t = block; t < blockEnd; ++t) {
                for (std::uint32_t c = 0; c < 3; ++c) {
                    const double a = angle[3 * (t - block) + c]; // -1: a collapsed corner, no angle
                    if (a >= 0.0) vertexNormals_[corners[t][c]] += a * glm::dvec3(faceNormals_[t]);
                }
            }
        }
        vertexNormalsBuilt_.store(true, std::memory_order_release);
    });
}

std::optional<double> MeshTopology::cornerCosine(std::size_t t, std::uint32_t c) const {
    const glm::uvec3& corners = links_->corners[t];
    const glm::dvec3 e1 = positions_[corners[(c + 1) % 3]] - positions_[corners[c]];
    const glm::dvec3 e2 = positions_[corners[(c + 2) % 3]] - positions_[corners[c]];
    const double l1 = glm::length(e1), l2 = glm::length(e2);
    if (!(l1 > 0.0 && l2 > 0.0)) return std::nullopt;
    return glm::dot(e1, e2) / (l1 * l2);
}

double MeshTopology::cornerAngle(std::size_t t, std::uint32_t c) const {
    const std::optional<double> cosine = cornerCosine(t, c);
    return cosine ? std::acos(glm::clamp(*cosine, -1.0, 1.0)) : -1.0;
}

glm::dvec3 MeshTopology::vertexNormal(std::uint32_t vertex) const {
    if (vertexCorners_) {
        std::atomic<std::uint8_t>& state = vertexNormalState_[vertex];
        if (state.load(std::memory_order_acquire) == 2) return vertexNormals_[vertex];
        const glm::dvec3 normal = measureVertexNormal(vertex);
        // Stored by the one thread that claims it; another measuring it meanwhile keeps its own (equal) value.
        std::uint8_t unclaimed = 0;
        if (state.compare_exchange_strong(unclaimed, 1, std::memory_order_acq_rel)) {
            vertexNormals_[vertex] = normal;
            state.store(2, std::memory_order_release);
        }
        return normal;
    }
    if (!vertexNormalsBuilt_.load(std::memory_order_acquire)) buildVertexNormals(nullptr);
    return vertexNormals_[vertex];
}

glm::dvec3 MeshTopology::measureVertexNormal(std::uint32_t vertex) const {
    glm::dvec3 normal(0.0);
    for (std::uint32_t at = vertexCorners_->start[vertex]; at < vertexCorners_->start[vertex + 1]; ++at) {
        const std::uint32_t t = vertexCorners_->corner[at] / 3, c = vertexCorners_->corner[at] % 3;
        const double a = cornerAngle(t, c); // -1: a collapsed corner, no angle
        if (a >= 0.0) normal += a * glm::dvec3(faceNormals_[t]);
    }
    return normal;
}

bool MeshTopology::facesAway(std::uint32_t triangle, TriangleFeature feature, const glm::dvec3& offset) const {
    if (vertexCorners_ && feature >= TriangleFeature::VertexA) {
        const std::uint32_t vertex = links_->corners[triangle][int(feature) - int(TriangleFeature::VertexA)];
        if (vertexNormalState_[vertex].load(std::memory_order_acquire) != 2) {
            if (const int side = vertexSide(vertex, offset)) return side < 0;
        }
    }
    return glm::dot(offset, pseudonormal(triangle, feature)) < 0.0;
}

// The vertex normal is n = sum of a_i f_i over the vertex's corners, a_i >= 0 the corner's angle
// and f_i its face normal, summed in double (measureVertexNormal). Where every f_i puts d on one
// side by a margin, |d . f_i| > margin * m_i with m_i = sum_k |d_k f_ik|, the rounded sum keeps
// that side: the sum's rounding and the dot product's stay below (corners + 4) * 2^-53 of
// sum_i a_i m_i, far under margin = 8 (corners + 8) * 2^-53 of it, provided one a_i is above 0
// (acos is 0 only at a cosine of 1). m_i above 2^-900 keeps every product clear of underflow.
int MeshTopology::vertexSide(std::uint32_t vertex, const glm::dvec3& d) const {
    const std::uint32_t begin = vertexCorners_->start[vertex], end = vertexCorners_->start[vertex + 1];
    const double margin = double(end - begin + 8) * 0x1p-50;
    const glm::dvec3 size = glm::abs(d);
    int side = 0;
    bool angle = false;
    for (std::uint32_t at = begin; at < end; ++at) {
        const std::uint32_t t = vertexCorners_->corner[at] / 3, c = vertexCorners_->corner[at] % 3;
        const glm::dvec3 f(faceNormals_[t]);
        const double s = glm::dot(d, f), m = glm::dot(size, glm::abs(f));
        const int faceSide = !(m > 0x1p-900) ? 0 : s > margin * m ? 1 : s < -margin * m ? -1 : 0;
        if (faceSide == 0 || (side != 0 && faceSide != side)) return 0;
        side = faceSide;
        if (!angle) {
            const std::optional<double> cosine = cornerCosine(t, c);
            angle = cosine && *cosine < 1.0;
        }
    }
    return angle ? side : 0;
}

glm::dvec3 MeshTopology::edgeNormal(std::uint32_t triangle, int edge) const {
    // The sum of the two face normals (each face's angle at the edge is π), in double.
    const std::uint32_t neighbour = links_->edgeNeighbours[3 * triangle + std::uint32_t(edge)];
    if (neighbour == kNoNeighbour) return glm::dvec3(faceNormals_[triangle]);
    return glm::dvec3(faceNormals_[triangle]) + glm::dvec3(faceNormals_[neighbour]);
}

} // namespace sdfgen
