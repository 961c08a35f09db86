#include "core/sign/winding_sign.hpp"
#include "core/mesh/geometry.hpp"
#include "core/runtime/parallel.hpp"
#include "core/mesh/sample_positions.hpp"
#include "core/sign/fan_kernel.hpp"
#include "core/sign/row_count.hpp"

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <algorithm>
#include <cassert>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <numeric>
#include <tuple>

namespace sdfgen {

namespace {

// The fan's solid angle with a single atan2: each triangle contributes 2·arg(den + i·det) (Van
// Oosterom & Strackee), args add when the complex numbers multiply, and every crossing of the
// negative real axis is counted so that no turn is lost. `onFan` is set where p lies on a fan
// triangle or within rounding of it (fans::onFanTriangle): there the angle's side of its 4π jump
// is rounding's choice, and only the caller can take the side the row's crossings took.
double fanSolidAngle(const glm::dvec3& p, const Cap& cap, bool& onFan) {
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
        const glm::dvec3 ra = cap.loop[i + 1 < n ? i + 1 : 0] - p; // no division: this is the hottest loop
        const double la = glm::length(ra), ac = glm::dot(ra, rc);
        const double det = glm::dot(ra, glm::cross(rb, rc));
        const double den = la * lb * lc + glm::dot(ra, rb) * lc + bc * la + ac * lb;
        if (fans::onFanTriangle(det, den, la, lb, lc)) {
            onFan = true;
            return 0.0;
        }
        const double nextRe = re * den - im * det, nextIm = re * det + im * den;
        // Each factor turns by less than π, so a sign change of the imaginary part in the turning
        // direction means the product passed -1.
        if (det > 0.0 && im >= 0.0 && nextIm < 0.0) ++turns;
        else if (det < 0.0 && im < 0.0 && nextIm >= 0.0) --turns;
        re = nextRe;
        im = nextIm;
        // Only the product's angle counts: it is rescaled only when it leaves [2^-400, 2^400]
        // (no division on the loop's critical path otherwise).
        const double scale = std::max(std::fabs(re), std::fabs(im));
        if (scale == 0.0) { // underflow past the rescaling: only where p is that near a fan
            onFan = true;
            return 0.0;
        }
        if (scale < 0x1p-400 || scale > 0x1p400) {
            re /= scale;
            im /= scale;
        }
        rb = ra;
        lb = la;
        bc = ac;
    }
    return 2.0 * (std::atan2(im, re) + 2.0 * M_PI * turns);
}

// The cap's fan triangles (loop[i + 1], loop[i], centre) that p's row crosses ahead of p, with
// their orientations summed.
int fanCrossingsAhead(const glm::dvec3& p, const std::vector<glm::dvec3>& loop, const glm::dvec3& centre) {
    int ahead = 0;
    for (std::size_t i = 0; i < loop.size(); ++i) ahead += rows::crossing(p, loop[(i + 1) % loop.size()], loop[i], centre);
    return ahead;
}

// The cap's share of w at p where p lies on its fan: (crossings ahead - winding number) is the same
// for every surface the loop bounds, so it is taken over the fan from a centre lifted off p (along
// the fan's normal, else an axis), and the crossings that p's row counted on the real fan replace
// the lifted fan's. 0 where every lift still passes through p: p on the loop, which is the mesh.
double windingOnFan(const glm::dvec3& p, const Cap& cap) {
    glm::dvec3 normal(0.0);
    double lift = 0.0;
    for (std::size_t i = 0; i < cap.loop.size(); ++i) {
        normal += glm::cross(cap.loop[i] - cap.centre, cap.loop[(i + 1) % cap.loop.size()] - cap.centre);
        lift = std::max(lift, glm::length(cap.loop[i] - cap.centre));
    }
    const double area = glm::length(normal);
    normal = area > 0.0 ? normal / area : glm::dvec3(0.0, 0.0, 1.0);
    const int counted = fanCrossingsAhead(p, cap.loop, cap.centre);
    for (const glm::dvec3& direction : {normal, -normal, glm::dvec3(1.0, 0.0, 0.0), glm::dvec3(0.0, 1.0, 0.0)}) {
        Cap lifted = cap;
        lifted.centre += lift * direction;
        bool onLifted = false;
        const double angle = fanSolidAngle(p, lifted, onLifted);
        if (!onLifted) return cap.weight * (angle / (4.0 * M_PI) - double(fanCrossingsAhead(p, lifted.loop, lifted.centre) - counted));
    }
    return 0.0;
}

// The cap's winding number at p, times its weight; on the fan, the value that the crossings
// counted along p's row call for.
double fanWinding(const glm::dvec3& p, const Cap& cap) {
    bool onFan = false;
    const double angle = fanSolidAngle(p, cap, onFan);
    return onFan ? windingOnFan(p, cap) : cap.weight * angle / (4.0 * M_PI);
}

// A bound on |Hessian| / 2 of the winding number of fans of total area `area` (times their
// weights) over a ball d > 0 from them: each triangle's solid angle is the integral over it of
// the normal derivative of 1/r, whose second derivatives in p are third derivatives of 1/r,
// at most 6 / r⁴ for any unit directions (|-15 a b² + 6 c b + 3 a| <= 6 for the cosines a, b, c
// of the normal, the direction and r). Far from a fan (d beyond its size), far tighter than
// fanTerms' Biot-Savart bound. Infinite where d <= 0.
double surfaceCurvature(double area, double d) {
    if (!(d > 0.0)) return std::numeric_limits<double>::infinity();
    const double near = d * (1.0 - 1e-12);
    return 3.0 * area / (4.0 * M_PI * near * near * near * near) * (1.0 + 1e-9);
}

} // namespace

// fanTerms (winding_sign.hpp) for one cap, in double, as the fan-terms kernel computes it for
// eight at once: the kernel's reference, and the answer for one cap that a ball touches or for
// caps of more than Cap::kMaxEdges edges.
bool fanTerms(const Cap& cap, const glm::dvec3& centre, double reach, FanTerms& out) {
    constexpr double kEps = std::numeric_limits<double>::epsilon();
    const glm::dvec3 rc = cap.centre - centre;
    const double lc = glm::length(rc);
    const std::size_t n = cap.loop.size();
    glm::dvec3 rb = cap.loop[0] - centre;
    double lb = glm::length(rb), bc = glm::dot(rb, rc);
    double re = 1.0, im = 0.0, rounding = 0.0, segments = 0.0;
    int turns = 0;
    out.chordCount = 0;
    glm::dvec3 field(0.0);
    for (std::size_t i = 0; i < n; ++i) {
        // Triangle (loop[i + 1], loop[i], centre) as fanSolidAngle measures it.
        const glm::dvec3 ra = cap.loop[i + 1 < n ? i + 1 : 0] - centre;
        const double la = glm::length(ra), ac = glm::dot(ra, rc);
        const double det = glm::dot(ra, glm::cross(rb, rc));
        const double den = la * lb * lc + glm::dot(ra, rb) * lc + bc * la + ac * lb;
        if (fans::onFanTriangle(det, den, la, lb, lc)) return false;
        const double nextRe = re * den - im * det, nextIm = re * det + im * den;
        if (det > 0.0 && im >= 0.0 && nextIm < 0.0) ++turns;
        else if (det < 0.0 && im < 0.0 && nextIm >= 0.0) --turns;
        re = nextRe, im = nextIm;
        const double scale = std::max(std::fabs(re), std::fabs(im));
        if (scale == 0.0) return false;
        if (scale < 0x1p-400 || scale > 0x1p400) re /= scale, im /= scale;
        // Edge a -> b = loop[i + 1] -> loop[i]: its Biot-Savart field (none where it has no length).
        const glm::dvec3 e = rb - ra, u = glm::cross(e, ra);
        const double u2 = glm::dot(u, u), length2 = glm::dot(e, e);
        if (length2 > 0.0) {
            if (!(u2 > 0.0)) return false; // on the edge's line: no bound on the rounding
            field += u * ((glm::dot(e, rb) / lb - glm::dot(e, ra) / la) / u2);
            // The centre's distance from the edge, and the ball's.
            const double t = std::clamp(-glm::dot(ra, e) / length2, 0.0, 1.0);
            const double r = glm::length(ra + t * e) * (1.0 - 1e-12), d = r - reach;
            if (!(d > 0.0)) return false;
            const double length = std::sqrt(length2);
            if (cap.chord[i]) out.chords[out.chordCount++] = {cap.chord[i], length / (d * d * d)};
            else segments += length / (d * d * d);
            rounding += std::sqrt(length2 / u2) + length / (r * r);
        } else if (!(la * (1.0 - 1e-12) > reach)) {
            return false;
        }
        rb = ra, lb = la, bc = ac;
    }
    const double k = cap.weight / (4.0 * M_PI);
    out.value = k * 2.0 * (std::atan2(im, re) + 2.0 * M_PI * turns);
    out.gradient = -k * field;
    out.slack = 8.0 * kEps * rounding * std::abs(k);
    out.curvature = segments * std::abs(k);
    for (std::size_t c = 0; c < out.chordCount; ++c) out.chords[c].curvature *= std::abs(k);
    return std::isfinite(out.slack) && std::isfinite(out.allCurvature());
}

namespace {

// Whether the ball (centre, reach) misses the cap's fan.
bool clearOf(const Cap& cap, const glm::dvec3& centre, double reach) {
    const std::size_t n = cap.loop.size();
    for (std::size_t i = 0; i < n; ++i) {
        const ClosestPoint closest = closestPointOnTriangle(centre, cap.loop[(i + 1) % n], cap.loop[i], cap.centre);
        if (!(glm::length(closest.point - centre) * (1.0 - 1e-9) > reach)) return false;
    }
    return true;
}

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

// Closes `loop` by fans of at most kMaxCapEdges edges each, all near the loop: its runs of
// kMaxCapEdges edges, each closed by the chord back to the run's start, and then (recursively)
// the polygon of those chords, whose edges cancel the chords. One fan over a long loop (a
// terrain's border) would span the whole sheet: every sample near the sheet would be near it and
// pay for its whole loop; small fans stay near the border and are bounded from afar.
// `chords`: the loop's edges' chord ids (Cap::chord), `lastChord` the last id given out.
void addLoop(const std::vector<glm::dvec3>& loop, const std::vector<std::uint32_t>& chords, int weight, std::vector<Cap>& caps,
             std::uint32_t& lastChord) {
    constexpr std::size_t kEdges = WindingCaps::kMaxCapEdges;
    static_assert(kEdges + 1 == Cap::kMaxEdges, "a run of kMaxCapEdges edges and its chord");
    if (loop.size() <= kEdges + 1) {
        caps.push_back(makeCap(loop, weight));
        std::copy(chords.begin(), chords.end(), caps.back().chord.begin());
        return;
    }
    std::vector<glm::dvec3> coarse;
    std::vector<std::uint32_t> coarseChords;
    for (std::size_t start = 0; start < loop.size(); start += kEdges) {
        const std::size_t end = std::min(start + kEdges, loop.size()); // the run's last vertex is loop[end % size]
        std::vector<glm::dvec3> run(loop.begin() + std::ptrdiff_t(start), loop.begin() + std::ptrdiff_t(end));
        run.push_back(loop[end % loop.size()]);
        caps.push_back(makeCap(std::move(run), weight));
        Cap& cap = caps.back();
        std::copy(chords.begin() + std::ptrdiff_t(start), chords.begin() + std::ptrdiff_t(end), cap.chord.begin());
        cap.chord[end - start] = ++lastChord; // back to the run's start; the coarse loop runs it forward
        coarse.push_back(loop[start]);
        coarseChords.push_back(lastChord);
    }
    addLoop(coarse, coarseChords, weight, caps, lastChord);
}


// A double-sided panel's two borders, the loop `a` and the loop `b` running the other way a hair
// beside it, are closed together by the strip between them, one quad (a[i], a[i + 1], b[j - 1],
// b[j]) per edge (the quads' rungs cancel), instead of a fan over each loop: the fans would span
// the panel twice with opposite signs, and every sample near the panel would measure both. The
// strip is thin, so its bounds are small. False, with nothing added, unless b has a's length and
// each b[j] lies within a tenth of a's size of its a[i] (j = s - i for the b[s] nearest a[0]).
bool addStrip(const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b, int weight, std::vector<Cap>& caps,
              std::uint32_t& lastChord) {
    constexpr double kMaxWidth = 0.1; // of the loop's box's diagonal
    const std::size_t n = a.size();
    if (n < 3 || b.size() != n) return false;
    glm::dvec3 lo = a[0], hi = a[0];
    for (const glm::dvec3& v : a) lo = glm::min(lo, v), hi = glm::max(hi, v);
    const double width = kMaxWidth * glm::length(hi - lo);
    std::size_t s = 0;
    for (std::size_t j = 1; j < n; ++j) {
        if (glm::length(b[j] - a[0]) < glm::length(b[s] - a[0])) s = j;
    }
    auto partner = [&](std::size_t i) -> const glm::dvec3& { return b[(s + n - i % n) % n]; };
    for (std::size_t i = 0; i < n; ++i) {
        if (!(glm::length(partner(i) - a[i]) <= width)) return false;
    }
    const std::uint32_t rungs = lastChord; // rung i (a[i] to its partner) is rungs + 1 + i
    for (std::size_t i = 0; i < n; ++i) {
        caps.push_back(makeCap({a[i], a[(i + 1) % n], partner(i + 1), partner(i)}, weight));
        caps.back().chord = {0, rungs + 1 + std::uint32_t((i + 1) % n), 0, rungs + 1 + std::uint32_t(i), 0};
    }
    lastChord += std::uint32_t(n);
    return true;
}

// Candidate rows of a coordinate range [lo, hi] on an axis with `count` samples from `first` at
// spacing h: one wider each way (the exact test decides), clamped before any conversion to int.
std::pair<int, int> sampleRange(double lo, double hi, double first, double h, int count) {
    const double from = std::floor((lo - first) / h) - 1.0, to = std::ceil((hi - first) / h) + 1.0;
    return {int(std::clamp(from, 0.0, double(count))), int(std::clamp(to, -1.0, double(count - 1)))};
}

} // namespace

WindingCaps::WindingCaps(const MeshTopology& topology) {
    // Equal loops (rotated to start at their smallest vertex) become one cap with a weight, so that
    // a stack of copies of an open triangle is one fan, evaluated once.
    std::map<std::vector<std::uint32_t>, int> loops;
    for (std::vector<std::uint32_t> loop : topology.boundaryLoops()) {
        std::rotate(loop.begin(), std::min_element(loop.begin(), loop.end()), loop.end());
        ++loops[loop];
    }
    std::vector<std::vector<glm::dvec3>> points;
    std::vector<int> weights;
    for (const auto& [loop, weight] : loops) {
        points.emplace_back();
        for (std::uint32_t v : loop) points.back().push_back(topology.position(v));
        weights.push_back(weight);
    }
    // Double-sided panels: each loop, in order, paired with the nearest loop by centroid's x of its
    // length and weight that addStrip takes (candidates within a tenth of its size); the others
    // closed by fans, in the same order as if no loop were paired.
    std::vector<glm::dvec3> centroids(points.size(), glm::dvec3(0.0));
    std::vector<double> sizes(points.size());
    for (std::size_t l = 0; l < points.size(); ++l) {
        glm::dvec3 lo = points[l][0], hi = points[l][0];
        for (const glm::dvec3& v : points[l]) centroids[l] += v, lo = glm::min(lo, v), hi = glm::max(hi, v);
        centroids[l] /= double(points[l].size());
        sizes[l] = glm::length(hi - lo);
    }
    std::vector<std::size_t> byX(points.size()), rank(points.size());
    std::iota(byX.begin(), byX.end(), std::size_t(0));
    std::sort(byX.begin(), byX.end(), [&](std::size_t l, std::size_t r) {
        return std::make_tuple(points[l].size(), centroids[l].x, l) < std::make_tuple(points[r].size(), centroids[r].x, r);
    });
    for (std::size_t o = 0; o < byX.size(); ++o) rank[byX[o]] = o;
    std::vector<bool> closed(points.size(), false);
    std::uint32_t lastChord = 0;
    // Whether loop m, a candidate for l, is out of reach, and so is every one beyond it by x.
    auto beyond = [&](std::size_t l, std::size_t m) {
        return points[m].size() != points[l].size() || std::fabs(centroids[m].x - centroids[l].x) > 0.1 * sizes[l];
    };
    auto pair = [&](std::size_t l, std::size_t m) {
        if (closed[m] || weights[m] != weights[l] || glm::length(centroids[m] - centroids[l]) > 0.1 * sizes[l]) return false;
        if (!addStrip(points[l], points[m], weights[l], caps_, lastChord)) return false;
        closed[m] = true;
        return true;
    };
    for (std::size_t l = 0; l < points.size(); ++l) {
        if (closed[l]) continue;
        closed[l] = true;
        bool paired = false;
        for (std::size_t o = rank[l] + 1; !paired && o < byX.size() && !beyond(l, byX[o]); ++o) paired = pair(l, byX[o]);
        for (std::size_t o = rank[l]; !paired && o-- > 0 && !beyond(l, byX[o]);) paired = pair(l, byX[o]);
        if (!paired) addLoop(points[l], std::vector<std::uint32_t>(points[l].size(), 0), weights[l], caps_, lastChord);
    }
    chords_ = lastChord + 1;
    if (caps_.empty()) return;
    std::vector<std::uint32_t> capOrder(caps_.size());
    std::iota(capOrder.begin(), capOrder.end(), 0u);
    nodes_.reserve(2 * caps_.size());
    multipoles_.reserve(2 * caps_.size());
    nodes_.push_back({});
    multipoles_.push_back({});
    build(0, capOrder, 0, capOrder.size());
}

void WindingCaps::flatten(Node& node, const std::vector<std::uint32_t>& order, std::size_t begin, std::size_t end) const {
    constexpr double kEps = std::numeric_limits<double>::epsilon();
    // Each fan triangle as f(a, b, c, |weight| times its area, unit normal, cross product).
    auto forEachTriangle = [&](const auto& f) {
        forEachFanTriangle(order, begin, end, [&](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& cross,
                                                  double length, int weight) { f(a, b, c, 0.5 * length * std::abs(weight), cross / length, cross); });
    };
    // n: the weighted normals summed, each turned to the largest triangle's side.
    glm::dvec3 reference(0.0), sum(0.0);
    double largest = 0.0, total = 0.0;
    forEachTriangle([&](auto&, auto&, auto&, double area, const glm::dvec3& m, auto&) {
        if (area > largest) largest = area, reference = m;
    });
    forEachTriangle([&](auto&, auto&, auto&, double area, const glm::dvec3& m, auto&) {
        sum += (glm::dot(m, reference) < 0.0 ? -area : area) * m;
        total += area;
    });
    const double length = glm::length(sum);
    if (!(length > 0.0) || !(total > 0.0)) return; // no plane: tilt 2 keeps the plain bound
    node.normal = sum / length;
    const glm::dvec3 centre = 0.5 * (node.lo + node.hi);
    double thickness = 0.0, tilt = 0.0;
    forEachTriangle([&](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, double area, const glm::dvec3& m,
                        const glm::dvec3& cross) {
        const double farthest = std::max({std::fabs(glm::dot(node.normal, a - centre)), std::fabs(glm::dot(node.normal, b - centre)),
                                          std::fabs(glm::dot(node.normal, c - centre))});
        // m's rounding: a normalized cross product is off by about eps times the edges' product
        // over the cross's length (large for slivers, whose area is small).
        const double rounding = 16.0 * kEps * glm::length(b - a) * glm::length(c - a) / glm::length(cross) + 1e-12;
        thickness += area * farthest;
        tilt += area * (std::min(glm::length(m - node.normal), glm::length(m + node.normal)) + rounding);
    });
    // Upper bounds over their own rounding.
    node.thickness = thickness / total * (1.0 + 1e-9) + 1e-12 * glm::length(node.hi - node.lo);
    node.tilt = std::min(2.0, tilt / total * (1.0 + 1e-9));
}

namespace {
// Homogeneous polynomials in (x, y, z) of degree 0 to 4, each coefficient by its monomial's
// exponents (kExponents[degree]); a symmetric tensor T of rank n is the polynomial T(r, ..., r),
// its component of exponents (a, b, c) the coefficient over the multinomial n! / (a! b! c!). The
// node's multipoles are kept as tensors in these orders (Multipole::quadrupole, octupole,
// hexadecapole).
constexpr int kMonomials[5] = {1, 3, 6, 10, 15};
constexpr int kExponents[5][15][3] = {
    {{0, 0, 0}},
    {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
    {{2, 0, 0}, {0, 2, 0}, {0, 0, 2}, {1, 1, 0}, {1, 0, 1}, {0, 1, 1}},
    {{3, 0, 0}, {0, 3, 0}, {0, 0, 3}, {2, 1, 0}, {2, 0, 1}, {1, 2, 0}, {0, 2, 1}, {1, 0, 2}, {0, 1, 2}, {1, 1, 1}},
    {{4, 0, 0}, {0, 4, 0}, {0, 0, 4}, {3, 1, 0}, {3, 0, 1}, {1, 3, 0}, {0, 3, 1}, {1, 0, 3}, {0, 1, 3}, {2, 2, 0}, {2, 0, 2}, {0, 2, 2}, {2, 1, 1}, {1, 2, 1}, {1, 1, 2}}};
struct MonomialTables {
    int index[5][5][5] = {}; // by exponents of x, y, z
    double multinomial[5][15] = {};
    constexpr MonomialTables() {
        constexpr double factorial[5] = {1, 1, 2, 6, 24};
        for (int n = 0; n < 5; ++n)
            for (int m = 0; m < kMonomials[n]; ++m) {
                const int* e = kExponents[n][m];
                index[e[0]][e[1]][e[2]] = m;
                multinomial[n][m] = factorial[n] / (factorial[e[0]] * factorial[e[1]] * factorial[e[2]]);
            }
    }
};
constexpr MonomialTables kMonomialTables{};

struct Polynomial {
    int degree = 0;
    double c[15] = {};
};
Polynomial linear(const glm::dvec3& v) { return {1, {v.x, v.y, v.z}}; }
Polynomial operator*(const Polynomial& a, const Polynomial& b) {
    Polynomial out{a.degree + b.degree};
    for (int i = 0; i < kMonomials[a.degree]; ++i) {
        const int* ea = kExponents[a.degree][i];
        for (int j = 0; j < kMonomials[b.degree]; ++j) {
            const int* eb = kExponents[b.degree][j];
            out.c[kMonomialTables.index[ea[0] + eb[0]][ea[1] + eb[1]][ea[2] + eb[2]]] += a.c[i] * b.c[j];
        }
    }
    return out;
}
// a += scale b (of a's degree).
void addTo(Polynomial& a, const Polynomial& b, double scale = 1.0) {
    for (int i = 0; i < kMonomials[a.degree]; ++i) a.c[i] += scale * b.c[i];
}
Polynomial fromTensor(const double* tensor, int rank) {
    Polynomial out{rank};
    for (int i = 0; i < kMonomials[rank]; ++i) out.c[i] = tensor[i] * kMonomialTables.multinomial[rank][i];
    return out;
}
// The tensor's traceless part (what the derivatives of 1/r, harmonic, meet), into `tensor`: for
// rank 2, T - tr T δ / 3; for 3, T - 1/5 Σ δ ⊗ T' (three placements; T' its trace); for 4,
// T - 1/7 Σ δ ⊗ T' + 1/35 Σ δ ⊗ δ T'' (six and three placements; T'' the trace's trace).
void tracelessTensor(const Polynomial& p, double* tensor) {
    const int n = p.degree;
    double t[15];
    for (int i = 0; i < kMonomials[n]; ++i) t[i] = p.c[i] / kMonomialTables.multinomial[n][i];
    const auto& index = kMonomialTables.index;
    if (n == 2) {
        const double third = (t[0] + t[1] + t[2]) / 3.0;
        for (int i = 0; i < 6; ++i) tensor[i] = t[i] - (i < 3 ? third : 0.0);
        return;
    }
    // The trace T': over the first two indices, by the others' exponents.
    double trace[15] = {};
    for (int m = 0; m < kMonomials[n - 2]; ++m) {
        const int* e = kExponents[n - 2][m];
        trace[m] = t[index[e[0] + 2][e[1]][e[2]]] + t[index[e[0]][e[1] + 2][e[2]]] + t[index[e[0]][e[1]][e[2] + 2]];
    }
    const double traces = n == 4 ? trace[0] + trace[1] + trace[2] : 0.0;
    for (int m = 0; m < kMonomials[n]; ++m) {
        int x[4] = {}, k = 0;
        for (int axis = 0; axis < 3; ++axis)
            for (int r = 0; r < kExponents[n][m][axis]; ++r) x[k++] = axis;
        // T' at the indices left when positions a and b (equal: the δ's) are taken out.
        auto traceWithout = [&](int a, int b) {
            if (x[a] != x[b]) return 0.0;
            int e[3] = {};
            for (int o = 0; o < n; ++o)
                if (o != a && o != b) ++e[x[o]];
            return trace[index[e[0]][e[1]][e[2]]];
        };
        double once = 0.0;
        for (int a = 0; a < n; ++a)
            for (int b = a + 1; b < n; ++b) once += traceWithout(a, b);
        if (n == 3) {
            tensor[m] = t[m] - once / 5.0;
        } else {
            auto delta = [&](int a, int b) { return x[a] == x[b] ? 1.0 : 0.0; };
            const double twice = delta(0, 1) * delta(2, 3) + delta(0, 2) * delta(1, 3) + delta(0, 3) * delta(1, 2);
            tensor[m] = t[m] - once / 7.0 + twice * traces / 35.0;
        }
    }
}
} // namespace

void WindingCaps::build(std::uint32_t index, std::vector<std::uint32_t>& order, std::size_t begin, std::size_t end) {
    Node node{glm::dvec3(std::numeric_limits<double>::max()), glm::dvec3(-std::numeric_limits<double>::max()), 0.0, 0, false};
    glm::dvec3 centreLo = node.lo, centreHi = node.hi;
    for (std::size_t i = begin; i < end; ++i) {
        const Cap& c = caps_[order[i]];
        node.lo = glm::min(node.lo, c.lo);
        node.hi = glm::max(node.hi, c.hi);
        centreLo = glm::min(centreLo, c.centre);
        centreHi = glm::max(centreHi, c.centre);
        node.area += std::abs(c.weight) * c.area;
    }
    flatten(node, order, begin, end);
    // The dipole.
    Multipole m;
    double weightedArea = 0.0;
    forEachFanTriangle(order, begin, end, [&](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& cross, double length,
                                              int weight) {
        const double area = 0.5 * length * std::abs(weight);
        m.vectorArea += 0.5 * double(weight) * cross;
        m.centroid += area * (a + b + c) / 3.0;
        weightedArea += area;
    });
    m.centroid = weightedArea > 0.0 ? glm::clamp(m.centroid / weightedArea, node.lo, node.hi) : 0.5 * (node.lo + node.hi);
    // The bounds' moments about the centroid; a leaf's multipole from its triangles (an inner
    // node's comes from its children's, shiftMultipoles).
    const bool leaf = end - begin == 1;
    Polynomial quadrupole{2}, octupole{3}, hexadecapole{4};
    forEachFanTriangle(order, begin, end, [&](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& cross, double length,
                                              int weight) {
        const double area = 0.5 * length * std::abs(weight);
        const glm::dvec3 offset = (a + b + c) / 3.0 - m.centroid;
        m.firstMoment += area * glm::length(offset);
        const glm::dvec3 da = a - m.centroid, db = b - m.centroid, dc = c - m.centroid;
        const double farthest = std::sqrt(std::max({glm::dot(da, da), glm::dot(db, db), glm::dot(dc, dc)}));
        m.secondMoment += area * farthest * farthest;
        m.thirdMoment += area * farthest * farthest * farthest;
        m.fourthMoment += area * farthest * farthest * farthest * farthest;
        if (!leaf) return;
        // Each term is n ⊗ the mean over the triangle of (y - centroid)^⊗k, times its area, as
        // polynomials: (a.r) times the mean of ((y - centroid).r)^k, a its vector area. With d_i
        // its corners less the centroid, s their sum, and the means of λ_i λ_j (1/6, 1/12) and
        // λ_i λ_j λ_k (1/10, 1/30, 1/60 as the barycentric indices repeat):
        // k = 1: (s.r) / 3; k = 2: ((s.r)² + Σ (d_i.r)²) / 12; k = 3: ((s.r)³ + 3 (s.r) Σ (d_i.r)² +
        // 2 Σ (d_i.r)³) / 60.
        const Polynomial vectorArea = linear(0.5 * double(weight) * cross), sum = linear(da + db + dc);
        const Polynomial corners[3] = {linear(da), linear(db), linear(dc)};
        Polynomial squares{2}, cubes{3};
        for (const Polynomial& corner : corners) {
            const Polynomial square = corner * corner;
            addTo(squares, square);
            addTo(cubes, square * corner);
        }
        const Polynomial sumSquared = sum * sum;
        addTo(quadrupole, vectorArea * sum, 1.0 / 3.0);
        Polynomial second = sumSquared;
        addTo(second, squares);
        addTo(octupole, vectorArea * second, 1.0 / 12.0);
        Polynomial third = sumSquared * sum;
        addTo(third, sum * squares, 3.0);
        addTo(third, cubes, 2.0);
        addTo(hexadecapole, vectorArea * third, 1.0 / 60.0);
    });
    if (leaf) {
        tracelessTensor(quadrupole, m.quadrupole);
        tracelessTensor(octupole, m.octupole);
        tracelessTensor(hexadecapole, m.hexadecapole);
    }
    m.firstMoment *= 1.0 + 1e-12, m.secondMoment *= 1.0 + 1e-12, m.thirdMoment *= 1.0 + 1e-12, m.fourthMoment *= 1.0 + 1e-12;
    node.fans = std::uint32_t(end - begin);
    if (end - begin == 1) {
        node.first = order[begin];
        node.leaf = true;
        nodes_[index] = node;
        multipoles_[index] = m;
        return;
    }
    node.first = std::uint32_t(nodes_.size());
    nodes_[index] = node;
    multipoles_[index] = m;
    nodes_.insert(nodes_.end(), 2, Node{});
    multipoles_.insert(multipoles_.end(), 2, Multipole{});
    // Fans of very different sizes apart first, at the geometric mean of the largest and the
    // smallest: beside a big fan (across a hole) the small ones (along its border) would be
    // bounded by the big one's area and spread, and opened with it, one by one. Only where the
    // largest spans much of the node: above, the split by place keeps walks from the root short.
    double largest = 0.0, smallest = std::numeric_limits<double>::infinity();
    for (std::size_t i = begin; i < end; ++i) {
        const double size = capSize(caps_[order[i]]);
        largest = std::max(largest, size);
        if (size > 0.0) smallest = std::min(smallest, size);
    }
    if (largest > kSizeRatio * smallest && largest >= kSizeSpan * glm::length(node.hi - node.lo)) {
        const double between = std::sqrt(largest * smallest);
        const auto firstLarge = std::stable_partition(order.begin() + std::ptrdiff_t(begin), order.begin() + std::ptrdiff_t(end),
                                                      [&](std::uint32_t c) { return capSize(caps_[c]) <= between; });
        const std::size_t split = std::size_t(firstLarge - order.begin());
        build(node.first, order, begin, split);
        build(node.first + 1, order, split, end);
        shiftMultipoles(index);
        return;
    }
    // Else the median split along the centres' longest extent.
    const glm::dvec3 extent = centreHi - centreLo;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
    const std::size_t middle = begin + (end - begin) / 2;
    std::nth_element(order.begin() + std::ptrdiff_t(begin), order.begin() + std::ptrdiff_t(middle), order.begin() + std::ptrdiff_t(end),
                     [&](std::uint32_t l, std::uint32_t r) {
                         const double cl = caps_[l].centre[axis], cr = caps_[r].centre[axis];
                         return cl != cr ? cl < cr : l < r;
                     });
    build(node.first, order, begin, middle);
    build(node.first + 1, order, middle, end);
    shiftMultipoles(index);
}

void WindingCaps::shiftMultipoles(std::uint32_t index) {
    const std::uint32_t first = nodes_[index].first;
    Multipole& parent = multipoles_[index];
    // A child's terms about its centroid c' moved to the node's c: with h = c' - c, the mean of
    // ((y - c).r)^k is that of ((y - c').r + h.r)^k, expanded binomially. The children's tensors
    // lack their traces, which the shift keeps as multiples of |r|² and the node's own traces drop.
    Polynomial quadrupole{2}, octupole{3}, hexadecapole{4};
    for (const std::uint32_t c : {first, first + 1}) {
        const Multipole& child = multipoles_[c];
        const Polynomial h = linear(child.centroid - parent.centroid), dipole = linear(child.vectorArea);
        const Polynomial second = fromTensor(child.quadrupole, 2), third = fromTensor(child.octupole, 3), fourth = fromTensor(child.hexadecapole, 4);
        // In Horner's form: the quadrupole's D h + S, the octupole's (D h + 2 S) h + H, the
        // hexadecapole's ((D h + 3 S) h + 3 H) h + G.
        const Polynomial dipoleH = dipole * h;
        addTo(quadrupole, second);
        addTo(quadrupole, dipoleH);
        Polynomial inner = dipoleH;
        addTo(inner, second, 2.0);
        addTo(octupole, third);
        addTo(octupole, inner * h);
        inner = dipoleH;
        addTo(inner, second, 3.0);
        Polynomial outer = inner * h;
        addTo(outer, third, 3.0);
        addTo(hexadecapole, fourth);
        addTo(hexadecapole, outer * h);
    }
    tracelessTensor(quadrupole, parent.quadrupole);
    tracelessTensor(octupole, parent.octupole);
    tracelessTensor(hexadecapole, parent.hexadecapole);
}


WindingCaps::BallDipole WindingCaps::multipoleOverBall(const Node& node, const Multipole& m, const glm::dvec3& centre, double reach, double d,
                                                       double limit) {
    BallDipole out;
    if (!(d > 0.0)) return out;
    constexpr double k = 1.0 / (4.0 * M_PI);
    // Every point between the centre and the ball's rim is at least d from the box, so at least d
    // from the centroid inside it. The dipole's Hessian is at most 6 |D| / r⁴ (third derivatives of
    // 1/r), the quadrupole's at most 24 firstMoment / r⁵ (fourth derivatives, at most 24 / r⁵), the
    // octupole's at most 60 secondMoment / r⁶ (half its fifth derivatives, at most 5! / r⁶), the
    // hexadecapole's at most 120 thirdMoment / r⁷ (a sixth of its sixth, at most 6! / r⁷).
    // The terms taken: to the order whose error and curvature over the ball sum the least.
    // (Reciprocals once: the cuts bound many nodes, and one division costs what a dozen products do.)
    const double inverse = 1.0 / d, inverseNear = 1.0 / (d * (1.0 - 1e-12)), inverseNear2 = inverseNear * inverseNear;
    const double scale = k * (1.0 + 1e-9) * inverseNear2 * inverseNear2;
    const double curvatures[3] = {(3.0 * glm::length(m.vectorArea) + 12.0 * m.firstMoment * inverseNear) * scale,
                                  30.0 * m.secondMoment * inverseNear2 * scale, 60.0 * m.thirdMoment * inverseNear2 * inverseNear * scale};
    double errors[3];
    truncationErrors(m, inverse, errors);
    int order = 2;
    double curvature = curvatures[0], error = errors[0];
    for (int o = 3; o <= 4; ++o) {
        const double withTerm = curvature + curvatures[o - 2];
        if (errors[o - 2] + withTerm * reach * reach < error + curvature * reach * reach) order = o, curvature = withTerm, error = errors[o - 2];
        else break;
    }
    // The value's and gradient's rounding: a 1e-12 share of each term's bound.
    error += 1e-12 * momentsOver(node, m, inverse) * k * inverse * inverse * (1.0 + reach * inverse);
    if (!(error + curvature * reach * reach < limit)) return out;
    out.curvature = curvature, out.error = error;
    const glm::dvec3 r = m.centroid - centre;
    const double length = glm::length(r), inverse2 = 1.0 / (length * length), inverse3 = inverse2 / length, inverse5 = inverse3 * inverse2;
    const double dr = glm::dot(m.vectorArea, r), rSr = quadrupoleForm(m, r), inverse7 = inverse5 * inverse2;
    // The dipole D.r / |r|³, the quadrupole -3 rᵀSr / |r|⁵, the octupole 15/2 H(r, r, r) / |r|⁷ and
    // the hexadecapole -35/2 G(r, r, r, r) / |r|⁹, and their gradients in the point (minus those in r).
    out.value = (dr * inverse3 - 3.0 * rSr * inverse5) * k;
    out.gradient = (3.0 * dr * inverse5 * r - inverse3 * m.vectorArea) * k + (6.0 * inverse5 * quadrupoleTimes(m, r) - 15.0 * rSr * inverse7 * r) * k;
    if (order >= 3) {
        const glm::dvec3 hrr = octupoleTimes(m, r);
        const double hrrr = glm::dot(hrr, r), inverse9 = inverse7 * inverse2;
        out.value += 7.5 * hrrr * inverse7 * k;
        out.gradient += (52.5 * hrrr * inverse9 * r - 22.5 * inverse7 * hrr) * k;
        if (order >= 4) {
            const glm::dvec3 grrr = hexadecapoleTimes(m, r);
            const double grrrr = glm::dot(grrr, r);
            out.value -= 17.5 * grrrr * inverse9 * k;
            out.gradient += (70.0 * inverse9 * grrr - 157.5 * grrrr * inverse9 * inverse2 * r) * k;
        }
    }
    return out;
}

// The lazy walk for one point p: w = ahead minus the fans measured so far; every node not yet
// opened waits in `pending` with its bound, and while their sum leaves |w| within `margin` of 1/2
// plus that sum (w that near 1/2 or -1/2), the loosest is opened. The same steps for the same p,
// ahead and start, wherever the call comes from: the bake's samples and point queries agree to
// the bit.
struct WindingCaps::Search {
    const WindingCaps& caps;
    const glm::dvec3& p;
    double margin;
    double w;
    std::vector<Pending>& pending;
    double farSum = 0.0; // the bounds of the ball's nodes still waiting (a cut's, each small)
    // The bounds of the heap's nodes, with a bound on the rounding of their running sum: a node
    // bounded as p all but touches its box (1e30 a few ulps from a fan's plane) would leave
    // nothing of the others' bounds once it is subtracted, so the sum is then taken afresh.
    double heapSum = 0.0, heapRounding = 0.0;
    std::size_t measured = 0;
    // Whether a waiting node counts as its multipole where that bounds it more tightly (the bake's
    // samples in doubt; inside(), the reference, counts waiting nodes as 0).
    bool dipoles = false;
    std::size_t budget = std::numeric_limits<std::size_t>::max(); // fans measured before refine() stops in doubt

    void measure(std::uint32_t cap) {
        w -= fanWinding(p, caps.caps_[cap]);
        ++measured;
    }
    // Nodes whose box holds p are opened (fans measured) at once, the others wait with their bound.
    void add(std::uint32_t start) {
        std::uint32_t stack[128];
        int top = 0;
        stack[top++] = start;
        while (top > 0) {
            const std::uint32_t index = stack[--top];
            const Node& node = caps.nodes_[index];
            double b = caps.bound(node, p, 0.0);
            if (b <= 0.0) continue; // no area
            if (std::isfinite(b)) {
                double estimate = 0.0;
                if (dipoles) {
                    const Multipole& m = caps.multipoles_[index];
                    const Truncation t = multipoleError(node, m, boxDistance(node.lo, node.hi, p));
                    if (t.error < b) {
                        estimate = multipoleEstimate(m, p, t.order);
                        b = t.error;
                        w -= estimate;
                    }
                }
                Pending waiting{b, index};
                waiting.estimate = estimate;
                pending.push_back(waiting);
                heapSum += b;
                heapRounding += kUlp * heapSum;
            } else if (node.leaf) {
                measure(node.first);
            } else {
                stack[top++] = node.first + 1;
                stack[top++] = node.first;
            }
        }
    }
    static constexpr double kUlp = 0x1p-52;
    // The margin's factor covers the rounding of the running sums.
    bool doubtful() const { return std::fabs(std::fabs(w) - 0.5) <= (farSum + heapSum + heapRounding) * (1.0 + 1e-12) + margin; }
    // A heap node opened: its bound leaves the sum, which is taken afresh where that subtraction
    // may have lost the rest.
    void leaveHeap(double bound) {
        heapSum -= bound;
        heapRounding += kUlp * (std::fabs(heapSum) + bound);
        if (heapRounding > 1e-9 * heapSum) {
            heapSum = 0.0;
            for (const Pending& node : pending) heapSum += node.bound;
            heapRounding = double(pending.size()) * kUlp * heapSum;
        }
    }
    // Nodes bounded over a ball that holds p (a cut's far nodes, loosest first): each is opened
    // when it is the loosest, without being bounded again at p (that would shave little off a
    // ball's bound and cost a trip through the heap).
    const Pending* ballNext = nullptr;
    const Pending* ballEnd = nullptr;
    // The cut they come from: a far node bounded as a multipole (or a fan by its expansion) counts
    // as its expansion at the ball's centre (p at `offset` from it), until it is opened.
    const Cut* ball = nullptr;
    glm::dvec3 offset{0.0};

    // A leaf is measured; an inner node's children are bounded at p and join the heap.
    void open(std::uint32_t index) {
        const Node& node = caps.nodes_[index];
        if (node.leaf) {
            measure(node.first);
            return;
        }
        const std::size_t before = pending.size();
        add(node.first);
        add(node.first + 1);
        for (std::size_t n = before; n < pending.size(); ++n) std::push_heap(pending.begin(), pending.begin() + std::ptrdiff_t(n) + 1);
    }

    void refine() {
        std::make_heap(pending.begin(), pending.end());
        while ((!pending.empty() || ballNext != ballEnd) && measured < budget && doubtful()) {
            Pending loosest;
            const bool fromBall = ballNext != ballEnd && (pending.empty() || pending.front().bound < ballNext->bound);
            if (fromBall) {
                loosest = *ballNext++;
            } else {
                std::pop_heap(pending.begin(), pending.end());
                loosest = pending.back();
                pending.pop_back();
            }
            if (loosest.dipole) { // a ball's far node: its expansion and its bound at p, as the cut summed them
                const BallDipole& dipole = ball->dipoles[loosest.slot];
                w += dipole.value + glm::dot(dipole.gradient, offset);
                farSum -= dipole.error + dipole.curvature * glm::dot(offset, offset);
            } else {
                if (fromBall) farSum -= loosest.bound;
                else leaveHeap(loosest.bound);
                w += loosest.estimate;
            }
            open(loosest.node);
        }
    }
};

std::pair<double, bool> WindingCaps::walk(const glm::dvec3& p, int ahead, double margin, std::size_t* evaluations, bool dipoles,
                                          std::size_t budget) const {
    thread_local std::vector<Pending> pending;
    pending.clear();
    Search search{*this, p, margin, double(ahead), pending};
    search.dipoles = dipoles;
    search.budget = budget;
    if (!nodes_.empty()) search.add(0); // none: a closed surface, w is the integer count
    if (search.doubtful()) search.refine(); // most points are decided at once; the others refine, loosest node first
    if (evaluations) *evaluations += search.measured;
    return {search.w, search.doubtful()};
}

bool WindingCaps::inside(const glm::dvec3& p, int ahead, std::size_t* evaluations) const {
    return std::fabs(walk(p, ahead, 1e-15, evaluations).first) > 0.5;
}

void WindingCaps::cut(const glm::dvec3& centre, double reach, double target, std::size_t maxNear, bool expand, Cut& out,
                      const Cut* within, bool keepNear, int points) const {
    out.nearNodes.clear();
    out.exactNodes.clear();
    out.farNodes.clear();
    out.farSorted = false;
    out.farSum = 0.0;
    out.smooth = true;
    out.curvature = out.nearCurvature = 0.0;
    out.slack = 0.0;
    out.farValue = out.nearValue = 0.0;
    out.farGradient = out.nearGradient = glm::dvec3(0.0);
    out.centre = centre;
    out.reach = reach;
    out.dipoles.clear();
    out.chordTerms.clear();
    out.nearChords.clear();
    if (nodes_.empty()) return;
    // Nodes bounded by less than a twentieth of the target are not worth opening: they go to the
    // far nodes at once, and a smaller ball keeps the bounds they have in `within` (bounds over a
    // ball that holds every sample of this one), measuring only the nodes worth opening afresh.
    const double small = out.small = 0.05 * target;
    Waiting& pending = out.waiting;
    pending.clear();
    double sum = 0.0; // of the finite bounds, far and pending, running (farSum is summed afresh at the end)
    int touching = 0; // pending nodes whose box the ball touches (infinite bound)
    // A bounded node: far if too small to open, else waiting.
    auto place = [&](const Pending& node) {
        if (node.bound <= small) {
            out.farNodes.push_back(node);
            sum += node.bound;
            return;
        }
        pending.push(node);
        if (std::isfinite(node.bound)) sum += node.bound;
        else ++touching;
    };
    auto push = [&](std::uint32_t index) {
        const Pending bounded = boundOverBall(out, index, ballDistance(nodes_[index], centre, reach), small);
        if (bounded.bound > 0.0) place(bounded); // else no area
    };
    if (within) { // a ball inside `within`'s: its cut refines that one
        assert(!(keepNear && expand)); // expanded near fans carry curvature that a kept one would lose
        if (keepNear) out.nearNodes = within->nearNodes;
        else
            for (std::uint32_t index : within->nearNodes) push(index);
        for (std::uint32_t index : within->exactNodes) push(index);
        // Over the same ball, a far node keeps its bound and dipole where push() would find them
        // again: where its multipole was tried (its plain bound above within's `small`) if and only
        // if it is tried here (above this cut's; multipoleErrorFloor's test is the same over the ball).
        const bool sameBall = within->centre == centre && within->reach == reach;
        auto boundAsHere = [&](const Pending& far) {
            if (far.expanded) return true; // an expansion holds over the ball for any target
            if (far.dipole) return small <= within->small || far.bound > small; // plain bound > far.bound
            return small >= within->small || far.bound > within->small;
        };
        for (const Pending& far : within->farNodes) {
            if (far.bound <= small && !far.dipole) { // a dipole is expanded afresh at this ball's centre
                out.farNodes.push_back(far);
                sum += far.bound;
            } else if (sameBall && boundAsHere(far)) {
                Pending kept = far;
                if (far.dipole) {
                    kept.slot = std::uint32_t(out.dipoles.size());
                    BallDipole dipole = within->dipoles[far.slot];
                    const auto first = within->chordTerms.begin() + std::ptrdiff_t(dipole.chordFirst);
                    dipole.chordFirst = std::uint32_t(out.chordTerms.size());
                    out.chordTerms.insert(out.chordTerms.end(), first, first + std::ptrdiff_t(dipole.chordCount));
                    out.dipoles.push_back(dipole);
                }
                place(kept);
            } else {
                push(far.node);
            }
        }
    } else {
        push(0);
    }
    // A fan's surface bound over the ball (surfaceCurvature).
    auto surfaceOf = [&](const Pending& fan) {
        const Node& leaf = nodes_[fan.node];
        return surfaceCurvature(leaf.area, ballDistance(leaf, centre, reach));
    };
    // Fans whose expansion (their fanTerms) the cut wants: a near fan with `expand`; without, the
    // loosest waiting fan about to be measured, bounded by its expansion at the centre instead (a
    // far dipole) where that is twice as tight (kExpandedFanPoints; its surface bound must promise
    // that). Taken as if their terms had come out as they mostly do (the fan expanded), computed
    // kFanPoints at a time by the fan-terms kernel, then settled in turn: the cut goes on where
    // one came out otherwise. Popped already.
    std::array<Pending, kFanPoints> deferred;
    int deferredCount = 0;
    std::size_t expansions = 0; // far fans expanded (or deferred to be), each half a near fan towards maxNear
    // A near fan of an expanded cut: its expansion joins the near fans' sums.
    auto addExpandedNear = [&](std::uint32_t node, const FanTerms& t) {
        out.nearCurvature += t.curvature;
        out.nearChords.insert(out.nearChords.end(), t.chords.begin(), t.chords.begin() + std::ptrdiff_t(t.chordCount));
        out.slack += t.slack;
        out.nearValue += t.value;
        out.nearGradient += t.gradient;
        out.nearNodes.push_back(node);
    };
    auto settleDeferred = [&] {
        const int n = deferredCount;
        deferredCount = 0;
        std::uint32_t leaves[kFanPoints];
        for (int f = 0; f < n; ++f) leaves[f] = deferred[std::size_t(f)].node;
        FanTerms terms[kFanPoints];
        bool ok[kFanPoints];
        fanTermsOf(leaves, n, centre, reach, terms, ok);
        for (int f = 0; f < n; ++f) {
            const Pending& fan = deferred[std::size_t(f)];
            const FanTerms& t = terms[f];
            if (expand) {
                // Expanded if that bounds it more tightly than its bound does (a sliver's area is small).
                if (!(ok[f] && (t.allCurvature() * reach + t.slack) * reach < fan.bound)) {
                    out.farNodes.push_back(fan);
                    sum += fan.bound;
                    continue;
                }
                addExpandedNear(fan.node, t);
                continue;
            }
            // A far dipole where its expansion bounds it twice as tightly; else measured after all.
            Pending bounded = fan;
            if (!expandedFan(out, t, ok[f], surfaceOf(fan), 0.5 * fan.bound, bounded)) {
                --expansions;
                out.nearNodes.push_back(fan.node);
                continue;
            }
            place(bounded);
        }
    };
    auto defer = [&](const Pending& fan) {
        deferred[std::size_t(deferredCount++)] = fan;
        if (deferredCount == kFanPoints) settleDeferred();
    };
    for (;;) {
        while (!pending.empty() && (touching > 0 || sum > target)) {
            const Pending loosest = pending.loosest();
            const Node& node = nodes_[loosest.node];
            const bool touches = !std::isfinite(loosest.bound);
            const std::size_t nearSoFar = out.nearNodes.size() + out.exactNodes.size() + (expand ? std::size_t(deferredCount) : 0);
            if (node.leaf && !touches && nearSoFar + expansions / 2 >= maxNear) break;
            pending.pop();
            if (touches) --touching;
            else sum -= loosest.bound;
            if (!node.leaf) {
                push(node.first);
                push(node.first + 1);
                continue;
            }
            if (!touches && (expand || (points >= kExpandedFanPoints && !loosest.expanded &&
                                        (surfaceOf(loosest) * reach * reach < 0.25 * loosest.bound ||
                                         ballDistance(node, centre, reach) >= kFarReaches * reach)))) {
                expansions += !expand;
                defer(loosest);
                continue;
            }
            if (expand) { // the ball may meet the fan: expanded only where it misses it, else measured at every point
                const Cap& cap = caps_[node.first];
                FanTerms terms;
                if (!(clearOf(cap, centre, reach) && fanTerms(cap, centre, reach, terms))) {
                    out.exactNodes.push_back(loosest.node);
                    continue;
                }
                addExpandedNear(loosest.node, terms);
                continue;
            }
            out.nearNodes.push_back(loosest.node);
        }
        if (deferredCount == 0) break;
        settleDeferred(); // and on, where that leaves the sum above the target
    }
    out.smooth = out.exactNodes.size() <= kMaxExactFans;
    pending.forEach([&](const Pending& node) { out.farNodes.push_back(node); });
    sumFar(out);
}

bool WindingCaps::expandedFan(Cut& out, const FanTerms& t, bool ok, double surface, double limit, Pending& fan) const {
    const double error = t.slack * out.reach; // the gradient's rounding, at the rim
    const double spread = error + std::min(surface, t.allCurvature()) * out.reach * out.reach;
    if (!(ok && spread < limit)) return false;
    BallDipole expansion;
    expansion.value = t.value, expansion.gradient = t.gradient, expansion.error = error;
    // Its edges' bound, its chords' terms apart to cancel with their other sides' where those
    // are expanded too (chosen with them: the fans beside a far one are mostly measured).
    if (t.allCurvature() <= surface) {
        expansion.curvature = t.curvature;
        expansion.chordFirst = std::uint32_t(out.chordTerms.size()), expansion.chordCount = std::uint32_t(t.chordCount);
        out.chordTerms.insert(out.chordTerms.end(), t.chords.begin(), t.chords.begin() + std::ptrdiff_t(t.chordCount));
    } else {
        expansion.curvature = surface;
    }
    fan.bound = spread, fan.dipole = fan.expanded = true;
    fan.slot = std::uint32_t(out.dipoles.size());
    out.dipoles.push_back(expansion);
    return true;
}

WindingCaps::Pending WindingCaps::boundOverBall(Cut& out, std::uint32_t index, double d, double small) const {
    const Node& node = nodes_[index];
    Pending bounded{bound(node, out.centre, out.reach, d), index};
    // Below `small`, not worth the multipole's work; nor where its error alone exceeds the bound.
    const Multipole& m = multipoles_[index];
    if (std::isfinite(bounded.bound) && bounded.bound > small && multipoleErrorFloor(m, d) < bounded.bound) {
        const BallDipole multipole = multipoleOverBall(node, m, out.centre, out.reach, d, bounded.bound);
        const double spread = multipole.error + multipole.curvature * out.reach * out.reach;
        if (spread < bounded.bound) {
            bounded.bound = spread, bounded.dipole = true, bounded.slot = std::uint32_t(out.dipoles.size());
            out.dipoles.push_back(multipole);
        }
    }
    return bounded;
}

bool WindingCaps::toExpand(const Cut& cut, const Pending& far) const {
    return !far.expanded && std::isfinite(far.bound) && ballDistance(nodes_[far.node], cut.centre, cut.reach) >= kFarReaches * cut.reach;
}

WindingCaps::FarToExpand WindingCaps::farToExpand(Cut& cut) const {
    const auto first = std::partition(cut.farNodes.begin(), cut.farNodes.end(), [&](const Pending& far) { return !toExpand(cut, far); });
    cut.farSorted = false;
    double sum = 0.0;
    for (auto far = first; far != cut.farNodes.end(); ++far) sum += far->bound;
    return {std::size_t(first - cut.farNodes.begin()), sum};
}

bool WindingCaps::expandFar(Cut& cut, const FarToExpand& opened, double target, std::size_t maxFans) const {
    const glm::dvec3 centre = cut.centre;
    const double reach = cut.reach, nearest = kFarReaches * reach;
    // The nodes to open wait (loosest first); the others stay.
    Waiting& waiting = cut.waiting;
    waiting.clear();
    double sum = opened.sum; // of the waiting bounds
    for (std::size_t n = opened.first; n < cut.farNodes.size(); ++n) waiting.push(cut.farNodes[n]);
    cut.farNodes.resize(opened.first);
    if (!(sum > target)) { // nothing to do: the nodes go back (in another order)
        waiting.forEach([&](const Pending& node) { cut.farNodes.push_back(node); });
        cut.farSorted = false;
        return false;
    }
    // Fans to expand, kFanPoints at a time (the fan-terms kernel); their bounds left the sum.
    Pending deferred[kFanPoints];
    int count = 0;
    std::size_t expanded = 0; // fans taken, settled or deferred
    auto settle = [&] {
        std::uint32_t leaves[kFanPoints];
        for (int f = 0; f < count; ++f) leaves[f] = deferred[f].node;
        FanTerms terms[kFanPoints];
        bool ok[kFanPoints];
        fanTermsOf(leaves, count, centre, reach, terms, ok);
        for (int f = 0; f < count; ++f) {
            Pending fan = deferred[f];
            const Node& leaf = nodes_[fan.node];
            if (!expandedFan(cut, terms[f], ok[f], surfaceCurvature(leaf.area, ballDistance(leaf, centre, reach)), fan.bound, fan)) {
                sum += fan.bound; // stays bounded by its area
            }
            cut.farNodes.push_back(fan);
        }
        count = 0;
    };
    auto take = [&](const Pending& fan) {
        ++expanded;
        deferred[count] = fan;
        if (++count == kFanPoints) settle();
    };
    for (;;) {
        while (!waiting.empty() && sum > target) {
            const Pending loosest = waiting.loosest();
            const Node& node = nodes_[loosest.node];
            if (node.leaf && expanded == maxFans) break;
            waiting.pop();
            sum -= loosest.bound;
            if (node.leaf) {
                take(loosest);
                continue;
            }
            // A node of a few fans has them expanded at once: bounding the nodes between costs
            // more than the few fans that the target might have left unopened.
            constexpr std::uint32_t kWholeFans = 4;
            if (node.fans <= kWholeFans && expanded + node.fans <= maxFans) {
                std::uint32_t below[2 * kWholeFans];
                int top = 0;
                below[top++] = node.first, below[top++] = node.first + 1;
                while (top > 0) {
                    const std::uint32_t index = below[--top];
                    const Node& n = nodes_[index];
                    if (!n.leaf) {
                        below[top++] = n.first, below[top++] = n.first + 1;
                        continue;
                    }
                    const Pending fan{bound(n, centre, reach, ballDistance(n, centre, reach)), index};
                    if (fan.bound > 0.0) take(fan); // else no area
                }
                continue;
            }
            for (const std::uint32_t child : {node.first, node.first + 1}) {
                const double d = ballDistance(nodes_[child], centre, reach);
                const Pending bounded = boundOverBall(cut, child, d, kFarMultipoleShare * target);
                if (!(bounded.bound > 0.0)) continue; // no area
                if (d >= nearest) {
                    waiting.push(bounded);
                    sum += bounded.bound;
                } else {
                    cut.farNodes.push_back(bounded);
                }
            }
        }
        if (count == 0) break;
        settle(); // and on, where fans that kept their bounds leave the sum above the target
    }
    waiting.forEach([&](const Pending& node) { cut.farNodes.push_back(node); });
    sumFar(cut);
    return true;
}

void WindingCaps::sumFar(Cut& out) const {
    out.farSorted = false;
    out.farValue = 0.0;
    out.farGradient = glm::dvec3(0.0);
    out.farSum = 0.0;
    out.curvature = out.nearCurvature;
    out.farChords.clear();
    for (const Pending& far : out.farNodes) {
        if (far.dipole) {
            const BallDipole& dipole = out.dipoles[far.slot];
            out.farValue += dipole.value;
            out.farGradient += dipole.gradient;
            out.curvature += dipole.curvature;
            out.farSum += dipole.error;
            const auto first = out.chordTerms.begin() + std::ptrdiff_t(dipole.chordFirst);
            out.farChords.insert(out.farChords.end(), first, first + std::ptrdiff_t(dipole.chordCount));
        } else {
            out.farSum += far.bound;
        }
    }
    if (!out.nearChords.empty() || !out.farChords.empty()) {
        out.curvature += out.marks.uncancelled(chords_, [&](const auto& f) {
            for (const ChordTerm& term : out.nearChords) f(term);
            for (const ChordTerm& term : out.farChords) f(term);
        });
    }
}

double WindingCaps::nearWinding(const glm::dvec3& p, const Cut& cut) const {
    double w = 0.0;
    for (std::uint32_t node : cut.nearNodes) w += fanWinding(p, caps_[nodes_[node].first]);
    return w;
}

int WindingCaps::sideNear(const glm::dvec3& p, int ahead, double near, const Cut& cut) const {
    // As a Search from the cut that has opened nothing yet doubts.
    const glm::dvec3 offset = p - cut.centre;
    const double w = double(ahead) - near - (cut.farValue + glm::dot(cut.farGradient, offset));
    const double spread = cut.farSum + cut.curvature * glm::dot(offset, offset);
    if (std::fabs(std::fabs(w) - 0.5) <= spread * (1.0 + 1e-12) + kDecisionMargin) return -1;
    return std::fabs(w) > 0.5;
}

static_assert(fans::FanReach::kMaxFactors == WindingCaps::kMaxCapEdges + 1, "a cap's fans have up to kMaxCapEdges + 1 triangles");

std::size_t WindingCaps::fanWindings(const std::uint32_t* leaves, std::size_t count, const glm::dvec3* points, int n, double* windings) const {
    // Fans of weight 1 go to the kernel, the others (copies of open triangles, rare) are measured one by one.
    const Cap* unit[64];
    std::size_t units = 0, measured = 0;
    for (int s = 0; s < n; ++s) windings[s] = 0.0;
    auto flush = [&] {
        if (units == 0) return;
        double part[kFanPoints];
        fans::active()(unit, units, points, n, part);
        measured += units * std::size_t((n + 3) / 4);
        for (int s = 0; s < n; ++s) {
            if (std::isnan(part[s])) { // a point on a fan: each fan as inside() measures it
                part[s] = 0.0;
                measured += units;
                for (std::size_t f = 0; f < units; ++f) part[s] += fanWinding(points[s], *unit[f]);
            }
            windings[s] += part[s];
        }
        units = 0;
    };
    for (std::size_t leaf = 0; leaf < count; ++leaf) {
        const Cap& cap = caps_[nodes_[leaves[leaf]].first];
        if (cap.weight != 1) {
            for (int s = 0; s < n; ++s) windings[s] += fanWinding(points[s], cap);
            measured += std::size_t(n);
            continue;
        }
        unit[units++] = &cap;
        if (units == std::size(unit)) flush();
    }
    flush();
    return measured;
}

bool WindingCaps::insideNear(const glm::dvec3& p, int ahead, double near, Cut& cut, Cut& scratch, std::size_t* evaluations) const {
    if (const int side = sideNear(p, ahead, near, cut); side >= 0) return side != 0; // the ball's bounds decide
    std::vector<Pending>& pending = scratch.scratch;
    pending.clear();
    // The cut's far nodes as the ball bounds them (dipoles expanded at its centre), opened loosest
    // first; their children are bounded at p, as dipoles where that is tighter.
    const glm::dvec3 offset = p - cut.centre;
    Search search{*this, p, kDecisionMargin, double(ahead) - near - (cut.farValue + glm::dot(cut.farGradient, offset)), pending};
    search.farSum = cut.farSum + cut.curvature * glm::dot(offset, offset);
    search.dipoles = true;
    if (!cut.farSorted) {
        std::sort(cut.farNodes.begin(), cut.farNodes.end(), [](const Pending& l, const Pending& r) { return r < l; });
        cut.farSorted = true;
    }
    search.ballNext = cut.farNodes.data();
    search.ballEnd = cut.farNodes.data() + cut.farNodes.size();
    search.ball = &cut;
    search.offset = offset;
    search.refine();
    const bool decided = !search.doubtful();
    if (evaluations) *evaluations += search.measured;
    if (!decided) return inside(p, ahead, evaluations); // |w| within the margin of 1/2: inside()'s own steps
    return std::fabs(search.w) > 0.5;
}

void WindingCaps::insideMany(const glm::dvec3* points, const int* ahead, std::size_t count, std::uint8_t* flags) const {
    // The measured cuts, as the dense bake's bricks take them (BrickSigns).
    thread_local Cut nearest, loose, carried[2], scratch;
    const double span = nodes_.empty() ? 0.0 : kGroupSpan * glm::length(nodes_[0].hi - nodes_[0].lo);
    glm::dvec3 group[kGroupPoints], lo(0.0), hi(0.0);
    std::size_t at[kGroupPoints];
    // The near fans of a cut from `from` on at each of `size` points, kFanPoints at a time.
    auto measure = [&](const Cut& c, std::size_t from, const glm::dvec3* where, int size, double* near) {
        for (int first = 0; first < size; first += kFanPoints) {
            fanWindings(c.nearNodes.data() + from, c.nearNodes.size() - from, where + first, std::min(kFanPoints, size - first), near + first);
        }
    };
    int n = 0;
    auto decide = [&] {
        if (n == 1) {
            flags[at[0]] = inside(group[0], ahead[at[0]]);
        } else if (n > 1) {
            const glm::dvec3 centre = 0.5 * (lo + hi);
            const double reach = 0.5 * glm::length(hi - lo) * (1.0 + 1e-9);
            cut(centre, reach, kTightTarget, kNearestFans, false, nearest, nullptr, false, n);
            Cut* chosen = &nearest;
            if (nearest.spread() > kHopeless) {
                cut(centre, reach, kLooseTarget, kMeasuredFans, false, loose, &nearest, false, n);
                chosen = &loose;
            }
            double near[kGroupPoints];
            measure(*chosen, 0, group, n, near);
            glm::dvec3 doubtful[kGroupPoints];
            int which[kGroupPoints], left = 0;
            // Decides the points `chosen` decides, and keeps the others in doubt.
            auto settle = [&](int count) {
                int still = 0;
                for (int d = 0; d < count; ++d) {
                    const int s = which[d];
                    const int side = sideNear(group[s], ahead[at[s]], near[s], *chosen);
                    if (side >= 0) flags[at[s]] = std::uint8_t(side);
                    else doubtful[still] = group[s], which[still++] = s;
                }
                left = still;
            };
            std::iota(which, which + n, 0);
            settle(n);
            // The cut carried on while points are left in doubt: only the fans it adds are measured.
            for (double target : kCarriedTargets) {
                if (left < kCarriedFrom) break;
                if (!(chosen->spread() > target)) continue; // met already
                Cut& next = carried[chosen == &carried[0]];
                cut(centre, reach, target, chosen->nearNodes.size() + kMeasuredFans, false, next, chosen, true, left);
                double added[kGroupPoints];
                measure(next, chosen->nearNodes.size(), doubtful, left, added);
                for (int d = 0; d < left; ++d) near[which[d]] += added[d];
                chosen = &next;
                settle(left);
            }
            for (int d = 0; d < left; ++d) {
                const int s = which[d];
                flags[at[s]] = insideNear(group[s], ahead[at[s]], near[s], *chosen, scratch);
            }
        }
        n = 0;
    };
    unsigned doubts = 0, skipped = 0; // the last first walks' outcomes (bit set: in doubt), the walks skipped
    for (std::size_t i = 0; i < count; ++i) {
        const glm::dvec3& p = points[i];
        if (nodes_.empty() || bound(nodes_[0], p, 0.0) < 0.45) { // every fan together moves w by less than 0.45 (farFromEveryFan)
            flags[i] = ahead[i] != 0;
            continue;
        }
        // Where most of the last eight first walks were left in doubt (among many open parts),
        // points join the runs at once; one in eight still walks, so the choice follows the surface.
        if (__builtin_popcount(doubts & 0xffu) < 6 || ++skipped % 8 == 0) {
            const auto [w, doubtful] = walk(p, ahead[i], kDecisionMargin, nullptr, true, kWalkBudget);
            doubts = doubts << 1 | unsigned(doubtful);
            if (!doubtful) {
                flags[i] = std::fabs(w) > 0.5;
                continue;
            }
        }
        if (n > 0 && glm::length(glm::max(hi, p) - glm::min(lo, p)) > span) decide();
        lo = n == 0 ? p : glm::min(lo, p);
        hi = n == 0 ? p : glm::max(hi, p);
        group[n] = p;
        at[n++] = i;
        if (n == kGroupPoints) decide();
    }
    decide();
}

bool WindingCaps::clearOfFans(const glm::dvec3& p, double reach, bool byTriangles) const {
    if (nodes_.empty()) return true;
    std::uint32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node& node = nodes_[stack[--top]];
        if (boxDistance(node.lo, node.hi, p) > reach * (1.0 + 1e-9)) continue;
        if (node.leaf) {
            if (!byTriangles || !clearOf(caps_[node.first], p, reach)) return false;
            continue;
        }
        stack[top++] = node.first + 1;
        stack[top++] = node.first;
    }
    return true;
}

bool WindingCaps::farFromEveryFan(const glm::dvec3& p, double reach) const {
    // Nodes bounded below kFarBound, and leaves, are summed, not opened; a fan the ball may touch
    // (an infinite bound) ends the search, as does a sum reaching 0.45. Below that, every point of the ball
    // has w within 0.45 of the integer ahead, so inside() can only answer ahead != 0 there.
    constexpr double kFarBound = 0.01, kMaxSum = 0.45;
    if (nodes_.empty()) return true;
    double sum = 0.0;
    std::uint32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node& node = nodes_[stack[--top]];
        const double b = bound(node, p, reach);
        if (b < kFarBound || node.leaf) {
            if (!((sum += b) < kMaxSum)) return false;
        } else {
            stack[top++] = node.first + 1;
            stack[top++] = node.first;
        }
    }
    return true;
}

WindingFans WindingCaps::flattened() const {
    WindingFans out;
    for (const Cap& cap : caps_) {
        out.fans.push_back({std::uint32_t(out.points.size()), std::uint32_t(cap.loop.size()), cap.weight});
        out.points.push_back(cap.centre);
        out.points.insert(out.points.end(), cap.loop.begin(), cap.loop.end());
    }
    for (const Node& node : nodes_) out.nodes.push_back({node.lo, node.hi, node.area, node.first, node.leaf});
    return out;
}

double WindingCaps::winding(const glm::dvec3& p, int ahead) const {
    double w = double(ahead);
    for (const Cap& cap : caps_) w -= fanWinding(p, cap);
    return w;
}

void WindingCaps::sidesBeyond(const glm::dvec3* points, const int* ahead, const double* margins, int n, int* sides,
                              const FansEstimate* first) const {
    // An estimate to a thousandth a node decides most cubes, and shows where even w itself
    // would leave |w| within the margin of 1/2; one to a ten-thousandth decides most of the rest
    // (with the kernel measuring the fans, more cheaply than a walk); the rest walk.
    int left[kFanPoints], count = n; // the points not decided yet
    for (int i = 0; i < n; ++i) left[i] = i, sides[i] = -1;
    for (std::size_t pass = 0; pass < std::size(kSideNodeErrors); ++pass) {
        FansEstimate fans[kFanPoints];
        if (pass == 0 && first) {
            std::copy(first, first + n, fans); // every point left
        } else if (count > 0) {
            glm::dvec3 at[kFanPoints];
            for (int c = 0; c < count; ++c) at[c] = points[left[c]];
            estimateFans(at, count, kSideNodeErrors[pass], fans);
        }
        int next = 0;
        for (int c = 0; c < count; ++c) {
            const int i = left[c];
            const double estimate = double(ahead[i]) - fans[c].value, off = std::fabs(std::fabs(estimate) - 0.5), margin = margins[i];
            if (off > (fans[c].error + margin) * (1.0 + 1e-12)) sides[i] = std::fabs(estimate) > 0.5;
            else if (!(off + fans[c].error * (1.0 + 1e-12) < margin * (1.0 - 1e-12))) left[next++] = i; // else in doubt even by w
        }
        count = next;
    }
    for (int c = 0; c < count; ++c) {
        const int i = left[c];
        const auto [w, doubtful] = walk(points[i], ahead[i], margins[i], nullptr);
        sides[i] = doubtful ? -1 : std::fabs(w) > 0.5;
    }
}

void WindingCaps::estimateFans(const glm::dvec3* points, int n, double nodeError, FansEstimate* out) const {
    assert(n > 0 && n <= kFanPoints);
    double magnitude[kFanPoints] = {}; // of the terms summed
    for (int i = 0; i < n; ++i) out[i] = {};
    if (nodes_.empty()) return;
    // The leaves to measure, kFanPoints-wide batches of the kernel's fans at a time.
    std::uint32_t leaves[64];
    std::size_t count = 0;
    auto measure = [&] {
        double windings[kFanPoints];
        fanWindings(leaves, count, points, n, windings);
        // The kernel's rounding: a few ulps of each fan's turn (at most one) on top of the sum's.
        for (int i = 0; i < n; ++i) out[i].value += windings[i], magnitude[i] += std::fabs(windings[i]) + double(count);
        count = 0;
    };
    std::uint32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    double plains[kFanPoints];
    Truncation truncations[kFanPoints];
    while (top > 0) {
        const std::uint32_t index = stack[--top];
        const Node& node = nodes_[index];
        const Multipole& m = multipoles_[index];
        bool counted = true; // every point takes the node's dipole or bound
        for (int i = 0; i < n && counted; ++i) {
            const double d = boxDistance(node.lo, node.hi, points[i]);
            truncations[i] = multipoleError(node, m, d), plains[i] = bound(node, points[i], 0.0, d);
            counted = std::min(truncations[i].error, plains[i]) < nodeError;
        }
        if (counted) {
            for (int i = 0; i < n; ++i) {
                if (truncations[i].error < plains[i]) {
                    const double estimate = multipoleEstimate(m, points[i], truncations[i].order);
                    out[i].value += estimate, out[i].error += truncations[i].error;
                    magnitude[i] += std::fabs(estimate);
                } else {
                    out[i].error += plains[i];
                }
            }
        } else if (node.leaf) {
            leaves[count++] = index;
            if (count == std::size(leaves)) measure();
        } else {
            stack[top++] = node.first + 1;
            stack[top++] = node.first;
        }
    }
    if (count > 0) measure();
    // The terms' and the running sums' rounding: a few ulps of each.
    for (int i = 0; i < n; ++i) out[i].error = out[i].error * (1.0 + 1e-12) + 1e-12 * magnitude[i];
}

void WindingCaps::fanTermsOf(const std::uint32_t* leaves, int n, const glm::dvec3& centre, double reach, FanTerms* terms, bool* ok,
                             bool angles) const {
    const Cap* fanCaps[kFanPoints];
    bool small = true; // every cap within the kernel's edges
    for (int f = 0; f < n; ++f) {
        fanCaps[f] = &caps_[nodes_[leaves[f]].first];
        small &= fanCaps[f]->loop.size() <= Cap::kMaxEdges;
    }
    if (small) {
        (angles ? fans::activeTerms() : fans::activeFields())(fanCaps, n, centre, reach, terms, ok);
    } else {
        for (int f = 0; f < n; ++f) ok[f] = fanTerms(*fanCaps[f], centre, reach, terms[f]);
    }
}

double WindingCaps::windingVariation(const glm::dvec3& centre, double reach, double limit) const {
    // Nodes whose fans move w by less than this over the ball are bounded, not opened.
    constexpr double kOpen = 1e-3;
    constexpr double inf = std::numeric_limits<double>::infinity();
    glm::dvec3 gradient(0.0); // the near caps' field at the centre
    double curvature = 0.0, slack = 0.0, far = 0.0;
    thread_local std::vector<ChordTerm> chords; // of the caps summed (kept for its memory)
    chords.clear();
    if (nodes_.empty()) return 0.0;
    // The caps met, with their bounds: their terms are computed kFanPoints at a time.
    std::uint32_t leaves[kFanPoints];
    double distances[kFanPoints], bounds[kFanPoints];
    int count = 0;
    auto sumCaps = [&] {
        FanTerms terms[kFanPoints];
        bool ok[kFanPoints];
        fanTermsOf(leaves, count, centre, reach, terms, ok, false);
        for (int f = 0; f < count; ++f) {
            if (ok[f]) {
                // The cap's loop's field at the centre (its chords and rungs cancel those of the
                // neighbouring caps measured here too, and so do their terms of the bound).
                gradient += terms[f].gradient;
                // Its edges' bound, its chords' terms apart (the caps beside it are summed here
                // too, and mostly cancel them), or its surface bound where that is tighter.
                const double surface = surfaceCurvature(nodes_[leaves[f]].area, distances[f]);
                if (terms[f].curvature <= surface) {
                    curvature += terms[f].curvature;
                    chords.insert(chords.end(), terms[f].chords.begin(), terms[f].chords.begin() + std::ptrdiff_t(terms[f].chordCount));
                } else {
                    curvature += surface;
                }
                slack += terms[f].slack;
            } else if (bounds[f] < inf) {
                far += bounds[f];
            } else {
                return false; // the ball reaches one of the cap's edges
            }
        }
        count = 0;
        return far + (curvature * reach + slack) * reach <= limit; // these only grow
    };
    std::uint32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const std::uint32_t index = stack[--top];
        const Node& node = nodes_[index];
        const double d = ballDistance(node, centre, reach);
        // The gradient of the solid angle's kernel m.r / |r|³ is at most 2 / |r|³: over a ball
        // that misses the node's box, its fans' winding number moves by at most 2 A reach / (4π d³).
        const double bounded = d > 0.0 ? 2.0 * node.area * reach / (4.0 * M_PI * d * d * d) : inf;
        if (bounded < kOpen) {
            far += bounded;
        } else if (!node.leaf) {
            stack[top++] = node.first + 1;
            stack[top++] = node.first;
        } else {
            leaves[count] = index, distances[count] = d, bounds[count] = bounded;
            if (++count == kFanPoints && !sumCaps()) return inf;
        }
        if (!(far + (curvature * reach + slack) * reach <= limit)) return inf;
    }
    if (count > 0 && !sumCaps()) return inf;
    if (!chords.empty()) {
        thread_local ChordMarks marks;
        curvature += marks.uncancelled(chords_, [&](const auto& f) {
            for (const ChordTerm& term : chords) f(term);
        });
    }
    return (glm::length(gradient) * reach + (curvature * reach + slack) * reach + far) * (1.0 + 1e-9);
}

int crossingsAhead(const Mesh& mesh, const Bvh& tree, const WindingCaps& caps, const glm::dvec3& p) {
    return rows::count<rows::Side::Ahead>(mesh, tree, caps, p, [&](float x, float y, float z, const auto& visit) {
        Bounds ray;
        ray.min = glm::vec3(x, y, z);
        ray.max = glm::vec3(std::numeric_limits<float>::infinity(), y, z);
        tree.forEachOverlap(ray, visit);
    });
}

int crossingsAhead(const Mesh& mesh, const WideBvh& wide, const Bvh& tree, const WindingCaps& caps, const glm::dvec3& p, bool fansClose) {
    return rows::active()(mesh, wide, tree, caps, p, fansClose);
}

namespace {

// fansCloseMesh's test, measured.
bool edgesBalanceLoops(const MeshTopology& topology) {
    // Each directed edge of the mesh's triangles (each set of copies once, weighted by its number, as
    // the counts weigh it) adds its weight, each edge of a loop subtracts 1; stored by the
    // undirected edge, the weight negated when it runs from the higher vertex.
    std::vector<std::pair<std::uint64_t, std::int64_t>> edges;
    auto add = [&](std::uint32_t from, std::uint32_t to, std::int64_t weight) {
        if (from == to) return; // an edge of no length bounds nothing
        if (from > to) std::swap(from, to), weight = -weight;
        edges.emplace_back(std::uint64_t(from) << 32 | to, weight);
    };
    const std::size_t triangles = topology.triangleCount();
    edges.reserve(3 * triangles);
    for (std::uint32_t t = 0; t < triangles; ++t) {
        const std::int64_t weight = topology.copies(t);
        if (weight == 0) continue;
        const glm::uvec3 c = topology.corners(t);
        add(c.x, c.y, weight), add(c.y, c.z, weight), add(c.z, c.x, weight);
    }
    for (const std::vector<std::uint32_t>& loop : topology.boundaryLoops()) {
        for (std::size_t i = 0; i < loop.size(); ++i) add(loop[i], loop[(i + 1) % loop.size()], -1);
    }
    std::sort(edges.begin(), edges.end());
    for (std::size_t i = 0; i < edges.size();) {
        std::int64_t sum = 0;
        std::size_t j = i;
        for (; j < edges.size() && edges[j].first == edges[i].first; ++j) sum += edges[j].second;
        if (sum != 0) return false;
        i = j;
    }
    return true;
}

} // namespace

bool fansCloseMesh(const MeshTopology& topology) {
    const MeshTopology::Links& links = topology.links();
    std::call_once(links.fansCloseOnce, [&] { links.fansClose = edgesBalanceLoops(topology); });
    return links.fansClose;
}

double windingNumber(const Mesh& mesh, const glm::dvec3& p) {
    double sum = 0.0;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        sum += solidAngle(p, glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2)));
    }
    return sum / (4.0 * M_PI);
}

namespace {

// Where the winding sign puts its answer: inside flags, or the field itself, negated where inside;
// sample (i, j, k) at base + i + rowStride * j + planeStride * k (the grid's layout, or a brick's).
struct SignOutput {
    std::uint8_t* flags;
    float* field;
    std::ptrdiff_t base = 0, rowStride = 0, planeStride = 0;
    std::size_t index(int i, int j, int k) const { return std::size_t(base + i + rowStride * j + planeStride * k); }
    void set(std::size_t index, bool inside) const {
        if (flags) flags[index] = inside;
        else if (inside) field[index] = -field[index];
    }
};

// sampleAxes by axis: position(i, j, k) == localPosition(mesh, grid, i, j, k) to the bit.
struct SampleAxes {
    std::vector<double> all;
    const double *x, *y, *z;
    SampleAxes(const Mesh& mesh, const Grid& grid)
        : all(sampleAxes(mesh, grid)), x(all.data()), y(x + grid.dims.x), z(y + grid.dims.y) {}
    glm::dvec3 position(int i, int j, int k) const { return {x[i], y[j], z[k]}; }
    // The ball (centre, reach) around the samples [i0, i1) x [j0, j1) x [k0, k1).
    std::pair<glm::dvec3, double> ball(int i0, int j0, int k0, int i1, int j1, int k1) const {
        const glm::dvec3 lo = position(i0, j0, k0), hi = position(i1 - 1, j1 - 1, k1 - 1);
        return {0.5 * (lo + hi), 0.5 * glm::length(hi - lo) * (1.0 + 1e-9)};
    }
    // Whether no fan can move the winding number of those samples across ±1/2 (their ball far
    // from every fan): their counts decide.
    bool clearOfFans(const WindingCaps& caps, int i0, int j0, int k0, int i1, int j1, int k1) const {
        const auto [centre, reach] = ball(i0, j0, k0, i1, j1, k1);
        return caps.farFromEveryFan(centre, reach);
    }
};

// The winding signs of one brick of up to 8³ samples, given each sample's count of crossings
// ahead, coarse to fine: a brick that no fan can reach is decided by its counts; else the near
// fans that its ball misses have their winding number expanded to first order at its centre, the
// few it may meet (a big fan across a sheet) are measured at each sample, and every sample whose
// w the bounds (the far nodes' over the ball, the expansion's rest) keep off ±1/2 is decided; the
// samples left measure the near fans of the brick or of its octant (the fan kernel, eight samples
// at a time; the far fans expanded at the centre: WindingCaps::cut's measured cuts) and are
// decided by WindingCaps::insideNear.
struct BrickSigns {
    static constexpr int kEdge = 8;
    // The expanded cut's target (the sum of its far bounds) and its most fans; the measured cuts
    // are WindingCaps's (kNearestFans, kLooseTarget, ...).
    // Loose and few: the samples that these leave in doubt have the cut's far fans expanded
    // (expandFarFans) only where that pays.
    static constexpr double kExpandTarget = 0.1;
    static constexpr std::size_t kExpandedFans = 16;
    // WindingCaps::expandFar's targets, for the samples a cut leaves in doubt: each finer one
    // taken where it decides enough samples beyond the one before.
    static constexpr double kFarTargets[] = {0.01, 1e-3, 1e-4};
    // A brick of the band that no fan meets: the fans' winding number at its centre (estimated),
    // and windingVariation's bound on its change over the brick's ball (none at or above
    // WindingCaps::kMostEstimateVariation).
    struct CentreEstimate {
        WindingCaps::FansEstimate fans;
        double variation = std::numeric_limits<double>::infinity();
    };
    const SampleAxes& axes;
    const WindingCaps& caps;
    SignOutput output;
    std::size_t evaluations = 0, exactDecided = 0, carriedOn = 0, farExpanded = 0;
    // The brick's expanded cut; the measured cut of the nearest fans, and the loose one;
    // insideNear's heap; a measured cut carried on, and the next.
    WindingCaps::Cut expanded, nearest, loose, scratch, carried[2];
    // The brick being decided: its first sample, its end, its counts (row r = (j - j0) + 8 (k - k0)
    // at counts + r * stride, sample i at [i - i0]) and its undecided samples (bit (i - i0) + 8 (j - j0)
    // of undecided[k - k0]).
    int i0 = 0, j0 = 0, k0 = 0, i1 = 0, j1 = 0, k1 = 0;
    const int* counts = nullptr;
    int stride = 0;
    std::uint64_t undecided[kEdge] = {};
    glm::dvec3 centre{0.0}; // the ball around the region's samples
    double reach = 0.0;

    BrickSigns(const SampleAxes& axes, const WindingCaps& caps, const SignOutput& output) : axes(axes), caps(caps), output(output) {}

    const int& count(int i, int j, int k) const { return counts[std::ptrdiff_t((j - j0) + kEdge * (k - k0)) * stride + (i - i0)]; }
    static std::uint64_t bit(int i, int j) { return std::uint64_t(1) << (i + kEdge * j); }
    std::uint64_t& row(int k) { return undecided[k - k0]; }
    // A sample's index in the brick.
    int local(const glm::ivec3& q) const { return (q.x - i0) + kEdge * ((q.y - j0) + kEdge * (q.z - k0)); }
    // The region whose samples are decided together: the brick, or an octant (layers [ka, ke),
    // bits `mask` of each).
    int ka = 0, ke = 0;
    std::uint64_t mask = 0;
    int undecidedCount() {
        int n = 0;
        for (int k = ka; k < ke; ++k) n += __builtin_popcountll(row(k) & mask);
        return n;
    }
    // f(i, j, k) for each undecided sample of the region, in the grid's order.
    template <class F>
    void forEachUndecided(const F& f) {
        for (int k = ka; k < ke; ++k)
            for (std::uint64_t bits = row(k) & mask; bits; bits &= bits - 1) {
                const int b = __builtin_ctzll(bits);
                f(i0 + b % kEdge, j0 + b / kEdge, k);
            }
    }
    // Sets the region to [ia, ie) x [ja, je) x [k, kEnd), and its ball.
    void region(int ia, int ja, int k, int ie, int je, int kEnd) {
        ka = k, ke = kEnd, mask = 0;
        for (int j = ja; j < je; ++j)
            for (int i = ia; i < ie; ++i) mask |= bit(i - i0, j - j0);
        std::tie(centre, reach) = axes.ball(ia, ja, ka, ie, je, ke);
    }

    // Decides the brick: by its counts where no fan can reach it; else, given the fans' winding
    // number at its centre (`centreFans`: the band's bricks that fans reach, estimated a row at a
    // time, or none), by that where no fan meets it (decideByEstimate); else by its near fans'
    // expansion; the samples left measure the near fans, the whole brick's at once where its ball
    // meets at most kMaxExactFans fans (its expanded cut is smooth), else by octants, each
    // measuring only the fans near it (a brick among many small holes meets dozens).
    void decide(int ib, int jb, int kb, int ie, int je, int ke, const int* brickCounts, int rowStride,
                const CentreEstimate* centreFans = nullptr) {
        i0 = ib, j0 = jb, k0 = kb, i1 = ie, j1 = je, k1 = ke;
        counts = brickCounts;
        stride = rowStride;
        std::uint64_t layer = 0; // the brick's samples in one of its layers
        for (int j = 0; j < je - jb; ++j)
            for (int i = 0; i < ie - ib; ++i) layer |= bit(i, j);
        for (int k = 0; k < kEdge; ++k) undecided[k] = k < ke - kb ? layer : 0;
        if (!centreFans && axes.clearOfFans(caps, i0, j0, k0, i1, j1, k1)) { // the counts decide (as insideNear() would)
            const SignOutput out = output; // a local copy: its pointers stay in registers across the stores
            for (int k = k0; k < k1; ++k)
                for (int j = j0; j < j1; ++j) {
                    const int* rowCounts = &count(i0, j, k);
                    const std::size_t rowStart = out.index(i0, j, k);
                    for (int i = 0; i < i1 - i0; ++i) out.set(rowStart + std::size_t(i), rowCounts[i] != 0);
                }
            return;
        }
        region(i0, j0, k0, i1, j1, k1);
        if (centreFans && decideByEstimate(*centreFans)) return;
        if (decideByExpansion()) return;
        if (expanded.smooth) {
            decideByMeasuring(&expanded);
            return;
        }
        const int half = kEdge / 2;
        for (int dk = 0; dk < kEdge; dk += half)
            for (int dj = 0; dj < kEdge; dj += half)
                for (int di = 0; di < kEdge; di += half) {
                    const int x0 = i0 + di, y0 = j0 + dj, z0 = k0 + dk;
                    const int x1 = std::min(i1, x0 + half), y1 = std::min(j1, y0 + half), z1 = std::min(k1, z0 + half);
                    if (x1 <= x0 || y1 <= y0 || z1 <= z0) continue;
                    region(x0, y0, z0, x1, y1, z1);
                    if (undecidedCount() > 0) decideByMeasuring(&expanded);
                }
    }

    // Decides sample q where the fans' winding number there, estimated as `fans` by the cut's
    // expansions at offset `distance` from its centre, keeps |w| off 1/2 by more than its bounds.
    bool settle(const glm::ivec3& q, double fans, double distance, const WindingCaps::Cut& cut) {
        // |w| - 1/2: its distance from 0 bounds w's from both 1/2 and -1/2.
        const double x = std::fabs(double(count(q.x, q.y, q.z)) - fans) - 0.5;
        const double spread = cut.farSum + (cut.curvature * distance + cut.slack) * distance;
        if (!(std::fabs(x) > spread * (1.0 + 1e-12) + WindingCaps::kDecisionMargin)) {
            room[local(q)] = std::fabs(x) - (spread - cut.farSum);
            return false;
        }
        output.set(output.index(q.x, q.y, q.z), x > 0.0);
        row(q.z) &= ~bit(q.x - i0, q.y - j0);
        return true;
    }

    // Per sample left in doubt by settle(): how far |w| - 1/2 is from 0 but for the far bounds.
    double room[kEdge * kEdge * kEdge];
    // The cut's far fans expanded (WindingCaps::expandFar) for the samples that settle() left in
    // doubt, where that would decide enough of them: a quarter and at least kFarExpansionLeast,
    // whose room exceeds the far bounds it would leave; to a finer target where the samples that
    // decides beyond the coarser one's are enough again (of those the coarser leaves): among open
    // parts most samples lie within 0.1 of |w| = 1/2, and the fans of the other parts bound them
    // by hundredths together. Beside small holes the samples left are those near |w| = 1/2, which
    // no expansion of far fans decides (it would cost more than the fans measured at them). With
    // `limited` (where the samples left can still measure their fans: after a brick's expansion),
    // at most kFarFansPerSample fans are expanded for each sample it would decide: beside many
    // small holes, the far fans are many and those samples few. Whether the cut changed (its
    // samples are then settled again by the caller).
    static constexpr int kFarExpansionLeast = 8;
    static constexpr std::size_t kFarFansPerSample = 2;
    bool expandFarFans(WindingCaps::Cut& cut, bool limited) {
        if (undecidedCount() == 0) return false;
        const WindingCaps::FarToExpand opened = caps.farToExpand(cut);
        if (!(opened.sum > kFarTargets[std::size(kFarTargets) - 1])) return false;
        const double rest = cut.farSum - opened.sum;
        int doubtful = 0, decidedAt[std::size(kFarTargets)] = {};
        forEachUndecided([&](int i, int j, int k) {
            ++doubtful;
            const double r = room[local({i, j, k})];
            for (std::size_t t = 0; t < std::size(kFarTargets); ++t) decidedAt[t] += r > rest + 2.0 * kFarTargets[t];
        });
        auto pays = [&](int decided, int among) { return decided >= kFarExpansionLeast && 4 * decided >= among; };
        double target = 0.0;
        int decided = 0;
        for (std::size_t t = 0; t < std::size(kFarTargets); ++t) {
            if (opened.sum > kFarTargets[t] && pays(decidedAt[t] - decided, doubtful - decided)) target = kFarTargets[t], decided = decidedAt[t];
        }
        if (decided == 0) return false;
        const std::size_t maxFans = limited ? kFarFansPerSample * std::size_t(decided) : std::numeric_limits<std::size_t>::max();
        if (!caps.expandFar(cut, opened, target, maxFans)) return false;
        ++farExpanded;
        return true;
    }

    // settle() for each undecided sample of the region, given the fans' winding number there as
    // value(n, offset): n its index in the brick, offset its position less the centre. A loop of
    // its own: it runs for every sample of every brick that fans reach. Returns the samples decided.
    template <class Value>
    int settleEach(const WindingCaps::Cut& cut, const Value& value) {
        int decided = 0;
        for (int k = ka; k < ke; ++k) {
            const double dz = axes.z[k] - centre.z;
            for (std::uint64_t bits = row(k) & mask; bits; bits &= bits - 1) {
                const int b = __builtin_ctzll(bits), i = i0 + b % kEdge, j = j0 + b / kEdge;
                const glm::dvec3 offset(axes.x[i] - centre.x, axes.y[j] - centre.y, dz);
                decided += settle({i, j, k}, value(b + kEdge * kEdge * (k - k0), offset), glm::length(offset), cut);
            }
        }
        return decided;
    }

    // The undecided samples, a batch of up to kFanPoints at a time: their fans are measured together.
    glm::dvec3 points[kFanPoints];
    glm::ivec3 at[kFanPoints];
    int batch = 0;
    template <class F>
    void forEachBatch(const F& decideBatch) {
        forEachUndecided([&](int i, int j, int k) {
            points[batch] = axes.position(i, j, k), at[batch] = glm::ivec3(i, j, k);
            if (++batch == kFanPoints) decideBatch(), batch = 0;
        });
        if (batch > 0) decideBatch(), batch = 0;
    }

    // Where no fan meets the brick, the fans' winding number is harmonic over it (the surface
    // inside or not) and moves from its value at the centre by at most windingVariation's bound:
    // each sample whose count keeps |w| off 1/2 by more than that and the estimate's error is
    // decided. Whether that decides every sample.
    bool decideByEstimate(const CentreEstimate& estimate) {
        if (!(estimate.variation < WindingCaps::kMostEstimateVariation)) return false;
        const double spread = estimate.fans.spread(estimate.variation);
        forEachUndecided([&](int i, int j, int k) {
            const double x = std::fabs(double(count(i, j, k)) - estimate.fans.value) - 0.5; // |w| - 1/2, within spread
            if (!(std::fabs(x) > spread)) return;
            output.set(output.index(i, j, k), x > 0.0);
            row(k) &= ~bit(i - i0, j - j0);
        });
        return undecidedCount() == 0;
    }

    // The near fans expanded at the centre, the fans the ball may meet measured: whether that
    // decides every sample.
    bool decideByExpansion() {
        WindingCaps::Cut& cut = expanded;
        caps.cut(centre, reach, kExpandTarget, kExpandedFans, true, cut);
        if (!cut.smooth) return false;
        evaluations += cut.nearNodes.size();
        double exactAt[kEdge * kEdge * kEdge]; // the exact fans' winding number at each sample
        const bool exact = !cut.exactNodes.empty();
        if (exact) {
            forEachBatch([&] {
                double measured[kFanPoints];
                evaluations += caps.fanWindings(cut.exactNodes, points, batch, measured);
                for (int s = 0; s < batch; ++s) exactAt[local(at[s])] = measured[s];
            });
        }
        auto settleAll = [&] {
            const double near = cut.nearValue + cut.farValue;
            const glm::dvec3 gradient = cut.nearGradient + cut.farGradient;
            const int decided = settleEach(cut, [&](int n, const glm::dvec3& offset) {
                return near + glm::dot(gradient, offset) + (exact ? exactAt[n] : 0.0);
            });
            if (exact) exactDecided += std::size_t(decided);
        };
        settleAll();
        if (expandFarFans(cut, true)) settleAll(); // the samples left, with the far fans expanded too
        return undecidedCount() == 0;
    }

    // The region's samples left measure its near fans: first the nearest few, with the far fans
    // expanded for the samples those leave in doubt where that pays (WindingCaps::expandFar); where
    // the nearest left every sample in doubt, the cut is carried on to the loose target (the fans
    // it adds measured at the samples left, the far ones expanded again); while samples are left
    // in doubt, the cut is carried on to ever tighter targets and only the fans it adds are
    // measured at those samples (beside an open sheet, where |w| nears 1/2, that costs a fraction
    // of a walk); the samples still in doubt walk the tree on their own.
    void decideByMeasuring(const WindingCaps::Cut* within) {
        double nearAt[kEdge * kEdge * kEdge] = {};
        // Measures the cut's near fans from `from` on, adds them to each undecided sample's
        // nearAt and settles the samples that decides.
        auto measure = [&](const WindingCaps::Cut& measured, std::size_t from) {
            forEachBatch([&] {
                double near[kFanPoints];
                evaluations += caps.fanWindings(measured.nearNodes.data() + from, measured.nearNodes.size() - from, points, batch, near);
                for (int s = 0; s < batch; ++s) {
                    double& total = nearAt[local(at[s])];
                    total += near[s];
                    const glm::dvec3 offset = points[s] - centre;
                    settle(at[s], total + measured.farValue + glm::dot(measured.farGradient, offset), glm::length(offset), measured);
                }
            });
        };
        const int points = undecidedCount();
        caps.cut(centre, reach, WindingCaps::kTightTarget, WindingCaps::kNearestFans, false, nearest, within, false, points);
        // The samples left by a measure, settled again with the cut's far fans expanded too.
        auto settleExpanded = [&](WindingCaps::Cut& cut) {
            if (!expandFarFans(cut, false)) return;
            settleEach(cut, [&](int n, const glm::dvec3& offset) { return nearAt[n] + cut.farValue + glm::dot(cut.farGradient, offset); });
        };
        const bool hopeless = nearest.spread() > WindingCaps::kHopeless;
        measure(nearest, 0);
        settleExpanded(nearest);
        WindingCaps::Cut* measured = &nearest;
        if (hopeless && undecidedCount() > 0 && nearest.spread() > WindingCaps::kLooseTarget) {
            caps.cut(centre, reach, WindingCaps::kLooseTarget, nearest.nearNodes.size() + WindingCaps::kMeasuredFans, false, loose, &nearest, true,
                     undecidedCount());
            measure(loose, nearest.nearNodes.size());
            measured = &loose;
            settleExpanded(loose);
        }
        int flip = 0;
        for (double target : WindingCaps::kCarriedTargets) {
            if (!(measured->spread() > target)) continue; // met already
            const int doubtful = undecidedCount();
            if (doubtful == 0) break;
            WindingCaps::Cut& next = carried[flip ^= 1];
            carriedOn += std::size_t(doubtful);
            caps.cut(centre, reach, target, measured->nearNodes.size() + WindingCaps::kMeasuredFans, false, next, measured, true, doubtful);
            measure(next, measured->nearNodes.size());
            measured = &next;
        }

        forEachUndecided([&](int i, int j, int k) {
            output.set(output.index(i, j, k),
                       caps.insideNear(axes.position(i, j, k), count(i, j, k), nearAt[local({i, j, k})], *measured, scratch, &evaluations));
        });
    }
};

// Signed crossings of rows' lines (parallel to x, through the samples' own (y, z) in double, as
// crossingsAhead's and the GPU's shaders/winding_rows.comp are) with the closed surface: the mesh,
// copies of a triangle counted once with their number as the weight, and the fans. The scan
// triangles are bucketed to groups of `planes` z planes, in index order, so that each row's
// crossings are the same for any thread count.
struct Crossing {
    double x;
    int sign; // +weight where the surface faces +x: moving along +x leaves the solid there
};
class RowCrossings {
public:
    RowCrossings(const Mesh& mesh, const MeshTopology& topology, const WindingCaps& caps, const Grid& grid, const SampleAxes& axes,
                 int planes, const RunControl& control)
        : mesh_(mesh), topology_(topology), grid_(grid), axes_(axes), planes_(planes) {
        for (std::uint32_t t = 0; t < mesh.triangleCount(); ++t) {
            if (topology.copies(t)) firstCopies_.push_back(t);
        }
        for (const Cap& cap : caps.caps()) {
            for (std::size_t i = 0; i < cap.loop.size(); ++i) {
                capTriangles_.push_back({cap.loop[(i + 1) % cap.loop.size()], cap.loop[i], cap.centre, cap.weight});
            }
        }
        const std::size_t scanCount = firstCopies_.size() + capTriangles_.size();
        const int nz = grid.dims.z, ny = grid.dims.y;
        const glm::dvec3 first = localPosition(mesh, grid, 0, 0, 0);
        const double h = grid.voxel / mesh.unit;
        groups_ = (nz + planes - 1) / planes;
        // Each scan triangle's candidate planes (k) and rows (j), in parallel by chunks of triangles.
        candidates_.resize(scanCount);
        constexpr std::size_t kChunk = 4096;
        parallelFor((scanCount + kChunk - 1) / kChunk, control, [&](std::size_t chunk) {
            for (std::size_t index = chunk * kChunk; index < std::min(scanCount, (chunk + 1) * kChunk); ++index) {
                const ScanTriangle s = triangle(index);
                const auto [k0, k1] = sampleRange(std::min({s.a.z, s.b.z, s.c.z}), std::max({s.a.z, s.b.z, s.c.z}), first.z, h, nz);
                const auto [j0, j1] = sampleRange(std::min({s.a.y, s.b.y, s.c.y}), std::max({s.a.y, s.b.y, s.c.y}), first.y, h, ny);
                candidates_[index] = {k0, k1, j0, j1};
            }
        });
        groupStart_.assign(std::size_t(groups_) + 1, 0);
        for (std::size_t index = 0; index < scanCount; ++index) {
            const Candidates& c = candidates_[index];
            if (c.k0 > c.k1) continue;
            for (int group = c.k0 / planes; group <= c.k1 / planes; ++group) ++groupStart_[std::size_t(group) + 1];
        }
        for (int group = 0; group < groups_; ++group) groupStart_[std::size_t(group) + 1] += groupStart_[std::size_t(group)];
        groupTriangles_.resize(groupStart_.back());
        std::vector<std::size_t> fill(groupStart_.begin(), groupStart_.end() - 1);
        for (std::size_t index = 0; index < scanCount; ++index) {
            const Candidates& c = candidates_[index];
            if (c.k0 > c.k1) continue;
            for (int group = c.k0 / planes; group <= c.k1 / planes; ++group) {
                groupTriangles_[fill[std::size_t(group)]++] = std::uint32_t(index);
            }
        }
    }
    int groups() const { return groups_; }
    // Whether no scan triangle reaches group g's planes: their rows cross nothing.
    bool crossesNothing(int g) const { return groupStart_[std::size_t(g)] == groupStart_[std::size_t(g) + 1]; }
    // Appends the crossings of the rows of group g's planes k to rows[(k - g * planes) * ny + j].
    void fill(int g, std::vector<Crossing>* rows) const {
        const int ny = grid_.dims.y;
        const int groupLo = g * planes_, groupHi = std::min(grid_.dims.z - 1, groupLo + planes_ - 1);
        for (std::size_t n = groupStart_[std::size_t(g)]; n < groupStart_[std::size_t(g) + 1]; ++n) {
            const ScanTriangle s = triangle(groupTriangles_[n]);
            const Candidates& c = candidates_[groupTriangles_[n]];
            const int k0 = std::max(groupLo, c.k0), k1 = std::min(groupHi, c.k1);
            for (int k = k0; k <= k1; ++k) {
                for (int j = c.j0; j <= c.j1; ++j) {
                    int orientation2d;
                    glm::dvec3 w;
                    if (!pointInTriangle2d({axes_.y[j], axes_.z[k]}, {s.a.y, s.a.z}, {s.b.y, s.b.z}, {s.c.y, s.c.z}, orientation2d, w)) continue;
                    rows[std::size_t(k - groupLo) * std::size_t(ny) + std::size_t(j)].push_back(
                        {w.x * s.a.x + w.y * s.b.x + w.z * s.c.x, orientation2d * s.weight});
                }
            }
        }
    }

private:
    struct ScanTriangle {
        glm::dvec3 a, b, c;
        int weight;
    };
    struct Candidates {
        int k0, k1, j0, j1;
    };
    ScanTriangle triangle(std::size_t index) const {
        if (index >= firstCopies_.size()) return capTriangles_[index - firstCopies_.size()];
        const std::uint32_t t = firstCopies_[index];
        return {glm::dvec3(mesh_.vertex(t, 0)), glm::dvec3(mesh_.vertex(t, 1)), glm::dvec3(mesh_.vertex(t, 2)), int(topology_.copies(t))};
    }
    const Mesh& mesh_;
    const MeshTopology& topology_;
    const Grid& grid_;
    const SampleAxes& axes_;
    int planes_, groups_ = 0;
    std::vector<std::uint32_t> firstCopies_;
    std::vector<ScanTriangle> capTriangles_;
    std::vector<Candidates> candidates_;
    std::vector<std::size_t> groupStart_;
    std::vector<std::uint32_t> groupTriangles_;
};

void windingSigns(const Mesh& mesh, const MeshTopology& topology, const Grid& grid, const SignOutput& output,
                  const RunControl& control, WindingStats* stats) {
    const WindingCaps caps(topology);
    const int nx = grid.dims.x, ny = grid.dims.y, nz = grid.dims.z;
    const SampleAxes axes(mesh, grid);

    // 1. Signed crossings of every row's line (parallel to x) with the closed surface mesh + fans.
    constexpr int kBandPlanes = 4;
    std::vector<std::vector<Crossing>> rows(std::size_t(ny) * std::size_t(nz));
    {
        const RowCrossings scan(mesh, topology, caps, grid, axes, kBandPlanes, control.phase(0.0, 0.05));
        // Parallel over bands of z planes: each band's rows are written by its item alone.
        parallelFor(std::size_t(scan.groups()), control.phase(0.05, 0.3), [&](std::size_t band) {
            scan.fill(int(band), &rows[std::size_t(band) * kBandPlanes * std::size_t(ny)]);
        });
    }

    // 2. Per block of kBrickEdge² rows: the closed surface's winding number is the signed count of
    //    crossings ahead (+x); then, per brick of kBrickEdge³ samples, the fans' winding number is
    //    subtracted wherever it might matter.
    constexpr int kBrickEdge = BrickSigns::kEdge;
    std::atomic<std::size_t> fanEvaluations{0}, exactFanSamples{0}, carriedSamples{0}, farExpansions{0};
    const int blocksY = (ny + kBrickEdge - 1) / kBrickEdge, blocksZ = (nz + kBrickEdge - 1) / kBrickEdge;
    parallelFor(std::size_t(blocksY) * std::size_t(blocksZ), control.phase(0.3, 1.0), [&](std::size_t block) {
        const int jb = kBrickEdge * int(block % std::size_t(blocksY)), kb = kBrickEdge * int(block / std::size_t(blocksY));
        const int je = std::min(ny, jb + kBrickEdge), ke = std::min(nz, kb + kBrickEdge);
        std::vector<int> ahead(std::size_t(kBrickEdge * kBrickEdge) * std::size_t(nx));
        auto rowAhead = [&](int j, int k) { return &ahead[std::size_t((k - kb) * kBrickEdge + (j - jb)) * std::size_t(nx)]; };
        for (int k = kb; k < ke; ++k) {
            for (int j = jb; j < je; ++j) {
                std::vector<Crossing>& crossings = rows[std::size_t(k) * std::size_t(ny) + std::size_t(j)];
                std::sort(crossings.begin(), crossings.end(), [](const Crossing& l, const Crossing& r) { return l.x > r.x; });
                int* counts = rowAhead(j, k);
                int count = 0;
                std::size_t next = 0;
                for (int i = nx - 1; i >= 0; --i) {
                    const double x = axes.x[i];
                    while (next < crossings.size() && crossings[next].x > x) count += crossings[next++].sign;
                    counts[i] = count;
                }
                std::vector<Crossing>().swap(crossings); // done with this row
            }
        }
        SignOutput layout = output;
        layout.rowStride = nx, layout.planeStride = std::ptrdiff_t(nx) * ny;
        BrickSigns brick(axes, caps, layout);
        for (int ib = 0; ib < nx; ib += kBrickEdge) {
            brick.decide(ib, jb, kb, std::min(nx, ib + kBrickEdge), je, ke, ahead.data() + ib, nx);
        }
        const std::size_t evaluations = brick.evaluations;
        fanEvaluations += evaluations;
        exactFanSamples += brick.exactDecided;
        carriedSamples += brick.carriedOn;
        farExpansions += brick.farExpanded;
    });
    if (stats) {
        stats->caps = caps.caps().size();
        stats->fanEvaluations = fanEvaluations;
        stats->exactFanSamples = exactFanSamples;
        stats->carriedSamples = carriedSamples;
        stats->farExpansions = farExpansions;
    }
}

} // namespace

namespace {

// One layer of bricks (8 planes of samples) of a narrow-band bake: each brick row's stored bricks
// signed, its fan bricks decided, the sided ones taken as they are, and every other brick sided by
// its first sample's count, in runs between the first row's crossings (band sides: see
// bandWindingSigns).
struct BandLayerSigns {
    static constexpr int kEdge = BrickSigns::kEdge;
    // What every layer reads.
    struct Shared {
        const Grid& grid;
        const SampleAxes& axes;
        const WindingCaps& caps;
        const RowCrossings& scan;
        BandSides& band;
        glm::ivec3 brickDims;
        // Where each layer's stored, fan and sided bricks begin (the lists are ordered by z, y, x).
        std::vector<std::size_t> storedStart, fanStart, sidedStart, clearStart;
        std::vector<glm::ivec3> sidedCoordinates;
    };
    // What one layer leaves: its inside boxes, and its fan bricks with both sides and their
    // samples' sides (1 inside: a quarter of their values' bytes until they are merged in).
    struct Output {
        std::vector<std::array<int, 6>> boxes;
        std::vector<glm::ivec3> mixed;
        std::vector<std::uint8_t> inside;
    };

    const Shared& shared;
    Output& out;
    int bz, k0, k1;
    std::size_t stored, fan, sided, clear;             // each list's next brick
    std::size_t storedEnd, fanEnd, sidedEnd, clearEnd; // and the layer's end of it
    std::vector<std::vector<Crossing>> rows;        // (j, k) at (k - k0) * ny + j
    BrickSigns signs;
    // The brick row being signed: its first sample row, whether it has bricks of the lists, and
    // per row r = (j - j0) + 8 (k - k0) the crossings behind the cursor, their sum, and the total.
    int by = 0, j0 = 0, j1 = 0;
    bool listed = false;
    std::size_t cursor[kEdge * kEdge];
    int behind[kEdge * kEdge], total[kEdge * kEdge];
    int counts[kEdge * kEdge * kEdge];
    std::uint8_t flags[kEdge * kEdge * kEdge];
    int runStart = -1; // the first brick of the open run of inside bricks

    BandLayerSigns(const Shared& shared, Output& out, std::size_t layerIndex)
        : shared(shared), out(out), bz(int(layerIndex)), k0(bz * kEdge), k1(std::min(shared.grid.dims.z, k0 + kEdge)),
          stored(shared.storedStart[layerIndex]), fan(shared.fanStart[layerIndex]), sided(shared.sidedStart[layerIndex]),
          clear(shared.clearStart[layerIndex]),
          storedEnd(shared.storedStart[layerIndex + 1]), fanEnd(shared.fanStart[layerIndex + 1]), sidedEnd(shared.sidedStart[layerIndex + 1]),
          clearEnd(shared.clearStart[layerIndex + 1]),
          signs(shared.axes, shared.caps, {}) {}

    void run() {
        // A layer that no triangle reaches and that holds no brick of the lists is outside
        // everywhere (every count 0): nothing to record, so empty space costs nothing.
        if (shared.scan.crossesNothing(bz) && stored == storedEnd && fan == fanEnd && sided == sidedEnd) return;
        rows.resize(std::size_t(kEdge) * std::size_t(shared.grid.dims.y));
        shared.scan.fill(bz, rows.data());
        for (by = 0; by < shared.brickDims.y; ++by) brickRow();
    }

    std::vector<Crossing>& rowAt(int j, int k) { return rows[std::size_t(k - k0) * std::size_t(shared.grid.dims.y) + std::size_t(j)]; }
    bool inRow(const glm::ivec3& b) const { return b.y == by && b.z == bz; }
    // The signed crossings ahead of sample i on row r (i ascending along each row).
    int aheadAt(int r, int i) {
        const std::vector<Crossing>& row = rowAt(j0 + r % kEdge, k0 + r / kEdge);
        while (cursor[r] < row.size() && row[cursor[r]].x <= shared.axes.x[i]) behind[r] += row[cursor[r]++].sign;
        return total[r] - behind[r];
    }
    void closeRun(int end) {
        if (runStart >= 0) out.boxes.push_back(SparseField::insideBox(shared.grid.dims, runStart, end, by, bz));
        runStart = -1;
    }

    void brickRow() {
        const BandSides& band = shared.band;
        j0 = by * kEdge, j1 = std::min(shared.grid.dims.y, j0 + kEdge);
        listed = (stored < storedEnd && inRow(band.bricks[stored])) || (sided < sidedEnd && inRow(shared.sidedCoordinates[sided])) ||
                 (fan < fanEnd && inRow(band.fanBricks[fan]));
        const std::vector<Crossing>& firstRow = rowAt(j0, k0); // (j0, k0): the other bricks' sides
        if (!listed && firstRow.empty()) return;              // outside throughout
        // The brick row's rows, crossings in ascending x: ahead of x is the total minus those at
        // or behind x. Without bricks of the lists, only the first row decides.
        for (int r = 0; r < kEdge * kEdge; ++r) {
            cursor[r] = 0, behind[r] = 0, total[r] = 0;
            const int j = j0 + r % kEdge, k = k0 + r / kEdge;
            if (j >= j1 || k >= k1 || (r > 0 && !listed)) continue;
            std::vector<Crossing>& row = rowAt(j, k);
            std::sort(row.begin(), row.end(), [](const Crossing& l, const Crossing& r) { return l.x < r.x; });
            for (const Crossing& c : row) total[r] += c.sign;
        }
        if (listed) estimateRow();
        runStart = -1;
        for (int bx = 0; bx < shared.brickDims.x; ++bx) {
            const int next = nextListed();
            if (bx < next) {
                bx = clearRun(bx, next, firstRow) - 1;
                continue;
            }
            const int side = listedBrick(bx);
            if (side == 1) {
                if (runStart < 0) runStart = bx;
            } else {
                closeRun(bx);
            }
        }
        closeRun(shared.brickDims.x);
    }

    // The brick row's stored bricks from `stored` on: whether each is clear of the fans (listed in
    // band.clearBricks, or far from every fan), and for the others that no fan meets the fans'
    // winding number at the centre, estimated kFanPoints at a time (one pass over the fan tree, the
    // fans measured by the kernel, to kCentreNodeError a node), with its variation, for
    // BrickSigns::decideByEstimate. A brick that a fan meets, or where the fans vary too much,
    // takes no estimate.
    static constexpr double kCentreNodeError = 1e-3;
    std::size_t rowFirst = 0;
    std::vector<std::uint8_t> rowClear;
    std::vector<BrickSigns::CentreEstimate> rowFans;
    void estimateRow() {
        const BandSides& band = shared.band;
        const WindingCaps& caps = shared.caps;
        rowFirst = stored;
        std::size_t end = stored;
        while (end < storedEnd && inRow(band.bricks[end])) ++end;
        rowClear.assign(end - stored, 0);
        rowFans.assign(end - stored, {});
        glm::dvec3 centres[kFanPoints];
        std::size_t at[kFanPoints];
        int batch = 0;
        auto flush = [&] {
            WindingCaps::FansEstimate fans[kFanPoints];
            if (batch > 0) caps.estimateFans(centres, batch, kCentreNodeError, fans);
            for (int b = 0; b < batch; ++b) rowFans[at[b]].fans = fans[b];
            batch = 0;
        };
        for (std::size_t s = stored; s < end; ++s) {
            const glm::ivec3& brick = band.bricks[s];
            const int i0 = brick.x * kEdge, i1 = std::min(shared.grid.dims.x, i0 + kEdge);
            while (clear < clearEnd && brickBefore(band.clearBricks[clear], brick)) ++clear;
            if ((clear < clearEnd && band.clearBricks[clear] == brick) || shared.axes.clearOfFans(caps, i0, j0, k0, i1, j1, k1)) {
                rowClear[s - stored] = 1;
                continue;
            }
            const auto [centre, reach] = shared.axes.ball(i0, j0, k0, i1, j1, k1); // as BrickSigns::region's
            if (!caps.fansMiss(centre, reach)) continue;
            const double variation = caps.windingVariation(centre, reach, WindingCaps::kMostEstimateVariation);
            if (!(variation < WindingCaps::kMostEstimateVariation)) continue;
            rowFans[s - stored].variation = variation;
            centres[batch] = centre, at[batch] = s - stored;
            if (++batch == kFanPoints) flush();
        }
        flush();
    }

    // The brick row's next brick of the lists (the row's end when none is left).
    int nextListed() const {
        const BandSides& band = shared.band;
        int next = shared.brickDims.x;
        if (stored < storedEnd && inRow(band.bricks[stored])) next = std::min(next, band.bricks[stored].x);
        if (sided < sidedEnd && inRow(shared.sidedCoordinates[sided])) next = std::min(next, shared.sidedCoordinates[sided].x);
        if (fan < fanEnd && inRow(band.fanBricks[fan])) next = std::min(next, band.fanBricks[fan].x);
        return next;
    }

    // Bricks [bx, next) are out of the band and clear of the fans: the surface is nowhere in them,
    // so every sample has its first sample's count and, the fans' winding number being below 0.45
    // there, is inside when that count is not 0 (as the dense bake decides). That count changes
    // only where the first row crosses the surface: the bricks up to the next crossing go as one
    // run. Returns the run's end.
    int clearRun(int bx, int next, const std::vector<Crossing>& firstRow) {
        const bool inside = aheadAt(0, bx * kEdge) != 0;
        int end = next;
        if (cursor[0] < firstRow.size()) { // the first brick whose first sample is at or past the next crossing
            const double x = firstRow[cursor[0]].x;
            int lo = bx + 1, hi = next;
            while (lo < hi) {
                const int mid = lo + (hi - lo) / 2;
                if (shared.axes.x[std::size_t(mid) * kEdge] >= x) hi = mid;
                else lo = mid + 1;
            }
            end = lo;
        }
        if (!inside) closeRun(bx);
        else if (runStart < 0) runStart = bx;
        return end;
    }

    // Every sample's count of brick bx, and its sides decided as the dense bake decides them.
    void decide(int bx, const SignOutput& output, const BrickSigns::CentreEstimate* centreFans = nullptr) {
        const int i0 = bx * kEdge, i1 = std::min(shared.grid.dims.x, i0 + kEdge);
        for (int k = k0; k < k1; ++k)
            for (int j = j0; j < j1; ++j) {
                const int r = (j - j0) + kEdge * (k - k0);
                for (int i = i0; i < i1; ++i) counts[r * kEdge + (i - i0)] = aheadAt(r, i);
            }
        signs.output = output;
        signs.decide(i0, j0, k0, i1, j1, k1, counts, kEdge, centreFans);
    }

    // The brick of the lists at bx: its side (1 inside, 0 outside, -1 both).
    int listedBrick(int bx) {
        BandSides& band = shared.band;
        const glm::ivec3 brick(bx, by, bz);
        const std::ptrdiff_t local = -(std::ptrdiff_t(bx) * kEdge + std::ptrdiff_t(j0) * kEdge + std::ptrdiff_t(k0) * kEdge * kEdge);
        if (stored < storedEnd && band.bricks[stored] == brick) {
            signStored(bx, &band.values[stored * std::size_t(SparseField::kBrickSamples)], local);
            ++stored;
            return -1;
        }
        if (sided < sidedEnd && shared.sidedCoordinates[sided] == brick) return band.sidedBricks[sided++].second;
        // The fan list's brick (one of the lists has a brick at bx).
        ++fan;
        std::fill(std::begin(flags), std::end(flags), std::uint8_t(2)); // past the grid's end: neither side
        static constexpr BrickSigns::CentreEstimate reached{}; // the search found fans reaching it: no estimate
        decide(bx, {flags, nullptr, local, kEdge, kEdge * kEdge}, &reached);
        bool in = false, outside = false;
        for (const std::uint8_t f : flags) in |= f == 1, outside |= f == 0;
        if (in && outside) {
            out.mixed.push_back(brick);
            for (const std::uint8_t f : flags) out.inside.push_back(f == 1);
            return -1;
        }
        return in ? 1 : 0;
    }

    // A stored brick's values signed where inside, and clamped to ±background out of the band.
    void signStored(int bx, float* values, std::ptrdiff_t local) {
        const BandSides& band = shared.band;
        const int i0 = bx * kEdge, i1 = std::min(shared.grid.dims.x, i0 + kEdge);
        const bool clear = rowClear[stored - rowFirst];
        const BrickSigns::CentreEstimate* centreFans = clear ? nullptr : &rowFans[stored - rowFirst];
        if (clear && band.signBricks) {
            // Clear of the fans (most of the band): negated where the count is not 0, as BrickSigns decides.
            for (int k = k0; k < k1; ++k)
                for (int j = j0; j < j1; ++j) {
                    const int r = (j - j0) + kEdge * (k - k0);
                    float* row = values + r * kEdge;
                    const std::vector<Crossing>& crossings = rowAt(j, k);
                    for (int i = i0; i < i1;) { // by runs of samples with no crossing between them
                        const bool inside = aheadAt(r, i) != 0;
                        const double next = cursor[r] < crossings.size() ? crossings[cursor[r]].x : std::numeric_limits<double>::infinity();
                        int end = i + 1;
                        while (end < i1 && next > shared.axes.x[end]) ++end;
                        if (inside) {
                            for (int n = i; n < end; ++n) row[n - i0] = -row[n - i0];
                        }
                        i = end;
                    }
                }
        } else if (band.signBricks) {
            decide(bx, {nullptr, values, local, kEdge, kEdge * kEdge}, centreFans);
        } else {
            // Signed as measured, but for the samples the distance pass skipped (out of the band,
            // still +background): theirs are the winding sign's (their counts', clear of the fans).
            std::fill(std::begin(flags), std::end(flags), std::uint8_t(0));
            const SignOutput sides{flags, nullptr, local, kEdge, kEdge * kEdge};
            if (clear) {
                for (int k = k0; k < k1; ++k)
                    for (int j = j0; j < j1; ++j)
                        for (int i = i0; i < i1; ++i) sides.set(sides.index(i, j, k), aheadAt((j - j0) + kEdge * (k - k0), i) != 0);
            } else {
                decide(bx, sides, centreFans);
            }
            for (int n = 0; n < SparseField::kBrickSamples; ++n) {
                if (flags[n] == 1 && values[n] == band.background) values[n] = -band.background;
            }
        }
        // Out of the band only the side is kept.
        const float background = band.background;
        for (int n = 0; n < SparseField::kBrickSamples; ++n) { // a select, so that it vectorizes
            values[n] = std::fabs(values[n]) < background ? values[n] : std::copysign(background, values[n]);
        }
    }
};

// Where each layer's bricks of `bricks` (ordered by z, y, x) begin, for `layers` layers and the end.
std::vector<std::size_t> layerStarts(const std::vector<glm::ivec3>& bricks, int layers) {
    std::vector<std::size_t> starts(std::size_t(layers) + 1);
    for (int z = 0; z <= layers; ++z) {
        starts[std::size_t(z)] =
            std::size_t(std::lower_bound(bricks.begin(), bricks.end(), z, [](const glm::ivec3& b, int layer) { return b.z < layer; }) -
                        bricks.begin());
    }
    return starts;
}

// The layers' mixed fan bricks joined to the stored ones, in order (merged from the back, in place).
void mergeMixedBricks(std::vector<BandLayerSigns::Output>& layers, BandSides& band) {
    std::size_t added = 0;
    for (const BandLayerSigns::Output& layer : layers) added += layer.mixed.size();
    if (!added) return;
    std::vector<glm::ivec3> mixed;
    std::vector<std::uint8_t> mixedInside;
    mixed.reserve(added), mixedInside.reserve(added * SparseField::kBrickSamples);
    for (BandLayerSigns::Output& layer : layers) {
        mixed.insert(mixed.end(), layer.mixed.begin(), layer.mixed.end());
        mixedInside.insert(mixedInside.end(), layer.inside.begin(), layer.inside.end());
        layer.mixed = {}, layer.inside = {};
    }
    std::size_t a = band.bricks.size(), b = mixed.size(), out = a + b;
    band.bricks.resize(out);
    band.values.resize(out * SparseField::kBrickSamples);
    constexpr std::size_t n = SparseField::kBrickSamples;
    while (b > 0) {
        --out;
        if (a > 0 && brickBefore(mixed[b - 1], band.bricks[a - 1])) {
            --a;
            band.bricks[out] = band.bricks[a];
            std::copy(band.values.begin() + std::ptrdiff_t(a * n), band.values.begin() + std::ptrdiff_t((a + 1) * n),
                      band.values.begin() + std::ptrdiff_t(out * n));
        } else {
            --b;
            band.bricks[out] = mixed[b];
            for (std::size_t k = 0; k < n; ++k) band.values[out * n + k] = mixedInside[b * n + k] ? -band.background : band.background;
        }
    }
}

} // namespace

void bandWindingSigns(const Mesh& mesh, const MeshTopology& topology, const WindingCaps& caps, const Grid& grid, BandSides& band,
                      const RunControl& control) {
    constexpr int kEdge = BandLayerSigns::kEdge;
    static_assert(kEdge == SparseField::kBrick, "the sign's bricks are the sparse field's");
    const glm::ivec3 brickDims = (grid.dims + (kEdge - 1)) / kEdge;
    const SampleAxes axes(mesh, grid);
    const RowCrossings scan(mesh, topology, caps, grid, axes, kEdge, control.phase(0.0, 0.1));
    BandLayerSigns::Shared shared{grid, axes, caps, scan, band, brickDims, {}, {}, {}, {}, {}};
    shared.storedStart = layerStarts(band.bricks, brickDims.z);
    shared.fanStart = layerStarts(band.fanBricks, brickDims.z);
    shared.clearStart = layerStarts(band.clearBricks, brickDims.z);
    shared.sidedCoordinates.resize(band.sidedBricks.size());
    for (std::size_t n = 0; n < band.sidedBricks.size(); ++n) shared.sidedCoordinates[n] = band.sidedBricks[n].first;
    shared.sidedStart = layerStarts(shared.sidedCoordinates, brickDims.z);
    std::vector<BandLayerSigns::Output> layers(std::size_t(brickDims.z));
    // The layers taken costliest first (by their bricks that fans may reach): the last ones to
    // finish are then cheap, and no thread waits long for the others at the end.
    std::vector<std::size_t> order(layers.size());
    std::vector<std::size_t> cost(layers.size());
    for (std::size_t z = 0; z < layers.size(); ++z) {
        order[z] = z;
        cost[z] = (shared.storedStart[z + 1] - shared.storedStart[z]) - (shared.clearStart[z + 1] - shared.clearStart[z]) +
                  (shared.fanStart[z + 1] - shared.fanStart[z]);
    }
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return cost[a] > cost[b]; });
    parallelFor(order.size(), control.phase(0.1, 1.0), [&](std::size_t n) {
        BandLayerSigns(shared, layers[order[n]], order[n]).run();
    });
    mergeMixedBricks(layers, band);
    band.insideBoxes.clear();
    for (const BandLayerSigns::Output& layer : layers) band.insideBoxes.insert(band.insideBoxes.end(), layer.boxes.begin(), layer.boxes.end());
}

std::vector<std::uint8_t> insideByWinding(const Mesh& mesh, const MeshTopology& topology, const Grid& grid,
                                          const RunControl& control, WindingStats* stats) {
    std::vector<std::uint8_t> inside(grid.sampleCount());
    windingSigns(mesh, topology, grid, {inside.data(), nullptr}, control, stats);
    return inside;
}

void signByWinding(const Mesh& mesh, const MeshTopology& topology, const Grid& grid, float* field, const RunControl& control,
                   WindingStats* stats) {
    windingSigns(mesh, topology, grid, {nullptr, field}, control, stats);
}

} // namespace sdfgen

