// The sign methods: generalized winding number, angle-weighted pseudonormal, the report's ray vote.
#include "core/exact.hpp"
#include "core/methods.hpp"
#include "core/ray_generator.hpp"
#include "core/sign.hpp"
#include "sdfgen/error.hpp"

namespace sdfgen {

namespace {

std::vector<std::uint8_t> windingSign(const BakeContext& context, DistancePass&, const RunControl& control) {
    return insideByWinding(context.mesh, context.topology(), context.grid, control, context.flipped);
}

// For distance methods that do not sign as they measure (rays): one more closest-feature search.
std::vector<std::uint8_t> pseudonormalSign(const BakeContext& context, DistancePass&, const RunControl& control) {
    // Every pseudonormal of a flipped mesh is negated: inside and outside swap.
    return insideByClosestFeature(context.mesh, context.wide, context.grid, context.topology(), context.flipped, control);
}

std::vector<std::uint8_t> raySign(const BakeContext& context, DistancePass& pass, const RunControl& control) {
    if (pass.inside) return std::move(*pass.inside); // the ray method's own vote
    return std::move(*splitSigned(generateRayField(context.mesh, context.tree, context.grid, context.settings.rays, control).values).inside);
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
