// The sign methods: generalized winding number, angle-weighted pseudonormal, the report's ray vote.
#include "core/distance/exact.hpp"
#include "core/bake/methods.hpp"
#include "core/runtime/parallel.hpp"
#include "core/distance/ray_generator.hpp"
#include "core/distance/sample_positions.hpp"
#include "core/sign/winding_sign.hpp"
#include "sdfgen/error.hpp"

namespace sdfgen {

namespace {

// The winding sign with the compute device counting the closed surface's crossings (the mesh, each
// set of copies of a triangle once with its number, and the fans over the holes with their
// weights, as insideByWinding closes it) and subtracting the fans' own part where their bounds
// leave doubt; the samples whose |w| its float cannot tell from 1/2 as the CPU's double would are
// decided here, by WindingCaps::inside (so the signs are the CPU's). Negates `distance` in place
// where inside.
void windingSignOnDevice(const BakeContext& context, std::vector<float>& distance, const RunControl& control) {
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
    if (context.device) return windingSignOnDevice(context, pass.distance, control);
    signByWinding(context.mesh, context.topology(), context.grid, pass.distance.data(), control);
}

// For passes that did not sign as they measured (rays): one more closest-feature search.
void pseudonormalSign(const BakeContext& context, DistancePass& pass, const RunControl& control) {
    // Every pseudonormal of a flipped mesh is negated: inside and outside swap.
    negateInside(pass.distance, insideByClosestFeature(context.mesh, context.wide(), context.grid, context.topology(), context.flipped, control));
}

void raySign(const BakeContext& context, DistancePass& pass, const RunControl& control) {
    const Field votes = generateRayField(context.mesh, context.tree, context.grid, context.settings.rays, control);
    for (std::size_t i = 0; i < votes.values.size(); ++i) {
        if (votes.values[i] < 0.0f) pass.distance[i] = -pass.distance[i];
    }
}

} // namespace

const std::vector<SignMethodInfo>& signMethods() {
    static const std::vector<SignMethodInfo> methods = {
        {SignMethod::Winding, "winding", "|generalized winding number| > 1/2, computed exactly", windingSign},
        {SignMethod::Pseudonormal, "pseudonormal", "angle-weighted pseudonormal of the closest feature", pseudonormalSign},
        {SignMethod::Rays, "rays", "majority of back-face first hits of the sample's rays", raySign},
    };
    return methods;
}

const SignMethodInfo& signMethod(SignMethod id) {
    for (const SignMethodInfo& method : signMethods()) {
        if (method.id == id) return method;
    }
    throw Error(std::string("sign method '") + toString(id) + "' is decided by bake, not run");
}

const char* toString(SignMethod sign) {
    if (sign == SignMethod::Default) return "default";
    if (sign == SignMethod::Auto) return "auto";
    for (const SignMethodInfo& info : signMethods()) {
        if (info.id == sign) return info.name;
    }
    return "?";
}

SignMethod parseSignMethod(const std::string& name) {
    if (name == "auto") return SignMethod::Auto;
    std::string known = "auto";
    for (const SignMethodInfo& info : signMethods()) {
        if (name == info.name) return info.id;
        known += std::string(", ") + info.name;
    }
    throw Error("unknown sign method '" + name + "' (expected " + known + ")");
}

} // namespace sdfgen
