// The sign methods: generalized winding number, angle-weighted pseudonormal, the report's ray vote.
#include "core/method/methods.hpp"
#include "core/runtime/parallel.hpp"
#include "core/accel/ray_generator.hpp"
#include "core/mesh/geometry.hpp"
#include "core/mesh/sample_positions.hpp"
#include "core/sign/winding_sign.hpp"
#include "sdfgen/error.hpp"

#include <glm/geometric.hpp>
#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>
#include <vector>

namespace sdfgen {

namespace {

// The winding sign with the compute device counting the closed surface's crossings (the mesh, each
// set of copies of a triangle once with its number, and the fans over the holes with their
// weights, as insideByWinding closes it) and subtracting the fans' own part where their bounds
// leave doubt; the samples whose |w| its float cannot tell from 1/2 as the CPU's double would are
// decided here, by WindingCaps::inside (so the signs are the CPU's). Negates `distance` in place
// where inside.
void windingSignOnDevice(const BakeContext& context, DistancePass& pass, const RunControl& control) {
    std::vector<float>& distance = pass.distance;
    const Mesh& mesh = context.mesh;
    const Grid& grid = context.grid;
    const MeshTopology& topology = context.topology();
    const WindingCaps caps(topology);
    std::vector<glm::dvec3> closed;
    std::vector<std::int32_t> weights;
    closed.reserve(3 * mesh.triangleCount());
    weights.reserve(mesh.triangleCount());
    for (std::uint32_t t = 0; t < mesh.triangleCount(); ++t) {
        if (topology.copies(t) == 0) continue; // counted with the first copy
        closed.insert(closed.end(), {glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2))});
        weights.push_back(std::int32_t(topology.copies(t)));
    }
    for (const Cap& cap : caps.caps()) {
        for (std::size_t i = 0; i < cap.loop.size(); ++i) {
            closed.insert(closed.end(), {cap.loop[(i + 1) % cap.loop.size()], cap.loop[i], cap.centre});
            weights.push_back(cap.weight);
        }
    }
    const WindingFans fans = caps.flattened();
    std::vector<std::uint8_t> sides;
    const std::vector<std::int32_t> ahead =
        context.device->windingNumbers(mesh, closed, weights, caps.empty() ? nullptr : &fans, grid, control.phase(0.0, 0.9), sides);
    const std::size_t rows = std::size_t(grid.dims.y) * std::size_t(grid.dims.z);
    parallelFor(rows, control.phase(0.9, 1.0), [&](std::size_t row) {
        const int j = int(row % std::size_t(grid.dims.y)), k = int(row / std::size_t(grid.dims.y));
        for (int i = 0; i < grid.dims.x; ++i) {
            const std::size_t index = grid.index(i, j, k);
            bool inside;
            if (caps.empty()) inside = ahead[index] != 0;
            else if (sides[index] != 2) inside = sides[index];
            else inside = caps.inside(localPosition(mesh, grid, i, j, k), ahead[index]);
            if (inside) distance[index] = -distance[index];
        }
    });
}

void windingSign(const BakeContext& context, DistancePass& pass, const RunControl& control) {
    signByWinding(context.mesh, context.topology(), context.grid, pass.distance.data(), control);
}

// A point's side by its crossings ahead and the fans over the holes, as the dense grid's samples.
class WindingPointSide final : public PointSide {
public:
    explicit WindingPointSide(const PointContext& context)
        : mesh_(context.mesh), tree_(context.tree), wide_(context.wide()), caps_(context.topology()),
          fansClose_(fansCloseMesh(context.topology())) {}
    // The count ahead is the winding number of the mesh closed by its fans, the same integer
    // throughout a ball that neither the mesh nor a fan reaches: a point within the last point's
    // ball (its distance to the nearest triangle, less that search's rounding, and clear of every
    // fan's box) takes the last count instead of walking its row.
    void inside(const glm::dvec3* points, const NearestPoint* nearest, std::size_t count, bool, std::uint8_t* inside) const override {
        thread_local std::vector<int> ahead;
        ahead.resize(count);
        glm::dvec3 last(0.0);
        double clearance = -1.0; // of the last point's ball; none while negative
        for (std::size_t i = 0; i < count; ++i) {
            const glm::dvec3& p = points[i];
            const double step = glm::length(p - last);
            ahead[i] = i > 0 && step < clearance && caps_.noFanWithin(last, step) ? ahead[i - 1]
                                                                               : crossingsAhead(mesh_, wide_, tree_, caps_, p, fansClose_);
            // The float search's triangle may be a rounding farther than the nearest one (as the band bake allows).
            const double distance = std::sqrt(nearest[i].closest.distanceSquared);
            last = p;
            clearance = distance - 1e-5 * (std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)}) + distance);
        }
        caps_.insideMany(points, ahead.data(), count, inside);
    }

private:
    const Mesh& mesh_;
    const Bvh& tree_;
    const WideBvh& wide_;
    const WindingCaps caps_;
    const bool fansClose_; // the count may run on the row's shorter side (fansCloseMesh)
};

// For passes that did not sign as they measured (rays, brute force): one more closest-feature
// search, the exact distance's, so each side is the one the exact pass signs inline.
void pseudonormalSign(const BakeContext& context, DistancePass& pass, const RunControl& control) {
    const Mesh& mesh = context.mesh;
    const Grid& grid = context.grid;
    const MeshTopology& topology = context.topology();
    if (!context.nearestRows) throw Error("the pseudonormal sign's own pass needs the bake's nearest-triangle rows (BakeContext::nearestRows)");
    context.nearestRows(
        [&](int i, int j, int k, int count, const std::uint32_t* triangles) {
            for (int lane = 0; lane < count; ++lane) {
                const std::uint32_t t = triangles[lane];
                const glm::dvec3 p = localPosition(mesh, grid, i + lane, j, k);
                const ClosestPoint closest =
                    closestPointOnTriangle(p, glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2)));
                // Every pseudonormal of a flipped mesh is negated: inside and outside swap.
                if ((glm::dot(p - closest.point, topology.pseudonormal(t, closest.feature)) < 0.0) != context.flipped) {
                    float& value = pass.distance[grid.index(i + lane, j, k)];
                    value = -value;
                }
            }
        },
        control);
}

// A point's side by the pseudonormal of its closest feature, as the exact pass signs a sample.
class PseudonormalPointSide final : public PointSide {
public:
    explicit PseudonormalPointSide(const PointContext& context) : topology_(context.topology()) {}
    void inside(const glm::dvec3* points, const NearestPoint* nearest, std::size_t count, bool flipped, std::uint8_t* inside) const override {
        for (std::size_t i = 0; i < count; ++i) {
            inside[i] = topology_.facesAway(nearest[i].triangle, nearest[i].closest.feature, points[i] - nearest[i].closest.point) != flipped;
        }
    }

private:
    const MeshTopology& topology_;
};

void raySign(const BakeContext& context, DistancePass& pass, const RunControl& control) {
    const Field votes = generateRayField(context.mesh, context.tree, context.grid, context.settings.rays, control);
    for (std::size_t i = 0; i < votes.values.size(); ++i) {
        if (votes.values[i] < 0.0f) pass.distance[i] = -pass.distance[i];
    }
}

// The memory estimates' parts (core/bake/memory_estimate.cpp): the pseudonormal reads the topology, the winding
// sign the topology and its crossings; on a compute device the winding pass holds the closed
// surface's corners twice (72 bytes each), its weights and its triangles' row ranges (16), and per
// sample the crossings ahead (4) and the sides (1).
double windingMemory(const MemoryTerms& terms) { return terms.winding; }
double pseudonormalMemory(const MemoryTerms& terms) { return terms.topology; }
double windingDeviceMemory(const MemoryTerms& terms) { return terms.triangles * (72 + 72 + 4 + 16) + terms.samples * (4 + 1); }

// Why auto chose as it did, for the summary and the panel.
std::string autoReason(const MeshCheck& c) {
    if (c.closedAndClean()) {
        return "pseudonormal: the mesh is closed, manifold, consistently oriented and free of self-intersections";
    }
    std::string problems;
    for (const auto& [count, name] : {std::pair{c.boundaryEdges, "holes"}, {c.nonManifoldEdges, "non-manifold edges"},
                                      {c.inconsistentEdges, "flipped faces"}, {c.nonManifoldVertices, "pinched vertices"},
                                      {c.selfIntersections, "self-intersections"},
                                      {c.misorientedShells, "closed shells facing against their nesting"}}) {
        if (count) problems += std::string(problems.empty() ? "" : ", ") + name;
    }
    return "winding: the mesh has " + problems;
}

// A sign's atPoint: its PointSide made for the mesh.
template <class Side>
std::unique_ptr<PointSide> makePointSide(const PointContext& context) {
    return std::make_unique<Side>(context);
}

SignMethodPlugin autoEntry() {
    SignMethodPlugin sign(SignMethod::Auto, "auto", "pseudonormal when the mesh check proves it right, else winding");
    sign.settles = true;
    sign.settlesForQueries = true;
    sign.band = BandSigning::Sides;
    sign.readsTopology = true;
    return sign;
}

SignMethodPlugin windingEntry() {
    SignMethodPlugin sign(SignMethod::Winding, "winding", "|generalized winding number| > 1/2, computed exactly");
    sign.dense = windingSign;
    sign.band = BandSigning::Sides;
    sign.atPoint = makePointSide<WindingPointSide>;
    sign.onDevice = windingSignOnDevice;
    sign.readsTopology = true;
    sign.memory = windingMemory;
    sign.deviceMemory = windingDeviceMemory;
    return sign;
}

SignMethodPlugin pseudonormalEntry() {
    SignMethodPlugin sign(SignMethod::Pseudonormal, "pseudonormal", "angle-weighted pseudonormal of the closest feature");
    sign.dense = pseudonormalSign;
    // The exact method signs the band's bricks by it as it measures them.
    sign.band = BandSigning::WhereProven;
    sign.atPoint = makePointSide<PseudonormalPointSide>;
    sign.readsWideTree = true;
    sign.readsTopology = true;
    sign.memory = pseudonormalMemory;
    return sign;
}

SignMethodPlugin raysEntry() {
    SignMethodPlugin sign(SignMethod::Rays, "rays", "majority of back-face first hits of the sample's rays");
    sign.dense = raySign;
    sign.castsRays = true;
    return sign;
}

SignMethodPlugin defaultEntry() {
    SignMethodPlugin sign(SignMethod::Default, "default", "the method's own: rays for the rays method, auto otherwise");
    sign.settles = true;
    sign.band = BandSigning::Sides;
    return sign;
}

} // namespace

const std::vector<SignMethodPlugin>& signMethods() {
    // Auto first and default last: the order front ends list them in.
    static const std::vector<SignMethodPlugin> methods = {autoEntry(), windingEntry(), pseudonormalEntry(), raysEntry(),
                                                          defaultEntry()};
    return methods;
}

const SignMethodPlugin& signMethod(SignMethod id) {
    for (const SignMethodPlugin& method : signMethods()) {
        if (method.id == id) return method;
    }
    throw Error("unknown sign method");
}

const char* toString(SignMethod sign) {
    for (const SignMethodPlugin& info : signMethods()) {
        if (info.id == sign) return info.name;
    }
    return "?";
}

std::vector<Choice<SignMethod>> signMethodChoices() {
    std::vector<Choice<SignMethod>> choices;
    for (const SignMethodPlugin& info : signMethods()) choices.push_back({info.id, info.name, info.description});
    return choices;
}

std::vector<Choice<SignMethod>> pointQuerySignChoices() {
    std::vector<Choice<SignMethod>> choices;
    for (const SignMethodPlugin& info : signMethods()) {
        if (info.servesPointQueries()) choices.push_back({info.id, info.name, info.description});
    }
    return choices;
}

SignMethod parseSignMethod(const std::string& name) { return parseChoice(signMethodChoices(), name, "sign method"); }

std::vector<SignMethod> possibleSigns(SignMethod asked, SignMethod whenDefault) {
    const SignMethod sign = asked == SignMethod::Default ? whenDefault : asked;
    if (sign == SignMethod::Auto) return {SignMethod::Pseudonormal, SignMethod::Winding};
    return {sign};
}

SignDecision decideSign(SignMethod asked, SignMethod whenDefault, const std::function<const MeshTopology&()>& topology,
                        const std::function<const MeshCheck&()>& check) {
    SignDecision decision;
    decision.sign = asked == SignMethod::Default ? whenDefault : asked;
    if (decision.sign == SignMethod::Auto) {
        decision.checked = true;
        // Holes, non-manifold or flipped edges rule the pseudonormal out already: the costly
        // search for self-intersections could not change the choice, so it is skipped.
        const MeshCheck& edges = topology().edgeCheck();
        decision.check = edges.closedAndClean() ? check() : edges;
        decision.reason = autoReason(decision.check);
        decision.sign = decision.check.closedAndClean() ? SignMethod::Pseudonormal : SignMethod::Winding;
        if (decision.check.insideOut) {
            decision.flipped = true;
            decision.reason += decision.sign == SignMethod::Pseudonormal
                                   ? "; the mesh is inside out (closed, its faces point inwards), so inside and outside "
                                     "are swapped as if every face were flipped"
                                   : "; the mesh is inside out (closed, its faces point inwards): its winding number "
                                     "is -1 inside, and |w| > 1/2 counts that as inside";
        }
    } else if (decision.sign == SignMethod::Pseudonormal && topology().insideOut()) {
        decision.warnings.push_back("the mesh is inside out (closed, its faces point inwards); sign pseudonormal follows "
                                    "the faces, so inside and outside are swapped; sign auto or winding fixes it");
    }
    return decision;
}

} // namespace sdfgen
