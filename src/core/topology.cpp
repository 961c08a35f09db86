#include "core/topology.hpp"
#include "core/duplicates.hpp"
#include "core/parallel.hpp"
#include "core/predicates.hpp"

#include <tbb/parallel_sort.h>
#include <tbb/task_arena.h>

#include <glm/geometric.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numeric>
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

MeshTopology::MeshTopology(const Mesh& mesh, std::vector<std::uint32_t> copies, const RunControl& control) : copies_(std::move(copies)) {
    // Serial stages, each about as long as a pass over the triangles: progress and cancel between them.
    constexpr std::size_t kStages = 5;
    ProgressCounter progress(control, kStages);
    tbb::task_arena arena(control.threads > 0 ? control.threads : tbb::task_arena::automatic);
    // Merge vertices with identical coordinates (-0 and +0 alike; coordinates are finite, so equal
    // floats have equal bits): sorted by (bits, index) in parallel, a total order, each vertex
    // goes to the first of its group, and merged vertices are numbered in order of first use.
    const std::size_t vertexCount = mesh.positions.size();
    std::vector<std::array<std::uint32_t, 3>> keys(vertexCount);
    for (std::size_t i = 0; i < vertexCount; ++i) {
        const glm::vec3 p = mesh.positions[i] + glm::vec3(0.0f);
        std::memcpy(keys[i].data(), &p, sizeof(p));
    }
    std::vector<std::uint32_t> byPosition(vertexCount);
    std::iota(byPosition.begin(), byPosition.end(), 0u);
    arena.execute([&] {
        tbb::parallel_sort(byPosition.begin(), byPosition.end(),
                           [&](std::uint32_t x, std::uint32_t y) { return keys[x] != keys[y] ? keys[x] < keys[y] : x < y; });
    });
    std::vector<std::uint32_t> remap(vertexCount);
    for (std::size_t k = 0; k < vertexCount; ++k) {
        const std::uint32_t i = byPosition[k];
        remap[i] = k > 0 && keys[byPosition[k - 1]] == keys[i] ? remap[byPosition[k - 1]] : i;
    }
    for (std::size_t i = 0; i < vertexCount; ++i) {
        if (remap[i] == i) {
            remap[i] = std::uint32_t(positions_.size());
            positions_.emplace_back(mesh.positions[i] + glm::vec3(0.0f));
        } else {
            remap[i] = remap[remap[i]]; // the first of the group, already numbered
        }
    }
    const std::size_t n = mesh.triangleCount();
    corners_.resize(n);
    faceNormals_.resize(n);
    for (std::size_t t = 0; t < n; ++t) {
        for (int c = 0; c < 3; ++c) corners_[t][c] = remap[mesh.triangles[t][c]];
        faceNormals_[t] = mesh.faceNormals[t];
    }

    progress.add(1);
    // Every triangle edge as (low vertex, high vertex, triangle, which edge, runs low->high).
    struct EdgeUse {
        std::uint32_t lo, hi, triangle;
        std::uint8_t edge;
        bool forward;
    };
    std::vector<EdgeUse> uses;
    uses.reserve(3 * n);
    for (std::uint32_t t = 0; t < n; ++t) {
        for (std::uint8_t e = 0; e < 3; ++e) {
            const std::uint32_t u = corners_[t][e], v = corners_[t][(e + 1) % 3];
            if (u == v) continue; // collapsed by merging
            uses.push_back({std::min(u, v), std::max(u, v), t, e, u < v});
        }
    }
    // A total order (each triangle's edge is used once), so the parallel sort gives the same list
    // for any thread count.
    arena.execute([&] {
        tbb::parallel_sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
            return std::tie(x.lo, x.hi, x.triangle, x.edge) < std::tie(y.lo, y.hi, y.triangle, y.edge);
        });
    });

    progress.add(1);
    edgeNeighbours_.assign(3 * n, kNoNeighbour);
    // Corners (3 per triangle) around a vertex are joined across manifold edges; more than one
    // group at a vertex means its triangles form separate fans.
    std::vector<std::uint32_t> parent(3 * n);
    std::iota(parent.begin(), parent.end(), 0u);
    auto cornerOf = [&](std::uint32_t t, std::uint32_t vertex) {
        for (std::uint32_t c = 0; c < 3; ++c) {
            if (corners_[t][c] == vertex) return 3 * t + c;
        }
        return 3 * t;
    };
    std::vector<std::pair<std::uint32_t, std::uint32_t>> boundary; // directed, with multiplicity
    for (std::size_t begin = 0; begin < uses.size();) {
        std::size_t end = begin;
        int net = 0;
        while (end < uses.size() && uses[end].lo == uses[begin].lo && uses[end].hi == uses[begin].hi) {
            net += uses[end].forward ? 1 : -1;
            ++end;
        }
        const std::size_t count = end - begin;
        const EdgeUse& first = uses[begin];
        if (count == 1) ++edgeCheck_.boundaryEdges;
        if (count > 2) ++edgeCheck_.nonManifoldEdges;
        if (count == 2) {
            const EdgeUse& second = uses[begin + 1];
            if (first.forward == second.forward) ++edgeCheck_.inconsistentEdges;
            // The edge's pseudonormal is the sum of its two face normals (each face's angle is π).
            edgeNeighbours_[3 * first.triangle + first.edge] = second.triangle;
            edgeNeighbours_[3 * second.triangle + second.edge] = first.triangle;
            for (std::uint32_t vertex : {first.lo, first.hi}) {
                const std::uint32_t a = findRoot(parent, cornerOf(first.triangle, vertex));
                const std::uint32_t b = findRoot(parent, cornerOf(second.triangle, vertex));
                parent[a] = b;
            }
        }
        for (int k = 0; k < std::abs(net); ++k) {
            boundary.emplace_back(net > 0 ? first.lo : first.hi, net > 0 ? first.hi : first.lo);
        }
        begin = end;
    }

    progress.add(1);
    // Angle-weighted vertex normals, and the fans around each vertex.
    vertexNormals_.assign(positions_.size(), glm::dvec3(0.0));
    std::vector<std::uint32_t> fanRoot(positions_.size(), UINT32_MAX);
    std::vector<bool> pinched(positions_.size(), false);
    // The corners' angles (the costly part) in parallel, a block of triangles at a time, then
    // summed per vertex in triangle order as before.
    std::vector<double> angle(3 * std::min(n, kAngleBlock));
    for (std::size_t block = 0; block < n; block += kAngleBlock) {
        const std::size_t blockEnd = std::min(n, block + kAngleBlock);
        parallelFor((blockEnd - block + kCornerChunk - 1) / kCornerChunk, quiet(control), [&](std::size_t chunk) {
            const std::size_t from = block + chunk * kCornerChunk, to = std::min(blockEnd, from + kCornerChunk);
            for (std::size_t t = from; t < to; ++t) {
                for (std::uint32_t c = 0; c < 3; ++c) {
                    const std::uint32_t v = corners_[t][c];
                    const glm::dvec3 e1 = positions_[corners_[t][(c + 1) % 3]] - positions_[v];
                    const glm::dvec3 e2 = positions_[corners_[t][(c + 2) % 3]] - positions_[v];
                    const double l1 = glm::length(e1), l2 = glm::length(e2);
                    angle[3 * (t - block) + c] =
                        l1 > 0.0 && l2 > 0.0 ? std::acos(glm::clamp(glm::dot(e1, e2) / (l1 * l2), -1.0, 1.0)) : -1.0;
                }
            }
        });
        for (std::size_t t = block; t < blockEnd; ++t) {
            for (std::uint32_t c = 0; c < 3; ++c) {
                const double a = angle[3 * (t - block) + c]; // -1: a collapsed corner, no angle
                if (a >= 0.0) vertexNormals_[corners_[t][c]] += a * glm::dvec3(faceNormals_[t]);
            }
        }
    }
    for (std::uint32_t t = 0; t < n; ++t) {
        for (std::uint32_t c = 0; c < 3; ++c) {
            const std::uint32_t v = corners_[t][c];
            const std::uint32_t root = findRoot(parent, 3 * t + c);
            if (fanRoot[v] == UINT32_MAX) fanRoot[v] = root;
            else if (fanRoot[v] != root) pinched[v] = true;
        }
    }
    edgeCheck_.nonManifoldVertices = std::size_t(std::count(pinched.begin(), pinched.end(), true));

    // Signed volume by the divergence theorem, about the first vertex to keep the sum precise.
    double volume = 0.0;
    for (const glm::uvec3& t : corners_) {
        const glm::dvec3 o = positions_.front();
        volume += glm::dot(positions_[t[0]] - o, glm::cross(positions_[t[1]] - o, positions_[t[2]] - o));
    }
    edgeCheck_.signedVolume = volume / 6.0;
    edgeCheck_.selfIntersectionsSearched = false;
    edgeCheck_.insideOut = edgeCheck_.boundaryEdges == 0 && edgeCheck_.nonManifoldEdges == 0 &&
                           edgeCheck_.inconsistentEdges == 0 && edgeCheck_.signedVolume < 0.0;

    progress.add(1);
    // Split the boundary edges into closed loops (a boundary is a cycle, so every walk returns).
    // Each vertex keeps a cursor to its first possibly unused outgoing edge, so many copies of one
    // edge (a stack of duplicated open triangles) cost linear time, not quadratic.
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
        loops_.push_back(std::move(loop));
    }

    progress.add(1);
    progress.finish();
}

MeshCheck MeshTopology::check(const Mesh& mesh, const Bvh& tree, const RunControl& control) const {
    MeshCheck result = edgeCheck_;
    result.selfIntersectionsSearched = true;
    const std::size_t n = mesh.triangleCount();
    // In parallel over fixed chunks of triangles, each counting its own pairs into its own slot:
    // the sum is the same for any thread count. The tree reports first copies only: each crossing
    // pair of them stands for copies(t) x copies(u) pairs.
    constexpr std::size_t kChunk = 256;
    std::vector<std::size_t> crossings((n + kChunk - 1) / kChunk, 0);
    parallelFor(crossings.size(), control, [&](std::size_t chunk) {
        std::size_t found = 0;
        for (std::uint32_t t = std::uint32_t(chunk * kChunk); t < std::min(n, (chunk + 1) * kChunk); ++t) {
            if (tree.copies(t) == 0) continue;
            Bounds box{glm::min(glm::min(mesh.vertex(t, 0), mesh.vertex(t, 1)), mesh.vertex(t, 2)),
                       glm::max(glm::max(mesh.vertex(t, 0), mesh.vertex(t, 1)), mesh.vertex(t, 2))};
            tree.forEachOverlap(box, [&](std::uint32_t u) {
                if (u <= t) return;
                const glm::uvec3 a = corners_[t], b = corners_[u];
                int shared = 0;
                for (int i = 0; i < 3; ++i)
                    for (int j = 0; j < 3; ++j) shared += a[i] == b[j];
                if (shared >= 2) return; // neighbours across an edge can only overlap if coplanar
                // The merged positions are the mesh's floats, which the exact predicates take.
                const glm::vec3 pa[3] = {glm::vec3(positions_[a[0]]), glm::vec3(positions_[a[1]]), glm::vec3(positions_[a[2]])};
                const glm::vec3 pb[3] = {glm::vec3(positions_[b[0]]), glm::vec3(positions_[b[1]]), glm::vec3(positions_[b[2]])};
                // Cheap and exact rejection first: when one triangle's vertices (shared ones aside)
                // lie strictly on one side of the other's plane, the pair meets at shared vertices
                // at most, so none of the edge tests below could find a crossing.
                if (strictlyOnOneSide(pa, a, pb, b) || strictlyOnOneSide(pb, b, pa, a)) return;
                bool crossing = false;
                // An edge from a shared vertex meets the other triangle there, so only edges away from
                // shared vertices are tested: any other common point makes the pair self-intersecting.
                for (int e = 0; e < 3 && !crossing; ++e) {
                    const std::uint32_t u0 = a[e], u1 = a[(e + 1) % 3];
                    if (!(b[0] == u0 || b[1] == u0 || b[2] == u0 || b[0] == u1 || b[1] == u1 || b[2] == u1)) {
                        crossing = segmentMeetsTriangle(pa[e], pa[(e + 1) % 3], pb[0], pb[1], pb[2]);
                    }
                    const std::uint32_t v0 = b[e], v1 = b[(e + 1) % 3];
                    if (!crossing && !(a[0] == v0 || a[1] == v0 || a[2] == v0 || a[0] == v1 || a[1] == v1 || a[2] == v1)) {
                        crossing = segmentMeetsTriangle(pb[e], pb[(e + 1) % 3], pa[0], pa[1], pa[2]);
                    }
                }
                if (crossing) found += std::size_t(tree.copies(t)) * tree.copies(u);
            });
        }
        crossings[chunk] = found;
    });
    for (std::size_t count : crossings) result.selfIntersections += count;
    return result;
}

glm::dvec3 MeshTopology::pseudonormal(std::uint32_t triangle, TriangleFeature feature) const {
    switch (feature) {
    case TriangleFeature::Face: return glm::dvec3(faceNormals_[triangle]);
    case TriangleFeature::EdgeAB: return edgeNormal(triangle, 0);
    case TriangleFeature::EdgeBC: return edgeNormal(triangle, 1);
    case TriangleFeature::EdgeCA: return edgeNormal(triangle, 2);
    case TriangleFeature::VertexA: return vertexNormals_[corners_[triangle][0]];
    case TriangleFeature::VertexB: return vertexNormals_[corners_[triangle][1]];
    case TriangleFeature::VertexC: return vertexNormals_[corners_[triangle][2]];
    }
    return glm::dvec3(faceNormals_[triangle]);
}

glm::dvec3 MeshTopology::edgeNormal(std::uint32_t triangle, int edge) const {
    // The sum of the two face normals (each face's angle at the edge is π), in double.
    const std::uint32_t neighbour = edgeNeighbours_[3 * triangle + std::uint32_t(edge)];
    if (neighbour == kNoNeighbour) return glm::dvec3(faceNormals_[triangle]);
    return glm::dvec3(faceNormals_[triangle]) + glm::dvec3(faceNormals_[neighbour]);
}

} // namespace sdfgen
