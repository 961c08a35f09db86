// The distance methods: exact nearest triangle, the report's ray sampling, and the reference.
#include "core/exact.hpp"
#include "core/methods.hpp"
#include "core/ray_generator.hpp"
#include "sdfgen/error.hpp"

#include <cmath>

namespace sdfgen {

namespace {

// Straight into the field: signed by the closest feature's pseudonormal when that is the sign,
// unsigned for the winding sign (which negates in place), with no per-sample side arrays.
DistancePass exactDistance(const BakeContext& context, const RunControl& control) {
    if (context.device) {
        // The device measures unsigned distances and the nearest triangles; the sign follows.
        DistancePass pass;
        context.device->nearest(context.mesh, context.grid, control, pass.distance, pass.nearestTriangle);
        return pass;
    }
    DistancePass pass;
    pass.distance.resize(context.grid.sampleCount());
    pass.signedAsAsked = context.sign == SignMethod::Pseudonormal; // as distanceMethods() declares
    computeExactField(context.mesh, context.wide, context.grid, pass.signedAsAsked ? &context.topology() : nullptr, context.flipped,
                      pass.distance.data(), control);
    return pass;
}

DistancePass rayDistance(const BakeContext& context, const RunControl& control) {
    // Signed by the rays' own vote, as distanceMethods() declares; for another sign, unsigned in place.
    DistancePass pass;
    pass.distance = generateRayField(context.mesh, context.tree, context.grid, context.settings.rays, control).values;
    pass.signedAsAsked = context.sign == SignMethod::Rays;
    if (!pass.signedAsAsked) {
        for (float& d : pass.distance) d = std::fabs(d);
    }
    return pass;
}

DistancePass bruteDistance(const BakeContext& context, const RunControl& control) {
    return splitSigned(computeBruteForce(context.mesh, context.grid, control).values);
}

} // namespace

DistancePass splitSigned(std::vector<float> values) {
    DistancePass pass;
    pass.inside.emplace(values.size());
    for (std::size_t i = 0; i < values.size(); ++i) {
        (*pass.inside)[i] = values[i] < 0.0f;
        values[i] = std::fabs(values[i]);
    }
    pass.distance = std::move(values);
    return pass;
}

void negateInside(std::vector<float>& distance, const std::vector<std::uint8_t>& inside) {
    for (std::size_t i = 0; i < inside.size(); ++i) {
        if (inside[i]) distance[i] = -distance[i];
    }
}

const std::vector<DistanceMethodInfo>& distanceMethods() {
    static const std::vector<DistanceMethodInfo> methods = {
        {DistanceMethod::Exact, "exact", "the true distance to the nearest triangle", exactDistance, SignMethod::Auto, false,
         SignMethod::Pseudonormal},
        {DistanceMethod::Rays, "rays", "the original report's ray sampling (an upper bound)", rayDistance, SignMethod::Rays, false,
         SignMethod::Rays},
        {DistanceMethod::Brute, "brute", "every triangle for every sample in double, signed by the exact winding number (the reference)",
         bruteDistance, SignMethod::Winding, true, SignMethod::Default},
    };
    return methods;
}

const DistanceMethodInfo& distanceMethod(DistanceMethod id) {
    for (const DistanceMethodInfo& method : distanceMethods()) {
        if (method.id == id) return method;
    }
    throw Error("unknown distance method");
}

const char* toString(DistanceMethod method) {
    for (const DistanceMethodInfo& info : distanceMethods()) {
        if (info.id == method) return info.name;
    }
    return "?";
}

DistanceMethod parseDistanceMethod(const std::string& name) {
    std::string known;
    for (const DistanceMethodInfo& info : distanceMethods()) {
        if (name == info.name) return info.id;
        known += std::string(known.empty() ? "" : ", ") + info.name;
    }
    throw Error("unknown distance method '" + name + "' (expected " + known + ")");
}

} // namespace sdfgen
