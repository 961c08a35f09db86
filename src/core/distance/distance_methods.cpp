// The distance methods: exact nearest triangle, the report's ray sampling, and the reference.
#include "core/distance/exact.hpp"
#include "core/method/methods.hpp"
#include "core/runtime/memory.hpp"
#include "core/runtime/parallel.hpp"
#include "core/accel/ray_generator.hpp"
#include "core/mesh/sample_positions.hpp"
#include "sdfgen/device.hpp"
#include "sdfgen/error.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace sdfgen {

namespace {

// The device measures, signed by the pseudonormal when that is the sign; the samples it leaves
// undecided (NaN: near-ties it cannot settle as the CPU would) are the CPU's own.
DistancePass exactDistanceOnDevice(const BakeContext& context, const RunControl& control) {
    DistancePass pass;
    if (context.sign != SignMethod::Pseudonormal) {
        context.device->nearest(context.mesh, context.grid, nullptr, control, pass.distance);
        return pass;
    }
    const MeshTopology& topology = context.topology();
    PseudonormalSign sign;
    sign.flipped = context.flipped;
    sign.normals.reserve(7 * context.mesh.triangleCount());
    for (std::uint32_t t = 0; t < context.mesh.triangleCount(); ++t) {
        for (TriangleFeature feature : {TriangleFeature::Face, TriangleFeature::EdgeAB, TriangleFeature::EdgeBC, TriangleFeature::EdgeCA,
                                        TriangleFeature::VertexA, TriangleFeature::VertexB, TriangleFeature::VertexC}) {
            sign.normals.push_back(topology.pseudonormal(t, feature));
        }
    }
    context.device->nearest(context.mesh, context.grid, &sign, control.phase(0.0, 0.95), pass.distance);
    const Grid& grid = context.grid;
    const WideBvh& wide = context.wide();
    const std::size_t rows = std::size_t(grid.dims.y) * std::size_t(grid.dims.z);
    parallelFor(rows, control.phase(0.95, 1.0), [&](std::size_t row) {
        const int j = int(row % std::size_t(grid.dims.y)), k = int(row / std::size_t(grid.dims.y));
        std::uint32_t hint = WideBvh::kEmpty;
        for (int i = 0; i < grid.dims.x; ++i) {
            float& value = pass.distance[grid.index(i, j, k)];
            if (!std::isnan(value)) continue;
            const glm::dvec3 p = localPosition(context.mesh, grid, i, j, k);
            value = exactSignedSample(context.mesh, wide, topology, context.flipped, p, hint);
        }
    });
    pass.signedAsAsked = true;
    return pass;
}

// Straight into the field: signed by the closest feature's pseudonormal when that is the sign,
// unsigned for the winding sign (which negates in place), with no per-sample side arrays.
DistancePass exactDistance(const BakeContext& context, const RunControl& control) {
    DistancePass pass;
    const std::size_t samples = context.grid.sampleCount();
    zeroFilled(pass.distance, samples, control);
    pass.signedAsAsked = context.sign == SignMethod::Pseudonormal; // as distanceMethods() declares
    // The channels come from the closest points the distances are measured with.
    const ChannelWriter channels(context.settings.channels, samples, true, pass.channels, control);
    computeExactField(context.mesh, context.wide(), context.grid, pass.signedAsAsked ? &context.topology() : nullptr, context.flipped,
                      pass.distance.data(), control, channels.empty() ? nullptr : &channels);
    return pass;
}

// A band's bricks, as the dense grid's: signed as measured when the pseudonormal is the sign.
bool exactBricks(const BakeContext& context, const glm::ivec3* bricks, std::size_t count, double skipBeyond, float* values,
                 const RunControl& control) {
    const bool signing = context.sign == SignMethod::Pseudonormal; // as distanceMethods() declares
    computeExactBricks(context.mesh, context.wide(), context.grid, bricks, count, skipBeyond, signing ? &context.topology() : nullptr,
                       context.flipped, values, control);
    return signing;
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

namespace {

// The memory estimates' parts (core/bake/memory_estimate.cpp): exact distances go straight into the field; on a
// compute device the distance pass's host-side tables are its tree (144-byte triangles, 32-byte
// nodes of up to 4) and, signing by the pseudonormal, the seven normals per triangle twice (the
// topology's and the upload's, 168 bytes each). The reference holds each triangle in double.
double exactDeviceMemory(const MemoryTerms& terms, bool signing) { return terms.triangles * (144 + 16 + (signing ? 2 * 168 : 0)); }
double bruteMemory(const MemoryTerms& terms) { return terms.triangles * 3 * sizeof(glm::dvec3); }

DistanceMethodPlugin exactEntry() {
    DistanceMethodPlugin method(DistanceMethod::Exact, "exact", "the true distance to the nearest triangle");
    method.dense = exactDistance;
    method.bricks = exactBricks;
    method.onDevice = exactDistanceOnDevice;
    method.defaultSign = SignMethod::Auto;
    method.signsInline = SignMethod::Pseudonormal;
    method.readsWideTree = true;
    method.makesChannels = true;
    method.deviceMemory = exactDeviceMemory;
    return method;
}

DistanceMethodPlugin raysEntry() {
    DistanceMethodPlugin method(DistanceMethod::Rays, "rays", "the nearest hit of rays cast from each sample, an upper bound");
    method.dense = rayDistance;
    method.defaultSign = SignMethod::Rays;
    method.signsInline = SignMethod::Rays;
    method.castsRays = true;
    return method;
}

DistanceMethodPlugin bruteEntry() {
    DistanceMethodPlugin method(DistanceMethod::Brute, "brute",
                                "every triangle for every sample in double, signed by the exact winding number: the reference");
    method.dense = bruteDistance;
    method.defaultSign = SignMethod::Winding;
    method.fixedSign = true;
    method.memory = bruteMemory;
    return method;
}

} // namespace

const std::vector<DistanceMethodPlugin>& distanceMethods() {
    static const std::vector<DistanceMethodPlugin> methods = {exactEntry(), raysEntry(), bruteEntry()};
    return methods;
}

const DistanceMethodPlugin& distanceMethod(DistanceMethod id) {
    for (const DistanceMethodPlugin& method : distanceMethods()) {
        if (method.id == id) return method;
    }
    throw Error("unknown distance method");
}

const char* toString(DistanceMethod method) {
    for (const DistanceMethodPlugin& info : distanceMethods()) {
        if (info.id == method) return info.name;
    }
    return "?";
}

std::vector<Choice<DistanceMethod>> distanceMethodChoices() {
    std::vector<Choice<DistanceMethod>> choices;
    for (const DistanceMethodPlugin& info : distanceMethods()) choices.push_back({info.id, info.name, info.description});
    return choices;
}

DistanceMethod parseDistanceMethod(const std::string& name) {
    return parseChoice(distanceMethodChoices(), name, "distance method");
}

} // namespace sdfgen
