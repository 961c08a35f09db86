// The sign methods: generalized winding number, angle-weighted pseudonormal, the report's ray vote.
#include "core/exact.hpp"
#include "core/methods.hpp"
#include "core/parallel.hpp"
#include "core/ray_generator.hpp"
#include "core/sign.hpp"
#include "sdfgen/error.hpp"

#include <cstdlib>

namespace sdfgen {

namespace {

// The winding sign with the compute device counting the closed surface's crossings (the mesh and
// a fan over each hole, as insideByWinding closes it); the fans' own part is subtracted here.
std::vector<std::uint8_t> windingSignOnDevice(const BakeContext& context, const RunControl& control) {
    const Mesh& mesh = context.mesh;
    const Grid& grid = context.grid;
    const WindingCaps caps(context.topology());
    std::vector<glm::dvec3> closed;
    closed.reserve(3 * mesh.triangleCount());
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        closed.insert(closed.end(), {glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2))});
    }
    // A cap shared by equal loops counts once per loop, as each loop's own fan would.
    for (const Cap& cap : caps.caps()) {
        for (int copy = 0; copy < std::abs(cap.weight); ++copy) {
            for (std::size_t i = 0; i < cap.loop.size(); ++i) {
                const glm::dvec3& a = cap.loop[(i + 1) % cap.loop.size()];
                const glm::dvec3& b = cap.loop[i];
                if (cap.weight > 0) closed.insert(closed.end(), {a, b, cap.centre});
                else closed.insert(closed.end(), {b, a, cap.centre});
            }
        }
    }
    const std::vector<std::int32_t> ahead = context.device->windingNumbers(mesh, closed, grid, control.phase(0.0, 0.8));
    const int orientation = context.flipped ? -1 : 1;
    std::vector<std::uint8_t> inside(grid.sampleCount());
    const std::size_t rows = std::size_t(grid.dims.y) * std::size_t(grid.dims.z);
    parallelFor(rows, control.phase(0.8, 1.0), [&](std::size_t row) {
        const int j = int(row % std::size_t(grid.dims.y)), k = int(row / std::size_t(grid.dims.y));
        for (int i = 0; i < grid.dims.x; ++i) {
            const std::size_t index = grid.index(i, j, k);
            inside[index] = caps.inside(localPosition(mesh, grid, i, j, k), ahead[index], orientation);
        }
    });
    return inside;
}

void windingSign(const BakeContext& context, DistancePass& pass, const RunControl& control) {
    if (context.device) return negateInside(pass.distance, windingSignOnDevice(context, control));
    signByWinding(context.mesh, context.topology(), context.grid, pass.distance.data(), control, context.flipped);
}

// For passes that did not sign as they measured: from the compute device's nearest triangles, or,
// for methods that find none (rays), one more closest-feature search.
void pseudonormalSign(const BakeContext& context, DistancePass& pass, const RunControl& control) {
    if (pass.nearestTriangle.empty()) {
        // Every pseudonormal of a flipped mesh is negated: inside and outside swap.
        return negateInside(pass.distance, insideByClosestFeature(context.mesh, context.wide, context.grid, context.topology(),
                                                                  context.flipped, control));
    }
    std::vector<std::uint8_t> inside = insideByPseudonormal(context.mesh, context.topology(), context.grid, pass.nearestTriangle, control);
    std::vector<std::uint32_t>().swap(pass.nearestTriangle);
    if (context.flipped) {
        for (std::uint8_t& in : inside) in = !in;
    }
    negateInside(pass.distance, inside);
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
        {SignMethod::Winding, "winding", "generalized winding number > 1/2, computed exactly", windingSign},
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
