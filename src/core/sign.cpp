#include "core/sign.hpp"
#include "core/duplicates.hpp"
#include "core/parallel.hpp"

#include <glm/geometric.hpp>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>

namespace sdfgen {

namespace {

// Where sample (i, j, k) is, in the coordinates the mesh is stored in. The one place that knows.
glm::dvec3 samplePoint(const Grid& grid, int i, int j, int k) { return glm::dvec3(grid.sample(i, j, k)); }

// A fan closing one boundary loop, counted `weight` times, with what bounds its winding number
// from afar. Its triangles are (loop[i + 1], loop[i], centre): the loop reversed, so that mesh +
// fans is closed.
struct Cap {
    std::vector<glm::dvec3> loop;
    glm::dvec3 centre{0.0};
    glm::dvec3 lo{0.0}, hi{0.0}; // bounds of the fan (of the loop and the centre)
    double area = 0;
    int weight = 1;
};

Cap makeCap(std::vector<glm::dvec3> loop, int weight) {
    Cap cap;
    cap.loop = std::move(loop);
    cap.weight = weight;
    for (const glm::dvec3& v : cap.loop) cap.centre += v;
    cap.centre /= double(cap.loop.size());
    cap.lo = cap.hi = cap.centre;
    for (std::size_t i = 0; i < cap.loop.size(); ++i) {
        const glm::dvec3& from = cap.loop[i];
        const glm::dvec3& to = cap.loop[(i + 1) % cap.loop.size()];
        cap.lo = glm::min(cap.lo, from);
        cap.hi = glm::max(cap.hi, from);
        cap.area += 0.5 * glm::length(glm::cross(from - cap.centre, to - cap.centre));
    }
    return cap;
}

// Loops longer than this are closed by several small fans (see addLoop).
constexpr std::size_t kMaxCapEdges = 4;

// Closes `loop` by fans of at most kMaxCapEdges edges each, all near the loop: its runs of
// kMaxCapEdges edges, each closed by the chord back to the run's start, and then (recursively)
// the polygon of those chords, whose edges cancel the chords. One fan over a long loop (a
// terrain's border) would span the whole sheet: every sample near the sheet would be near it and
// pay for its whole loop; small fans stay near the border and are bounded from afar.
void addLoop(const std::vector<glm::dvec3>& loop, int weight, std::vector<Cap>& caps) {
    if (loop.size() <= kMaxCapEdges + 1) {
        caps.push_back(makeCap(loop, weight));
        return;
    }
    std::vector<glm::dvec3> coarse;
    for (std::size_t start = 0; start < loop.size(); start += kMaxCapEdges) {
        const std::size_t end = std::min(start + kMaxCapEdges, loop.size()); // the run's last vertex is loop[end % size]
        std::vector<glm::dvec3> run(loop.begin() + std::ptrdiff_t(start), loop.begin() + std::ptrdiff_t(end));
        run.push_back(loop[end % loop.size()]);
        caps.push_back(makeCap(std::move(run), weight));
        coarse.push_back(loop[start]);
    }
    addLoop(coarse, weight, caps);
}

// The caps of the mesh's boundary: equal loops (copies of open triangles) become one cap with a
// weight, so that a stack of copies is evaluated once.
std::vector<Cap> makeCaps(const MeshTopology& topology) {
    std::map<std::vector<std::uint32_t>, int> loops; // rotated to start at the smallest vertex
    for (std::vector<std::uint32_t> loop : topology.boundaryLoops()) {
        std::rotate(loop.begin(), std::min_element(loop.begin(), loop.end()), loop.end());
        ++loops[loop];
    }
    std::vector<Cap> caps;
    for (const auto& [loop, weight] : loops) {
        std::vector<glm::dvec3> points;
        for (std::uint32_t v : loop) points.push_back(topology.position(v));
        addLoop(points, weight, caps);
    }
    return caps;
}

// The fan's solid angle with a single atan2: each triangle contributes 2·arg(den + i·det) (Van
// Oosterom & Strackee), args add when the complex numbers multiply, and every crossing of the
// negative real axis is counted so that no turn is lost.
double fanSolidAngle(const glm::dvec3& p, const Cap& cap) {
    // Triangle (a, b, c) = (loop[i + 1], loop[i], centre): lengths and dot products with the
    // centre are shared by neighbouring triangles, so each loop vertex is measured once.
    const glm::dvec3 rc = cap.centre - p;
    const double lc = glm::length(rc);
    const std::size_t n = cap.loop.size();
    glm::dvec3 rb = cap.loop[0] - p;
    double lb = glm::length(rb), bc = glm::dot(rb, rc);
    double re = 1.0, im = 0.0;
    int turns = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec3 ra = cap.loop[(i + 1) % n] - p;
        const double la = glm::length(ra), ac = glm::dot(ra, rc);
        const double det = glm::dot(ra, glm::cross(rb, rc));
        const double den = la * lb * lc + glm::dot(ra, rb) * lc + bc * la + ac * lb;
        const double nextRe = re * den - im * det, nextIm = re * det + im * den;
        // Each factor turns by less than π, so a sign change of the imaginary part in the turning
        // direction means the product passed -1.
        if (det > 0.0 && im >= 0.0 && nextIm < 0.0) ++turns;
        else if (det < 0.0 && im < 0.0 && nextIm >= 0.0) --turns;
        const double scale = std::max(std::fabs(nextRe), std::fabs(nextIm));
        if (scale == 0.0) return 0.0; // p lies on a fan edge: the angle is undefined there
        re = nextRe / scale;
        im = nextIm / scale;
        rb = ra;
        lb = la;
        bc = ac;
    }
    return 2.0 * (std::atan2(im, re) + 2.0 * M_PI * turns);
}

// The cap's winding number at p, times its weight.
double fanWinding(const glm::dvec3& p, const Cap& cap) { return cap.weight * fanSolidAngle(p, cap) / (4.0 * M_PI); }

// A bounding-box hierarchy over the caps: |winding number| of everything under a node, seen from a
// point at distance d > 0 from its box, is at most area / (4π d²) (the solid angle of a surface is
// at most its area over the squared distance to its nearest point). Boxes, not spheres: the small
// fans along a border are slivers, and a sphere around one would reach far across the sheet.
class CapTree {
public:
    struct Node {
        glm::dvec3 lo, hi;
        double area;           // the sum of |weight| * area below
        std::uint32_t first;   // inner: first child (the second is first + 1); leaf: the cap
        bool leaf;
    };

    explicit CapTree(const std::vector<Cap>& caps) : caps_(caps) {
        if (caps.empty()) return;
        std::vector<std::uint32_t> order(caps.size());
        std::iota(order.begin(), order.end(), 0u);
        nodes_.reserve(2 * caps.size());
        nodes_.push_back({});
        build(0, order, 0, order.size());
    }

    bool empty() const { return nodes_.empty(); }
    const Node& node(std::uint32_t index) const { return nodes_[index]; }
    const Cap& cap(const Node& leaf) const { return caps_[leaf.first]; }

    // The winding-number bound of a node for every point within `reach` of p (infinite when the
    // ball touches the node's box).
    double bound(const Node& node, const glm::dvec3& p, double reach) const {
        const double d = glm::length(glm::max(glm::max(node.lo - p, p - node.hi), glm::dvec3(0.0))) - reach;
        return d > 0.0 ? node.area / (4.0 * M_PI * d * d) : std::numeric_limits<double>::infinity();
    }

private:
    void build(std::uint32_t index, std::vector<std::uint32_t>& order, std::size_t begin, std::size_t end) {
        glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
        double area = 0.0;
        glm::dvec3 centreLo = lo, centreHi = hi;
        for (std::size_t i = begin; i < end; ++i) {
            const Cap& c = caps_[order[i]];
            lo = glm::min(lo, c.lo);
            hi = glm::max(hi, c.hi);
            centreLo = glm::min(centreLo, c.centre);
            centreHi = glm::max(centreHi, c.centre);
            area += std::abs(c.weight) * c.area;
        }
        Node node;
        node.lo = lo;
        node.hi = hi;
        node.area = area;
        if (end - begin == 1) {
            node.first = order[begin];
            node.leaf = true;
            nodes_[index] = node;
            return;
        }
        const glm::dvec3 extent = centreHi - centreLo;
        const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
        const std::size_t middle = begin + (end - begin) / 2;
        std::nth_element(order.begin() + std::ptrdiff_t(begin), order.begin() + std::ptrdiff_t(middle), order.begin() + std::ptrdiff_t(end),
                         [&](std::uint32_t l, std::uint32_t r) {
                             const double cl = caps_[l].centre[axis], cr = caps_[r].centre[axis];
                             return cl != cr ? cl < cr : l < r;
                         });
        node.first = std::uint32_t(nodes_.size());
        node.leaf = false;
        nodes_[index] = node;
        nodes_.push_back({});
        nodes_.push_back({});
        build(node.first, order, begin, middle);
        build(node.first + 1, order, middle, end);
    }

    const std::vector<Cap>& caps_;
    std::vector<Node> nodes_;
};

// Nodes whose winding number bound is below this are summed as bounds rather than opened.
constexpr double kFarBound = 0.01;

// A node left unopened with the bound it was accepted with.
struct FarNode {
    double bound;
    std::uint32_t node;
    bool operator<(const FarNode& other) const { return bound < other.bound; }
};

// Opens the tree from `start` around a ball (p, reach): leaves that may be near go to `near`,
// nodes bounded below kFarBound to `far` (with their sum in `farSum`).
void collect(const CapTree& tree, std::uint32_t start, const glm::dvec3& p, double reach, std::vector<std::uint32_t>& near,
             std::vector<FarNode>& far, double& farSum) {
    std::uint32_t stack[128];
    int top = 0;
    stack[top++] = start;
    while (top > 0) {
        const std::uint32_t index = stack[--top];
        const CapTree::Node& node = tree.node(index);
        const double bound = tree.bound(node, p, reach);
        if (bound < kFarBound) {
            if (bound > 0.0) {
                far.push_back({bound, index});
                farSum += bound;
            }
        } else if (node.leaf) {
            near.push_back(index);
        } else {
            stack[top++] = node.first + 1;
            stack[top++] = node.first;
        }
    }
}

// The exact winding number's side of 1/2 at one sample: w starts as the crossing count, fans are
// subtracted as they are measured, and `pending` holds unopened nodes (a max-heap by bound once
// settle() runs) whose bounds sum to at most farSum.
struct Refinement {
    const CapTree& tree;
    glm::dvec3 p;
    double w, farSum;
    std::vector<FarNode>& pending;
    std::size_t& evaluations;

    // A node for p: measured if it is a fan p may touch, opened if an inner node p may touch,
    // else pending with its bound.
    void add(std::uint32_t index) {
        const CapTree::Node& node = tree.node(index);
        const double bound = tree.bound(node, p, 0.0);
        if (bound <= 0.0) return; // no area
        if (std::isfinite(bound)) {
            pending.push_back({bound, index});
            farSum += bound;
        } else if (node.leaf) {
            w -= fanWinding(p, tree.cap(node));
            ++evaluations;
        } else {
            add(node.first);
            add(node.first + 1);
        }
    }
    // The margin covers the rounding of the running sum.
    bool doubtful() const { return std::fabs(w - 0.5) <= farSum * (1.0 + 1e-12) + 1e-15; }

    void settle() {
        if (!doubtful()) return;
        std::make_heap(pending.begin(), pending.end());
        while (!pending.empty() && doubtful()) {
            std::pop_heap(pending.begin(), pending.end());
            const FarNode loosest = pending.back();
            pending.pop_back();
            farSum -= loosest.bound;
            const CapTree::Node& node = tree.node(loosest.node);
            if (node.leaf) {
                w -= fanWinding(p, tree.cap(node));
                ++evaluations;
                continue;
            }
            for (std::uint32_t child : {node.first, node.first + 1}) {
                const std::size_t before = pending.size();
                add(child);
                for (std::size_t n = before; n < pending.size(); ++n) std::push_heap(pending.begin(), pending.begin() + std::ptrdiff_t(n) + 1);
            }
        }
    }
};

// Samples per brick edge: the cap tree is opened once per brick of brickEdge³ samples.
constexpr int kBrickEdge = 4;

// Candidate rows of a coordinate range [lo, hi] on an axis with `count` samples from `first` at
// spacing h: one wider each way (the exact test decides), clamped before any conversion to int.
std::pair<int, int> sampleRange(double lo, double hi, double first, double h, int count) {
    const double from = std::floor((lo - first) / h) - 1.0, to = std::ceil((hi - first) / h) + 1.0;
    return {int(std::clamp(from, 0.0, double(count))), int(std::clamp(to, -1.0, double(count - 1)))};
}

} // namespace

double windingNumber(const Mesh& mesh, const glm::dvec3& p) {
    double sum = 0.0;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        sum += solidAngle(p, glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2)));
    }
    return sum / (4.0 * M_PI);
}

namespace {

// The winding sign of every sample: store(index, inside).
template <class Store>
void windingSigns(const Mesh& mesh, const MeshTopology& topology, const Grid& grid, const RunControl& control,
                  WindingStats* stats, const Store& store) {
    const std::vector<Cap> caps = makeCaps(topology);
    const CapTree capTree(caps);
    const int nx = grid.dims.x, ny = grid.dims.y, nz = grid.dims.z;

    // 1. Signed crossings of every row's line (parallel to x) with the closed surface mesh + fans,
    //    copies of a triangle counted once with their number as the weight.
    struct ScanTriangle {
        glm::dvec3 a, b, c;
        int weight;
    };
    const TriangleCopies copies = findTriangleCopies(mesh);
    std::vector<ScanTriangle> capTriangles;
    for (const Cap& cap : caps) {
        for (std::size_t i = 0; i < cap.loop.size(); ++i) {
            capTriangles.push_back({cap.loop[(i + 1) % cap.loop.size()], cap.loop[i], cap.centre, cap.weight});
        }
    }
    const std::size_t scanCount = copies.unique.size() + capTriangles.size();
    auto scanTriangle = [&](std::size_t index) {
        if (index >= copies.unique.size()) return capTriangles[index - copies.unique.size()];
        const std::uint32_t t = copies.unique[index];
        return ScanTriangle{glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2)),
                            int(copies.count[index])};
    };
    struct Crossing {
        double x;
        int sign; // +weight where the surface faces +x: moving along +x leaves the solid there
    };
    std::vector<std::vector<Crossing>> rows(std::size_t(ny) * std::size_t(nz));
    const glm::dvec3 first = samplePoint(grid, 0, 0, 0);
    const double h = grid.voxel;
    // Parallel over bands of z planes: each band's rows are written by its item alone, from the
    // triangles bucketed to it in index order.
    constexpr int kBandPlanes = 4;
    const int bands = (nz + kBandPlanes - 1) / kBandPlanes;
    std::vector<std::pair<int, int>> planes(scanCount);
    std::vector<std::uint32_t> bandStart(std::size_t(bands) + 1, 0);
    for (std::size_t index = 0; index < scanCount; ++index) {
        const ScanTriangle s = scanTriangle(index);
        planes[index] = sampleRange(std::min({s.a.z, s.b.z, s.c.z}), std::max({s.a.z, s.b.z, s.c.z}), first.z, h, nz);
        if (planes[index].first > planes[index].second) continue;
        for (int band = planes[index].first / kBandPlanes; band <= planes[index].second / kBandPlanes; ++band) ++bandStart[std::size_t(band) + 1];
    }
    for (int band = 0; band < bands; ++band) bandStart[std::size_t(band) + 1] += bandStart[std::size_t(band)];
    std::vector<std::uint32_t> bandTriangles(bandStart.back());
    {
        std::vector<std::uint32_t> fill(bandStart.begin(), bandStart.end() - 1);
        for (std::size_t index = 0; index < scanCount; ++index) {
            if (planes[index].first > planes[index].second) continue;
            for (int band = planes[index].first / kBandPlanes; band <= planes[index].second / kBandPlanes; ++band) {
                bandTriangles[fill[std::size_t(band)]++] = std::uint32_t(index);
            }
        }
    }
    parallelFor(std::size_t(bands), control.phase(0.0, 0.3), [&](std::size_t band) {
        const int bandLo = int(band) * kBandPlanes, bandHi = std::min(nz - 1, bandLo + kBandPlanes - 1);
        for (std::uint32_t n = bandStart[band]; n < bandStart[band + 1]; ++n) {
            const ScanTriangle s = scanTriangle(bandTriangles[n]);
            const auto [j0, j1] = sampleRange(std::min({s.a.y, s.b.y, s.c.y}), std::max({s.a.y, s.b.y, s.c.y}), first.y, h, ny);
            const int k0 = std::max(bandLo, planes[bandTriangles[n]].first), k1 = std::min(bandHi, planes[bandTriangles[n]].second);
            for (int k = k0; k <= k1; ++k) {
                for (int j = j0; j <= j1; ++j) {
                    const glm::dvec3 q = samplePoint(grid, 0, j, k);
                    int orientation;
                    glm::dvec3 w;
                    if (!pointInTriangle2d({q.y, q.z}, {s.a.y, s.a.z}, {s.b.y, s.b.z}, {s.c.y, s.c.z}, orientation, w)) continue;
                    rows[std::size_t(k) * std::size_t(ny) + std::size_t(j)].push_back(
                        {w.x * s.a.x + w.y * s.b.x + w.z * s.c.x, orientation * s.weight});
                }
            }
        }
    });

    // 2. Per block of kBrickEdge² rows: the closed surface's winding number is the signed count of
    //    crossings ahead (+x); then the fans' winding number is subtracted where it might matter.
    std::atomic<std::size_t> fanEvaluations{0};
    const int blocksY = (ny + kBrickEdge - 1) / kBrickEdge, blocksZ = (nz + kBrickEdge - 1) / kBrickEdge;
    parallelFor(std::size_t(blocksY) * std::size_t(blocksZ), control.phase(0.3, 1.0), [&](std::size_t block) {
        const int jb = kBrickEdge * int(block % std::size_t(blocksY)), kb = kBrickEdge * int(block / std::size_t(blocksY));
        const int je = std::min(ny, jb + kBrickEdge), ke = std::min(nz, kb + kBrickEdge);
        std::vector<int> ahead(std::size_t(kBrickEdge * kBrickEdge) * std::size_t(nx));
        for (int k = kb; k < ke; ++k) {
            for (int j = jb; j < je; ++j) {
                std::vector<Crossing>& crossings = rows[std::size_t(k) * std::size_t(ny) + std::size_t(j)];
                std::sort(crossings.begin(), crossings.end(), [](const Crossing& l, const Crossing& r) { return l.x > r.x; });
                int* rowAhead = &ahead[std::size_t((k - kb) * kBrickEdge + (j - jb)) * std::size_t(nx)];
                int count = 0;
                std::size_t next = 0;
                for (int i = nx - 1; i >= 0; --i) {
                    const double x = samplePoint(grid, i, j, k).x;
                    while (next < crossings.size() && crossings[next].x > x) count += crossings[next++].sign;
                    rowAhead[i] = count;
                }
                std::vector<Crossing>().swap(crossings); // done with this row
            }
        }
        std::vector<std::uint32_t> near;
        std::vector<FarNode> far, pending;
        std::size_t evaluations = 0;
        for (int ib = 0; ib < nx; ib += kBrickEdge) {
            const int ie = std::min(nx, ib + kBrickEdge);
            near.clear();
            far.clear();
            double brickFar = 0.0;
            if (!capTree.empty()) {
                const glm::dvec3 lo = samplePoint(grid, ib, jb, kb), hi = samplePoint(grid, ie - 1, je - 1, ke - 1);
                collect(capTree, 0, 0.5 * (lo + hi), 0.5 * glm::length(hi - lo), near, far, brickFar);
            }
            for (int k = kb; k < ke; ++k) {
                for (int j = jb; j < je; ++j) {
                    const int* rowAhead = &ahead[std::size_t((k - kb) * kBrickEdge + (j - jb)) * std::size_t(nx)];
                    for (int i = ib; i < ie; ++i) {
                        if (capTree.empty()) { // a closed surface: w is the integer count
                            store(grid.index(i, j, k), rowAhead[i] >= 1);
                            continue;
                        }
                        const glm::dvec3 p = samplePoint(grid, i, j, k);
                        // w = crossings - fans. Fans that p may touch are measured; every other
                        // node waits in `pending` with its bound, and while their sum leaves w on
                        // either side of 1/2 the loosest is opened (measured, if a fan).
                        Refinement refine{capTree, p, double(rowAhead[i]), brickFar, pending, evaluations};
                        pending.assign(far.begin(), far.end());
                        for (std::uint32_t index : near) refine.add(index);
                        refine.settle();
                        store(grid.index(i, j, k), refine.w > 0.5);
                    }
                }
            }
        }
        fanEvaluations += evaluations;
    });
    if (stats) {
        stats->caps = caps.size();
        stats->fanEvaluations = fanEvaluations;
    }
}

} // namespace

std::vector<std::uint8_t> insideByWinding(const Mesh& mesh, const MeshTopology& topology, const Grid& grid,
                                          const RunControl& control, WindingStats* stats) {
    std::vector<std::uint8_t> inside(grid.sampleCount());
    windingSigns(mesh, topology, grid, control, stats, [&](std::size_t index, bool in) { inside[index] = in; });
    return inside;
}

void applyWindingSign(const Mesh& mesh, const MeshTopology& topology, const Grid& grid, float* values,
                      const RunControl& control, WindingStats* stats) {
    windingSigns(mesh, topology, grid, control, stats, [&](std::size_t index, bool in) {
        if (in) values[index] = -values[index];
    });
}

std::vector<std::uint8_t> insideByPseudonormal(const Mesh& mesh, const MeshTopology& topology, const Grid& grid,
                                               const NearestField& nearest, const RunControl& control) {
    std::vector<std::uint8_t> inside(grid.sampleCount());
    const std::size_t rows = std::size_t(grid.dims.y) * std::size_t(grid.dims.z);
    parallelFor(rows, control, [&](std::size_t row) {
        const int j = int(row % std::size_t(grid.dims.y)), k = int(row / std::size_t(grid.dims.y));
        for (int i = 0; i < grid.dims.x; ++i) {
            const std::size_t index = grid.index(i, j, k);
            const std::uint32_t t = nearest.triangle[index];
            const glm::dvec3 p(grid.sample(i, j, k));
            const ClosestPoint closest = closestPointOnTriangle(p, glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)),
                                                                glm::dvec3(mesh.vertex(t, 2)));
            inside[index] = glm::dot(p - closest.point, topology.pseudonormal(t, closest.feature)) < 0.0;
        }
    });
    return inside;
}

} // namespace sdfgen
