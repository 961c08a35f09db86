#pragma once
#include "core/accel/bvh.hpp"
#include "core/accel/wide_bvh.hpp"
#include "sdfgen/device.hpp"
#include "sdfgen/grid.hpp"
#include "sdfgen/mesh.hpp"
#include "core/accel/topology.hpp"

#include <glm/geometric.hpp>
#include <algorithm>
#include <cmath>
#include <array>
#include <cstdint>
#include <cstring>
#include <limits>
#include <tuple>
#include <utility>
#include <vector>

namespace sdfgen {

// A fan closing one boundary loop (or a run of one), counted `weight` times. Its triangles are
// (loop[i + 1], loop[i], centre): the loop reversed, so that mesh + fans is closed.
struct Cap {
    std::vector<glm::dvec3> loop;
    glm::dvec3 centre{0.0};
    glm::dvec3 lo{0.0}, hi{0.0}; // bounds of the fan (of the loop and the centre)
    double area = 0;
    int weight = 1;    // equal loops (copies of open triangles) share one cap
    // Per edge loop[i] -> loop[i + 1]: 0 for an edge of the mesh's boundary, else the id of the
    // chord that splits a long loop (or a strip's rung), which exactly one other cap of the same
    // weight runs the other way: where both caps are expanded together, its fields cancel.
    static constexpr std::size_t kMaxEdges = 5;
    std::array<std::uint32_t, kMaxEdges> chord{};
};

struct FanTerms; // below: a cap's first-order expansion over a ball

// The points the fan kernel (core/sign/fan_kernel.hpp) measures at once.
constexpr int kFanPoints = 8;

// The fans that close a mesh's boundary, and a bounding-box hierarchy over them that bounds their
// winding number from afar: seen from a point at distance d > 0 from a node's box, everything
// under the node has |winding number| <= area / (4π d²) (a surface's solid angle is at most its
// area over the squared distance to its nearest point). Boxes, not spheres: the small fans along a
// border are slivers, and a sphere around one would reach far across the sheet.
class WindingCaps {
public:
    // Equal boundary loops become one cap with a weight; loops longer than kMaxCapEdges are closed
    // by several small fans near the loop (runs of it closed by chords, then the chords' polygon).
    static constexpr std::size_t kMaxCapEdges = 4;

    explicit WindingCaps(const MeshTopology& topology);

    const std::vector<Cap>& caps() const { return caps_; }
    bool empty() const { return caps_.empty(); }

    // Inside flag at p, given `ahead`, the signed count of crossings of the mesh and the fans along
    // +x from p (the closed surface's winding number): inside where |w| > 1/2, w the exact winding
    // number (ahead minus the fans'), so that a part is solid whichever way its faces point. Lazy:
    // fans are measured only while the bounds of the rest leave doubt, loosest node first, down to
    // every fan exactly; so the answer is that of w in double and p pays only for the fans that can
    // move w across 1/2 or -1/2. `evaluations` (when given) counts the fans measured.
    bool inside(const glm::dvec3& p, int ahead, std::size_t* evaluations = nullptr) const;
    // The inside flags of `count` points given their counts ahead, each as inside() answers, with
    // fewer fans measured (point queries, whose points come in Morton order, neighbours after each
    // other): a point that every fan together cannot move by 0.45 by its count; then a walk whose
    // waiting nodes count as their multipoles where that bounds them more tightly, measuring at most
    // kWalkBudget fans and deciding only outside kDecisionMargin of 1/2 (skipped, but for one
    // point in eight, where most of the last eight walks were left in doubt); runs of up to
    // kGroupPoints points left within a ball of kGroupSpan of the fans' box share a cut of the
    // fan tree, measure its near fans together (the fan kernel) and are decided by insideNear, as
    // the dense bake's bricks are (the nearest fans, or the loose target's where the nearest
    // leave every point in doubt, carried on through kCarriedTargets while points are left in
    // doubt); a point left alone by inside().
    void insideMany(const glm::dvec3* points, const int* ahead, std::size_t count, std::uint8_t* flags) const;
    static constexpr double kGroupSpan = 1.0 / 32.0;
    static constexpr int kGroupPoints = 128;
    // Most points near a few holes are decided by the first fans or multipoles; a point among many
    // open parts needs dozens, measured more cheaply by a run's shared cut (tuned by time on the
    // Stanford bunny, the bunny with 1.4k holes, an open terrain and the open-parts corpus).
    static constexpr std::size_t kWalkBudget = 2;
    // Whether no fan's box comes within `reach` of p (then no fan meets that ball).
    bool noFanWithin(const glm::dvec3& p, double reach) const { return clearOfFans(p, reach, false); }
    // Whether every point within `reach` of p is decided by `ahead` alone: no fan is near enough
    // to move the winding number by 0.45 (then inside() returns ahead != 0 there).
    bool farFromEveryFan(const glm::dvec3& p, double reach) const;
    // The node as a multipole (dipole to hexadecapole) over a ball that misses its box:
    // its error there (as multipoleError's, d the ball's distance from the box), and its first-order
    // expansion at the centre o, whose rest at o + δ is at most curvature |δ|²: the dipole's
    // potential is D.grad(1/|c - p|), whose third derivatives are at most 3! / r⁴ in every
    // direction, so its Hessian is at most 6 |D| / r⁴; the quadrupole's, with fourth derivatives,
    // at most 24 firstMoment / r⁵; the octupole's, with fifth derivatives and its half, at most
    // 60 secondMoment / r⁶; the hexadecapole's, with sixth and its sixth, at most
    // 120 thirdMoment / r⁷ (r >= |c - o| - reach along the way). Error infinite where the ball
    // reaches the box. (An expanded fan's terms take the same form.)
    struct BallDipole {
        double value = 0, error = std::numeric_limits<double>::infinity(), curvature = 0;
        glm::dvec3 gradient{0.0};
        // An expanded fan's: its chords' terms (Cut::chordTerms[chordFirst, + chordCount)), not in curvature.
        std::uint32_t chordFirst = 0, chordCount = 0;
    };
    // A chord's share of an expanded fan's |Hessian| / 2 bound over a ball (Cap::chord). The two
    // caps on a chord run it both ways, so where both are expanded at the same centre the chord's
    // Biot-Savart fields cancel, and with them its share of the bound: a long loop's fans, split
    // by chords that cross its hole, are bounded together by the loop's own edges.
    struct ChordTerm {
        std::uint32_t id;
        double curvature;
    };
    // Sums the terms whose chord's other side is not among them: a mark per chord id, stamped
    // afresh for each set, so that nothing is sorted or cleared between sets.
    class ChordMarks {
    public:
        // forEach(f) calls f(term) for each term of the set (twice: marks, then sums).
        template <class ForEach>
        double uncancelled(std::uint32_t chords, const ForEach& forEach) {
            if (marks_.size() < chords || stamp_ > std::numeric_limits<std::uint32_t>::max() - 2) {
                marks_.assign(std::max<std::size_t>(marks_.size(), chords), 0);
                stamp_ = 0;
            }
            const std::uint32_t once = ++stamp_, twice = ++stamp_;
            forEach([&](const ChordTerm& term) {
                std::uint32_t& mark = marks_[term.id];
                mark = mark == once ? twice : once;
            });
            double sum = 0.0;
            forEach([&](const ChordTerm& term) {
                if (marks_[term.id] == once) sum += term.curvature;
            });
            return sum;
        }

    private:
        std::vector<std::uint32_t> marks_;
        std::uint32_t stamp_ = 0;
    };
    // A node waiting in a walk, with its bound.
    struct Pending { // 32 bytes: the walks' heaps move them
        double bound;
        std::uint32_t node;
        std::uint32_t slot = 0; // a dipole's terms in the cut's Cut::dipoles
        double estimate = 0; // what the walk counted for the node while it waits (its dipole term, or 0)
        bool dipole = false; // in a cut: bounded as a multipole (or a fan's expansion) expanded at the ball's centre (Cut::farValue)
        bool expanded = false; // in a measured cut: a fan bounded by its exact expansion (Cut's dipoles), measured when opened
        bool operator<(const Pending& other) const { return bound < other.bound; }
    };
    static_assert(sizeof(Pending) == 32, "a waiting node's record packs into 32 bytes");
    // A cut's nodes waiting to be opened, taken loosest first to within a factor of two: bucketed
    // by their bounds' binary exponents, which costs less than a heap's order (a cut needs no more).
    class Waiting {
    public:
        void clear() {
            for (int b = 0; b <= highest_; ++b) buckets_[std::size_t(b)].clear();
            top_ = highest_ = -1;
            count_ = 0;
        }
        bool empty() const { return count_ == 0; }
        void push(const Pending& node) {
            const int b = bucketOf(node.bound);
            buckets_[std::size_t(b)].push_back(node);
            top_ = std::max(top_, b), highest_ = std::max(highest_, b);
            ++count_;
        }
        const Pending& loosest() { // not empty()
            while (buckets_[std::size_t(top_)].empty()) --top_;
            return buckets_[std::size_t(top_)].back();
        }
        void pop() { // the loosest (after loosest())
            buckets_[std::size_t(top_)].pop_back();
            --count_;
        }
        template <class F>
        void forEach(const F& f) const {
            for (int b = 0; b <= highest_; ++b)
                for (const Pending& node : buckets_[std::size_t(b)]) f(node);
        }

    private:
        static constexpr int kBuckets = 64; // 2^-40 and below, ..., 2^22 and above, infinite
        static int bucketOf(double bound) {
            if (!std::isfinite(bound)) return kBuckets - 1;
            std::uint64_t bits;
            std::memcpy(&bits, &bound, sizeof bits);
            return std::clamp(int(bits >> 52 & 0x7ff) - 1023 + 40, 0, kBuckets - 2);
        }
        std::array<std::vector<Pending>, kBuckets> buckets_;
        int top_ = -1, highest_ = -1;
        std::size_t count_ = 0;
    };
    // The fan tree as seen from every point of a ball (a brick of samples, a run of query points):
    // a cut through the tree whose leaves (near fans) are measured and whose other nodes are
    // bounded over the whole ball,
    // opened loosest first (to within a factor of two: Waiting) until the bounds sum to at most
    // `target`, with at most `maxNear` fans measured (beyond those whose boxes the ball touches,
    // which are always measured).
    struct Cut {
        std::vector<std::uint32_t> nearNodes; // leaves
        // With `expand`: leaves whose fan the ball may meet, measured at every point of the ball.
        std::vector<std::uint32_t> exactNodes;
        std::vector<Pending> farNodes; // with their bounds over the ball
        bool farSorted = false; // farNodes loosest first (insideNear sorts them when it first needs them)
        double farSum = 0; // the sum of the far nodes' bounds over the ball
        // The most the far nodes leave in doubt anywhere in the ball: their bounds and their
        // expansions' rest at its rim.
        double spread() const { return farSum + curvature * reach * reach; }
        // The far nodes bounded as multipoles: their winding number at the ball's centre and its
        // gradient (their rest over the ball is in farSum, their expansion's in curvature).
        double farValue = 0;
        glm::dvec3 farGradient{0.0};
        glm::dvec3 centre{0.0}; // the ball
        double reach = 0;
        // The ball misses every near fan, and at most kMaxExactFans are exact: the near fans'
        // winding number is harmonic over it, and differs from its first-order expansion at the
        // centre (nearValue, nearGradient: with `expand`) by at most (curvature * |d| + slack) * |d|
        // at offset d. curvature also bounds the far dipoles' expansion (with or without `expand`).
        bool smooth = true;
        double curvature = 0, slack = 0;
        double nearCurvature = 0; // the near fans' share of curvature, their chords apart
        double nearValue = 0;
        glm::dvec3 nearGradient{0.0};
        // The dipoles' terms over the ball (Pending::slot), computed once for the cut, its sums,
        // its walks and the cuts of the same ball carried on from it.
        std::vector<BallDipole> dipoles;
        // The expanded fans' chord terms (BallDipole::chordFirst), and (with `expand`) the near fans';
        // the far ones' gathered, and their marks.
        std::vector<ChordTerm> chordTerms, nearChords, farChords;
        ChordMarks marks;
        double small = 0; // bounds below this went far unopened, without a dipole tried
        Waiting waiting;              // cut()'s, kept for its memory
        std::vector<Pending> scratch; // the walks' heap, kept for its memory
    };
    // The cuts of a ball of samples or query points whose near fans are measured at every point
    // (BrickSigns' bricks or octants, insideMany's runs): the nearest kNearestFans with the rest within
    // kTightTarget; where those leave the rest bounded by more than kHopeless (a ball among open
    // parts, whose points are mostly far from |w| = 1/2 but near dozens of fans), the fans that bring
    // it within kLooseTarget (a run of query points takes that cut instead; a brick carries the
    // nearest on to it for the samples that the nearest and its far fans expanded leave in doubt),
    // and for the points those leave in doubt, within kTightTarget and on (that cut carried on to
    // each of kCarriedTargets not met yet: its fans kept, only the ones added measured); at most
    // kMeasuredFans each time (tuned by time on open sheets, meshes with many holes and the messy
    // corpus).
    static constexpr double kTightTarget = 0.01, kLooseTarget = 0.1, kHopeless = 0.3;
    // The targets a measured cut is carried on to, in turn, while it leaves points in doubt (up to
    // kMeasuredFans more fans each time): beside an open sheet |w| nears 1/2, and the fans measured
    // together cost less than the walks they spare.
    static constexpr double kCarriedTargets[] = {kTightTarget, 1e-3, 1e-4, 1e-5};
    // From that many query points in doubt a cut is carried on; fewer walk the tree on their own.
    // (A brick carries its cut on for a single sample too: the fans it adds are those its ball
    // needs, measured by the fan kernel, where a walk measures them one by one.)
    static constexpr int kCarriedFrom = 2;
    static constexpr std::size_t kNearestFans = 12, kMeasuredFans = 96;
    // With `expand` (for the near fans' expansion), a fan is near only if the ball misses it and its
    // expansion's rest over the ball is below its bound; a fan the ball may meet is exact; the
    // others stay far. With `within`, the cut of a ball that holds this one's samples, the walk
    // starts from that cut, and its far nodes too small to open keep their bounds. With `keepNear`
    // too (a cut of the same ball whose near fans are measured already), within's near fans stay
    // near, first in nearNodes: only its far nodes are opened, and the fans they add follow.
    void cut(const glm::dvec3& centre, double reach, double target, std::size_t maxNear, bool expand, Cut& out, const Cut* within = nullptr,
             bool keepNear = false, int points = 0) const;
    // Without `expand`, for a cut whose near fans will be measured at `points` >= kExpandedFanPoints
    // points: a fan about to be measured is bounded by its exact first-order expansion at the
    // centre instead (a far dipole: measured only if opened again) where that bounds it at least
    // twice as tightly, and counts as half a near fan towards maxNear. Tried where its surface
    // bound promises that, or where it lies kFarReaches reaches or more away (its edges' bound may
    // be far tighter there). Most of the fans that a brick of samples among open parts would
    // measure lie dozens of reaches away, and an expansion costs about as much as measuring the
    // fan at a few points.
    static constexpr int kExpandedFanPoints = 24;
    // The cut's far nodes that lie kFarReaches reaches or more from its ball, bounded by their
    // area, opened loosest first down to their fans, and each fan expanded exactly at the centre
    // (as a far dipole) where that bounds it more tightly, until those nodes' bounds sum to at
    // most `target`. Seen from a brick beside open parts, the fans of the other parts each bound
    // w by little, yet hundreds of them together bound it by 0.1 to 1. An exact expansion's rest
    // is at most 3/4 of a fan's bound at kFarReaches reaches (surfaceCurvature) and shrinks as
    // the square of the distance: to thousandths of it at the dozens of reaches where most of
    // those fans lie. Far cheaper than measuring those fans at every point left in doubt, but not
    // free: BrickSigns calls it only where it would decide enough of the points left. At most
    // `maxFans` fans are expanded (the loosest first). The nodes it opens are bounded as
    // multipoles where that is tighter down to kFarMultipoleShare of its target: the cut's own
    // threshold (a twentieth of its looser target) would leave thousands of small nodes beside
    // long borders bounded by their area, and opened down to their fans. Whether it changed the cut.
    static constexpr double kFarReaches = 2.0, kFarMultipoleShare = 0.005;
    // The far nodes that expandFar would open, moved to the end of the cut's far nodes: from
    // `first` on, their bounds summing to `sum`.
    struct FarToExpand {
        std::size_t first;
        double sum;
    };
    FarToExpand farToExpand(Cut& cut) const;
    // `opened`: farToExpand's answer for the cut as it is.
    bool expandFar(Cut& cut, const FarToExpand& opened, double target, std::size_t maxFans) const;
    // Beyond that many exact fans (4 edges each, mostly), measuring them at every point costs more
    // than splitting the brick into octants.
    static constexpr std::size_t kMaxExactFans = 4;
    // The winding number of the fans of `leaves` (a cut's near or exact nodes) at each of n <=
    // kFanPoints points, measured together by the fan kernel. Returns the fan measurements made
    // (WindingStats::fanEvaluations).
    std::size_t fanWindings(const std::uint32_t* leaves, std::size_t count, const glm::dvec3* points, int n, double* windings) const;
    std::size_t fanWindings(const std::vector<std::uint32_t>& leaves, const glm::dvec3* points, int n, double* windings) const {
        return fanWindings(leaves.data(), leaves.size(), points, n, windings);
    }
    // The near fans' winding number at p, each fan measured alone, in the cut's order (the fan
    // kernel's reference).
    double nearWinding(const glm::dvec3& p, const Cut& cut) const;
    // inside() for a point of the ball that `cut` was made for, given `near`, the near fans'
    // winding number there (fanWindings): the far nodes bounded (the ball's bounds, far dipoles
    // counted as their expansion; then, loosest first, each far node opened and its children
    // bounded at the point, as multipoles where that is tighter) while |w| is within
    // kDecisionMargin of 1/2 plus the bounds; still in doubt, inside() decides. Deciding
    // only outside that margin, it answers as inside() does (their doubles of w differ by
    // rounding, far below the margin), with the tree's top walked once per brick.
    static constexpr double kDecisionMargin = 1e-7;
    // insideNear's answer where the cut's bounds alone decide it (1 inside, 0 outside), else -1.
    int sideNear(const glm::dvec3& p, int ahead, double near, const Cut& cut) const;
    // `scratch` is any Cut's: its heap is borrowed. The first point that the ball's bounds leave
    // in doubt sorts the cut's far nodes (loosest first), for every later one.
    // `evaluations` counts the fans measured beyond the near ones.
    bool insideNear(const glm::dvec3& p, int ahead, double near, Cut& cut, Cut& scratch, std::size_t* evaluations = nullptr) const;
    // Calls f(cap) for every cap whose box holds p's row (y and z within the box): the only caps
    // whose triangles the row's line can cross (a point outside a triangle's (y, z) box is
    // outside it, whatever the tie-breaking; the boxes bound their points exactly, in double).
    template <class F>
    void forEachCapOnRow(const glm::dvec3& p, F&& f) const {
        if (nodes_.empty()) return;
        std::uint32_t stack[128];
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const Node& node = nodes_[stack[--top]];
            if (p.y < node.lo.y || p.y > node.hi.y || p.z < node.lo.z || p.z > node.hi.z) continue;
            if (node.leaf) {
                f(caps_[node.first]);
            } else {
                stack[top++] = node.first + 1;
                stack[top++] = node.first;
            }
        }
    }
    // The caps and their tree for a compute device (WindingFans).
    WindingFans flattened() const;
    // The exact winding number at p given `ahead`: every fan measured.
    double winding(const glm::dvec3& p, int ahead) const;
    // The side at p (1 inside, 0 outside) where |w| is farther than `margin` from 1/2, else -1
    // (a cube's centre, the margin its variation): from an estimate of the fans where that
    // decides either way, else from a finer one, else from fans measured lazily, loosest node
    // first, as inside() measures them, until the bounds of the rest decide or every fan is
    // measured.
    int sideBeyond(const glm::dvec3& p, int ahead, double margin) const {
        int side = -1;
        sidesBeyond(&p, &ahead, &margin, 1, &side);
        return side;
    }
    // The fans' winding number at each of n <= kFanPoints points within `error`: each node whose
    // multipole (or area's bound) errs by less than `nodeError` at every point counts as that, the
    // others are opened, down to fans measured exactly (the fan kernel, at every point at once).
    // A pass over the nodes near the points, with no heap: cheaper than a walk where a margin
    // well above nodeError is wanted.
    struct FansEstimate {
        double value = 0.0, error = 0.0;
        // How far the fans' winding number may be from `value` anywhere in a ball no fan meets,
        // over which it varies by `variation` (windingVariation), with the decisions' margin.
        double spread(double variation) const { return (error + variation) * (1.0 + 1e-12) + kDecisionMargin; }
        // Whether it stays within 1/2 of 0 there: every point is then inside exactly where its count
        // of crossings ahead is not 0.
        bool countsDecide(double variation) const { return std::fabs(value) + spread(variation) < 0.5; }
    };
    // The most variation over a ball for which an estimate at its centre is worth making: beyond,
    // w within 0.05 of an integer is all it could decide (the band's bricks, and its search for
    // cubes whose counts decide).
    static constexpr double kMostEstimateVariation = 0.45;
    void estimateFans(const glm::dvec3* points, int n, double nodeError, FansEstimate* out) const;
    // sideBeyond at n <= kFanPoints points at once (the centres of a cube's children): their
    // estimates share one pass over the fan tree, and its fans are measured at every point by
    // the fan kernel. `first`, where given, is the points' first estimate (estimateFans to
    // kSideNodeErrors[0]), made already.
    static constexpr double kSideNodeErrors[] = {1e-3, 1e-4};
    void sidesBeyond(const glm::dvec3* points, const int* ahead, const double* margins, int n, int* sides,
                     const FansEstimate* first = nullptr) const;
    // Whether the ball (centre, reach) misses every fan (then the fans' winding number is
    // harmonic over it, whatever of the mesh it holds, and windingVariation bounds its change).
    bool fansMiss(const glm::dvec3& centre, double reach) const { return clearOfFans(centre, reach, true); }
    // A bound on how far the mesh's winding number w moves over the ball (centre, reach), which
    // no mesh triangle meets. Its gradient there is minus the fans' (their steps across the fans
    // aside, which the counts ahead cancel): the Biot-Savart field of the caps' loops, whose chords
    // and rungs cancel. So the caps near the ball have their field summed at the centre (where the
    // cancelling happens) and its change over the ball bounded by its curvature; the others are
    // bounded by their fans' area (a surface of area A at distance d moves its winding number by
    // at most 2 A / (4π d³) per unit of distance). Infinite where the ball reaches a cap's edge,
    // or where the bound's parts that only grow on the walk pass `limit` (the walk stops there).
    double windingVariation(const glm::dvec3& centre, double reach, double limit = std::numeric_limits<double>::infinity()) const;

private:
    struct Node {
        glm::dvec3 lo, hi;
        double area;         // the sum of |weight| * area below
        std::uint32_t first; // inner: first child (the second is first + 1); leaf: the cap
        bool leaf;
        std::uint32_t fans = 1; // the caps below
        // The fans below as a near-flat sheet (see bound()): a unit normal n, the box's centre c,
        // and area-weighted means of each triangle's farthest vertex from the plane (c, n) and of
        // the distance of its normal from ±n. tilt 2 (the most it can be) when no plane fits.
        glm::dvec3 normal{0.0};
        double thickness = 0, tilt = 2;
    };
    // The fans below a node as one multipole (see multipoleEstimate()), apart from the nodes that
    // every walk reads (multipoles_[i] is nodes_[i]'s); the bounds' moments and the lower terms
    // first, which most walks' nodes need alone.
    struct Multipole {
        // Σ |weight| area |c - centroid| and Σ |weight| area max |corner - centroid|^k (k = 2, 3,
        // 4) over their triangles (c each one's centroid), for the bounds;
        double firstMoment = 0, secondMoment = 0, thirdMoment = 0, fourthMoment = 0;
        // their vector area (each triangle's area times its unit normal n, times its weight) at
        // their area-weighted centroid;
        glm::dvec3 vectorArea{0.0}, centroid{0.0};
        // their quadrupole: the traceless part of the symmetric part of
        // Σ weight area n (c - centroid)ᵀ, as xx, yy, zz, xy, xz, yz;
        double quadrupole[6] = {};
        // their octupole: the traceless part of the symmetric part of Σ weight area n ⊗ M over
        // their triangles, M = the mean of (y - centroid)(y - centroid)ᵀ over the triangle, as
        // xxx, yyy, zzz, xxy, xxz, xyy, yyz, xzz, yzz, xyz;
        double octupole[10] = {};
        // their hexadecapole: the same of Σ weight area n ⊗ Q, Q the mean of (y - centroid)^⊗3
        // over the triangle, as xxxx, yyyy, zzzz, xxxy, xxxz, xyyy, yyyz, xzzz, yzzz, xxyy,
        // xxzz, yyzz, xxyz, xyyz, xyzz.
        double hexadecapole[15] = {};
    };
    struct Search; // one point's lazy walk of the tree (winding_sign.cpp)
    // The walk from the root at p, until |w| is farther than `margin` plus the bounds of the rest
    // from 1/2 or every fan is measured: w as measured, and whether it is still in doubt.
    // `dipoles`: waiting nodes count as their multipoles where that bounds them more tightly. The walk
    // stops in doubt once it has measured `budget` fans.
    std::pair<double, bool> walk(const glm::dvec3& p, int ahead, double margin, std::size_t* evaluations, bool dipoles = false,
                                 std::size_t budget = std::numeric_limits<std::size_t>::max()) const;
    // The tree over caps order[begin, end): fans whose sizes (their boxes' diagonals) differ by more
    // than kSizeRatio, the largest at least kSizeSpan of the node's diagonal, are split by size
    // first; the others at the median of their centres. A size split halves the log of the sizes'
    // range, so it adds at most about 10 levels to the median splits' log2(caps) (the walks' stacks).
    void build(std::uint32_t index, std::vector<std::uint32_t>& order, std::size_t begin, std::size_t end);
    // An inner node's multipole (quadrupole, octupole, hexadecapole) from its children's.
    void shiftMultipoles(std::uint32_t index);
    static constexpr double kSizeRatio = 8.0, kSizeSpan = 0.5;
    static double capSize(const Cap& cap) { return glm::length(cap.hi - cap.lo); }
    // The cut's far sums (farValue, farGradient, farSum) and its curvature (the near fans' and the
    // far dipoles', with the chords' terms that do not cancel), from its nodes.
    void sumFar(Cut& out) const;
    // Whether expandFar opens the far node: bounded by its area or as its multipole (not a fan
    // expanded already), kFarReaches reaches or more away.
    bool toExpand(const Cut& cut, const Pending& far) const;
    // A node's bound over the cut's ball, d from it: as its multipole expanded at the centre
    // (Cut::dipoles) where that is tighter, tried where its plain bound exceeds `small`.
    Pending boundOverBall(Cut& out, std::uint32_t index, double d, double small) const;
    // The far dipole of a fan whose expansion at the ball's centre is `terms`, for a fan bounded
    // by `bound` and `surface` (surfaceCurvature) there: its bound over the ball (the Pending's),
    // or no dipole where that is not below `limit`.
    bool expandedFan(Cut& out, const FanTerms& terms, bool ok, double surface, double limit, Pending& fan) const;
    // Whether no fan's box (byTriangles: no fan's triangle) comes within `reach` of p: one walk
    // for noFanWithin and fansMiss.
    bool clearOfFans(const glm::dvec3& p, double reach, bool byTriangles) const;
    // terms[f] = fanTerms of the cap of leaf leaves[f] over the ball, ok[f] its answer, f < n <=
    // kFanPoints: by the fan-terms kernel (fans::activeTerms); without `angles`, by the fields
    // kernel (fans::activeFields: no winding number).
    void fanTermsOf(const std::uint32_t* leaves, int n, const glm::dvec3& centre, double reach, FanTerms* terms, bool* ok,
                    bool angles = true) const;
    // f(a, b, c, cross, |cross|, weight) for each fan triangle (loop[i + 1], loop[i], centre) of the
    // caps order[begin, end), as fanSolidAngle measures them, cross = (b - a) x (c - a); zero-area
    // triangles are left out (they see no solid angle and weigh nothing).
    template <class F>
    void forEachFanTriangle(const std::vector<std::uint32_t>& order, std::size_t begin, std::size_t end, const F& f) const {
        for (std::size_t n = begin; n < end; ++n) {
            const Cap& cap = caps_[order[n]];
            for (std::size_t i = 0; i < cap.loop.size(); ++i) {
                const glm::dvec3& a = cap.loop[(i + 1) % cap.loop.size()];
                const glm::dvec3& b = cap.loop[i];
                const glm::dvec3 cross = glm::cross(b - a, cap.centre - a);
                const double length = glm::length(cross);
                if (length > 0.0) f(a, b, cap.centre, cross, length, cap.weight);
            }
        }
    }
    // Sets node's plane (normal, thickness, tilt) from the fans order[begin, end).
    void flatten(Node& node, const std::vector<std::uint32_t>& order, std::size_t begin, std::size_t end) const;
    // The winding-number bound of a node for every point within `reach` of p (infinite when the
    // ball touches the node's box). A triangle of area A, unit normal m, at distance r >= d from a
    // point x sees it under a solid angle of at most A |m.(x - y)| / r³ (y its point nearest x,
    // m.(x - y) the same over the whole plane), and |m.(x - y)| is at most x's height over the
    // node's plane plus the triangle's farthest vertex from it plus |m ∓ n| r: seen from near the
    // plane of a flat fan (a hole in a flat base, a sheet's border), far less than A / d². Inline:
    // the walks call it for every node they look at.
    // The distance from p to the box [lo, hi] (0 inside).
    static double boxDistance(const glm::dvec3& lo, const glm::dvec3& hi, const glm::dvec3& p) {
        return glm::length(glm::max(glm::max(lo - p, p - hi), glm::dvec3(0.0)));
    }
    static double bound(const Node& node, const glm::dvec3& p, double reach) { return bound(node, p, reach, ballDistance(node, p, reach)); }
    // The ball's distance from the node's box (<= 0 where it touches it), and bound() given it.
    static double ballDistance(const Node& node, const glm::dvec3& p, double reach) { return boxDistance(node.lo, node.hi, p) - reach; }
    static double bound(const Node& node, const glm::dvec3& p, double reach, double d) {
        if (!(d > 0.0)) return std::numeric_limits<double>::infinity();
        const double height = std::fabs(glm::dot(node.normal, p - 0.5 * (node.lo + node.hi))) + reach;
        const double flat = (height + node.thickness) / d + node.tilt;
        return node.area / (4.0 * M_PI * d * d) * std::min(1.0, flat);
    }

    // The node's winding number at p as a multipole: its dipole, quadrupole, octupole and
    // hexadecapole (Barill et al. 2018's expansion, two orders further), and a bound on that
    // estimate's error. Each fan triangle's solid angle is the integral of n.K(y - p) over it,
    // K(v) = v / |v|³ = -∇(1/|v|); expanded in y about the centroid, the first term is the
    // dipole's, the second the quadrupole's (the second derivatives of 1/r against each
    // triangle's area times n (c - centroid)ᵀ), the third the octupole's (the third derivatives
    // against its area times n ⊗ M, halved), the fourth the hexadecapole's (the fourth against n ⊗
    // Q, over 6): exact, n being constant over a triangle. The derivatives of 1/r are symmetric and
    // traceless, so only the tensors' symmetric, traceless parts count. The rest is at most
    // 1/24 |∇⁴K| |y - centroid|⁴, ∇⁴K being fifth derivatives of 1/r, at most 5! / r⁶ in any unit
    // directions (the k-th derivative of 1/r along one direction is k! P_k(cos) / r^(k+1), and a
    // symmetric multilinear form on a Euclidean space is no larger over several directions than
    // over one, Banach 1938), with y and the centroid both in the node's box (d from p):
    // 5 fourthMoment / (4π d⁶) in winding numbers, where the plain bound has area / (4π d²). It
    // shrinks as 1/d⁶. Infinite error where p touches the box.
    // d: the ball's distance from the node's box (ballDistance). Its terms are left out (error
    // infinite) where its bound over the ball would not undercut `limit`.
    static BallDipole multipoleOverBall(const Node& node, const Multipole& m, const glm::dvec3& centre, double reach, double d, double limit);
    // Where the multipole is cut off at d: after the quadrupole (order 2), the octupole (3) or the
    // hexadecapole (4), whichever rest is bounded the least there (3 secondMoment / (4π d⁴),
    // 4 thirdMoment / (4π d⁵), 5 fourthMoment / (4π d⁶): beside the node, nearer than its spread,
    // the lower orders' bounds are the tighter).
    struct Truncation {
        int order;
        double error; // without rounding
    };
    // The three rests' bounds, errors[order - 2] (inverse = 1 / d: the walks bound many nodes, and
    // one division costs what a dozen products do).
    static void truncationErrors(const Multipole& m, double inverse, double* errors) {
        const double inverse2 = inverse * inverse, k = (1.0 + 1e-9) / (4.0 * M_PI) * inverse2 * inverse2;
        errors[0] = 3.0 * m.secondMoment * k, errors[1] = 4.0 * m.thirdMoment * inverse * k, errors[2] = 5.0 * m.fourthMoment * inverse2 * k;
    }
    static Truncation truncation(const Multipole& m, double inverse) {
        double errors[3];
        truncationErrors(m, inverse, errors);
        Truncation best{2, errors[0]};
        if (errors[1] < best.error) best = {3, errors[1]};
        if (errors[2] < best.error) best = {4, errors[2]};
        return best;
    }
    // The least of those: where it is no smaller than the plain bound, the multipole cannot bound
    // the node more tightly (most nodes of a cut, too near for their size).
    static double multipoleErrorFloor(const Multipole& m, double d) { return truncation(m, 1.0 / d).error; }
    // The terms' bounds at d = 1 / inverse, times d²: what a share of their rounding is taken of.
    static double momentsOver(const Node& node, const Multipole& m, double inverse) {
        return node.area + (m.firstMoment + (m.secondMoment + m.thirdMoment * inverse) * inverse) * inverse;
    }
    // rᵀ S r and S r for the node's quadrupole S.
    static double quadrupoleForm(const Multipole& m, const glm::dvec3& r) {
        const double* q = m.quadrupole;
        return q[0] * r.x * r.x + q[1] * r.y * r.y + q[2] * r.z * r.z + 2.0 * (q[3] * r.x * r.y + q[4] * r.x * r.z + q[5] * r.y * r.z);
    }
    static glm::dvec3 quadrupoleTimes(const Multipole& m, const glm::dvec3& r) {
        const double* q = m.quadrupole;
        return {q[0] * r.x + q[3] * r.y + q[4] * r.z, q[3] * r.x + q[1] * r.y + q[5] * r.z, q[4] * r.x + q[5] * r.y + q[2] * r.z};
    }
    // H(r, r, .) for the node's octupole H (H(r, r, r) is its dot product with r).
    static glm::dvec3 octupoleTimes(const Multipole& m, const glm::dvec3& r) {
        const double* o = m.octupole;
        const double xx = r.x * r.x, yy = r.y * r.y, zz = r.z * r.z, xy = 2.0 * r.x * r.y, xz = 2.0 * r.x * r.z, yz = 2.0 * r.y * r.z;
        return {o[0] * xx + o[3] * xy + o[4] * xz + o[5] * yy + o[9] * yz + o[7] * zz,
                o[3] * xx + o[5] * xy + o[9] * xz + o[1] * yy + o[6] * yz + o[8] * zz,
                o[4] * xx + o[9] * xy + o[7] * xz + o[6] * yy + o[8] * yz + o[2] * zz};
    }
    // G(r, r, r, .) for the node's hexadecapole G (G(r, r, r, r) is its dot product with r).
    static glm::dvec3 hexadecapoleTimes(const Multipole& m, const glm::dvec3& r) {
        const double* g = m.hexadecapole;
        const double x = r.x, y = r.y, z = r.z, xx = x * x, yy = y * y, zz = z * z;
        // Each component times the multinomial count of its index orders among the first three.
        return {g[0] * xx * x + 3.0 * (g[3] * xx * y + g[4] * xx * z + g[9] * x * yy + g[10] * x * zz) + g[5] * yy * y + g[7] * zz * z +
                    3.0 * (g[13] * yy * z + g[14] * y * zz) + 6.0 * g[12] * x * y * z,
                g[1] * yy * y + 3.0 * (g[5] * yy * x + g[6] * yy * z + g[9] * xx * y + g[11] * y * zz) + g[3] * xx * x + g[8] * zz * z +
                    3.0 * (g[12] * xx * z + g[14] * x * zz) + 6.0 * g[13] * x * y * z,
                g[2] * zz * z + 3.0 * (g[7] * zz * x + g[8] * zz * y + g[10] * xx * z + g[11] * yy * z) + g[4] * xx * x + g[6] * yy * y +
                    3.0 * (g[12] * xx * y + g[13] * x * yy) + 6.0 * g[14] * x * y * z};
    }
    // The multipole at p, cut off after `order` (a Truncation's). With r = centroid - p, the
    // quadrupole's term is -S : ∇²(1/r) = -3 rᵀSr / |r|⁵, the octupole's -1/2 H : ∇³(1/r) =
    // 15/2 H(r, r, r) / |r|⁷ and the hexadecapole's -1/6 G : ∇⁴(1/r) = -35/2 G(r, r, r, r) / |r|⁹
    // (S, H, G traceless).
    static double multipoleEstimate(const Multipole& m, const glm::dvec3& p, int order) {
        const glm::dvec3 r = m.centroid - p;
        const double r2 = glm::dot(r, r), inverse = 1.0 / (r2 * std::sqrt(r2));
        double higher = 0.0;
        if (order >= 3) higher += 7.5 * glm::dot(octupoleTimes(m, r), r) / (r2 * r2);
        if (order >= 4) higher -= 17.5 * glm::dot(hexadecapoleTimes(m, r), r) / (r2 * r2 * r2);
        return (glm::dot(m.vectorArea, r) - 3.0 * quadrupoleForm(m, r) / r2 + higher) * inverse / (4.0 * M_PI);
    }
    // The truncation at d, its error with its rounding (a few ulps of each term, far below a 1e-12
    // share of each term's bound); infinite where p touches the box.
    static Truncation multipoleError(const Node& node, const Multipole& m, double d) {
        if (!(d > 0.0)) return {2, std::numeric_limits<double>::infinity()};
        const double inverse = 1.0 / d;
        Truncation t = truncation(m, inverse);
        t.error += 1e-12 / (4.0 * M_PI) * momentsOver(node, m, inverse) * inverse * inverse;
        return t;
    }

    std::vector<Cap> caps_;
    std::uint32_t chords_ = 1; // chord ids run from 1 (Cap::chord)
    std::vector<Node> nodes_;
    std::vector<Multipole> multipoles_;
};

// The cap's first-order expansion at the centre of the ball (centre, reach), in one pass over its
// loop (each vertex's distance shared): its winding number there (fanWinding's, off the fan), its
// gradient (the Biot-Savart field of its loop, reversed as the fan's triangles run, over 4π and
// times its weight: segment a -> b gives (e x ra) / |e x ra|² (e.rb / |rb| - e.ra / |ra|)), a
// bound on that gradient's rounding per unit of distance (each edge's 8 eps / h, h the centre's
// distance from its line, plus a relative 8 eps of the edge's field, at most length / r², r the
// centre's distance from the edge), and a bound on |Hessian| / 2 over the ball (each edge's field
// r / |r|³ has a Jacobian of norm 2 / |r|³, so |H| <= Σ 2 length / d³ over 4π, d the ball's
// distance from the edge; surfaceCurvature's is tighter far from the fan). That bound's terms of
// the chords (Cap::chord) apart: expanded together with the cap on a chord's other side, a chord's
// terms cancel (WindingCaps::ChordTerm). False where the ball reaches an edge or the centre is
// within rounding of the fan.
// fans::activeTerms() computes them for up to kFanPoints caps at once (core/sign/fan_kernel.hpp).
struct FanTerms {
    double value = 0, slack = 0;
    double curvature = 0; // of the edges of the mesh's boundary
    glm::dvec3 gradient{0.0};
    std::array<WindingCaps::ChordTerm, Cap::kMaxEdges> chords{};
    std::size_t chordCount = 0;
    // The bound with every chord's terms.
    double allCurvature() const {
        double sum = curvature;
        for (std::size_t c = 0; c < chordCount; ++c) sum += chords[c].curvature;
        return sum;
    }
};
bool fanTerms(const Cap& cap, const glm::dvec3& centre, double reach, FanTerms& out);

// `ahead` for one point p (local coordinates), from the tree: what insideByWinding's row scan
// finds for a sample at p (copies of a triangle and caps counted with their weight).
int crossingsAhead(const Mesh& mesh, const Bvh& tree, const WindingCaps& caps, const glm::dvec3& p);
// The same count found through the wide tree built from `tree` (its 8-wide nodes: fewer steps).
// With `fansClose` (fansCloseMesh), on the row's side nearer the mesh's bounds: minus the crossings
// behind p, where fewer nodes lie (the same integer: see fansCloseMesh).
int crossingsAhead(const Mesh& mesh, const WideBvh& wide, const Bvh& tree, const WindingCaps& caps, const glm::dvec3& p,
                   bool fansClose = false);
// Whether the fans close the mesh exactly: the boundary of its triangles (each set of copies once,
// with its number as weight, as the counts weigh them) is, edge for edge and way for way, its
// boundary loops, which WindingCaps closes exactly. Then the mesh and the fans form a cycle, which
// every line crosses as often one way as the other under the counts' predicates (each edge's tie
// is broken one way for both its triangles), so the crossings behind a point are minus those
// ahead. Linear in the triangles, plus a sort of their edges.
bool fansCloseMesh(const MeshTopology& topology);

// What the winding sign did, for tests and benchmarks.
struct WindingStats {
    std::size_t caps = 0;           // fans closing the boundary (equal loops share one, long ones are split)
    // Fan measurements over all samples: a fan's solid angle at one point, or at up to four at once
    // (one vector of the fan kernel).
    std::size_t fanEvaluations = 0;
    std::size_t exactFanSamples = 0; // samples decided by a brick's expansion with its exact fans measured at each
    std::size_t carriedSamples = 0; // samples measured again by a cut carried on (each time counted)
    std::size_t farExpansions = 0;  // cuts whose far fans were expanded for the samples they left in doubt
};

// The generalized winding number w (Jacobson et al. 2013), inside where |w| > 1/2, computed exactly.
// The mesh is closed with small fans over its boundary loops; the closed surface's winding number
// is an integer, counted for whole rows at once from the signed crossings of each row's line
// (robust 2D point-in-triangle tests in double with symbolic tie-breaking, so shared edges count
// once; copies of a triangle count once with their number as weight), scanned in parallel by bands
// of z planes. The fans' own winding number is subtracted wherever it could move w across ±1/2,
// by bricks of 8³ samples, coarse to fine: a brick that no fan can reach is decided by the counts
// alone, a brick clear of its near fans by their first-order expansion at its centre (within
// bounds), the samples left by measuring the near fans (the far ones expanded) and
// WindingCaps::insideNear. So signs are those of the exact w (those
// of WindingCaps::inside, bit for bit), and a sample pays only for the fans near it. Robust to
// holes, self-intersections, overlapping shells and flipped parts: by |w|, a closed part is solid
// whichever way its faces point (w = -1 inside a part modelled inside out), a cavity bounded by a
// reversed inner shell stays empty (w = 0 there), and the mesh with every face flipped has the
// same signs.
std::vector<std::uint8_t> insideByWinding(const Mesh& mesh, const MeshTopology& topology, const Grid& grid,
                                          const RunControl& control, WindingStats* stats = nullptr);
// The same signs applied in place: negates field[index] of every inside sample (no side array).
void signByWinding(const Mesh& mesh, const MeshTopology& topology, const Grid& grid, float* field, const RunControl& control,
                   WindingStats* stats = nullptr);

// A narrow-band bake's sides (band_bake.cpp), the same as the dense bake's winding sign gives.
struct BandSides {
    float background = 0;
    // In: the bricks in the band (ordered by z, y, x) and their 512 samples each (unsigned
    // distances, or signed already when signBricks is false); out: their samples negated where
    // inside, those beyond the band (|value| >= background) set to ±background, and the fan bricks
    // whose samples are on both sides added (±background).
    std::vector<glm::ivec3> bricks;
    std::vector<float> values;
    bool signBricks = true;
    // Bricks out of the band that a fan may reach (ordered by z, y, x): decided sample by sample.
    std::vector<glm::ivec3> fanBricks;
    // Bricks of `bricks` in a ball that no fan meets and where the fans' winding number stays within
    // 0.45 of 0 (ordered by z, y, x): their samples are sided by their counts alone.
    std::vector<glm::ivec3> clearBricks;
    // Bricks out of the band near the fans whose side is known already (1 inside, 0 outside), ordered by z, y, x.
    std::vector<std::pair<glm::ivec3, std::uint8_t>> sidedBricks;
    // Out: SparseField::insideBoxes.
    std::vector<std::array<int, 6>> insideBoxes;
};
// Whether brick a comes before b in BandSides' lists (ordered by z, y, x).
inline bool brickBefore(const glm::ivec3& a, const glm::ivec3& b) { return std::tie(a.z, a.y, a.x) < std::tie(b.z, b.y, b.x); }
// Every other brick must be out of the band (the surface nowhere in its samples' box) and clear of
// the fans (WindingCaps::farFromEveryFan over a ball around its samples, or in a ball that no fan
// meets and where the fans' winding number stays within 0.45 of 0): its side is its first
// sample's count of crossings ahead. The rows' crossings are counted by layers of 8 planes, in
// parallel, each layer's once.
void bandWindingSigns(const Mesh& mesh, const MeshTopology& topology, const WindingCaps& caps, const Grid& grid, BandSides& band,
                      const RunControl& control);

// The generalized winding number at p, summed over every triangle in double (the reference).
double windingNumber(const Mesh& mesh, const glm::dvec3& p);

} // namespace sdfgen
