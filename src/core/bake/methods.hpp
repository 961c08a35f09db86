#pragma once
// Distance and sign methods as plug-ins: each is a name, a description and a function, listed in
// one registry (distance_methods.cpp, sign_methods.cpp). bake() only looks them up, so adding a
// method is its function plus one registry line (and its enum value in sdfgen/bake.hpp).
#include "core/accel/bvh.hpp"
#include "core/mesh/topology.hpp"
#include "core/accel/wide_bvh.hpp"
#include "sdfgen/bake.hpp"
#include "sdfgen/device.hpp"
#include "sdfgen/grid.hpp"
#include "sdfgen/mesh.hpp"
#include "sdfgen/run_control.hpp"

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

namespace sdfgen {

// What a method may use: the mesh, its tree, the grid, the settings, and the mesh's wide tree,
// topology and check, built on first use and cached by whoever owns the mesh (sdfgen::Model).
struct BakeContext {
    const Mesh& mesh;
    const Bvh& tree;
    std::function<const WideBvh&()> wide; // the tree collapsed for closest-point searches
    const Grid& grid;
    const BakeSettings& settings;
    std::function<const MeshTopology&()> topology;
    std::function<const MeshCheck&()> check;
    bool flipped = false; // the mesh is inside out: the pseudonormal sign swaps inside and outside
    // The sign bake() settled on before the distance pass (never Auto there), Default when the
    // method signs by itself.
    SignMethod sign = SignMethod::Default;
    // Where the exact distance and the winding sign run (sdfgen/device.hpp); null: on the CPU.
    ComputeDevice* device = nullptr;
};

// A distance pass's output. `distance` is unsigned, in world units, unless `signedAsAsked`: then
// it already carries the context's sign and no sign method runs (the ray method signed by its own
// vote, exact distances signed by the pseudonormal, on the CPU or a compute device). A method may
// also leave inside flags of its own (the reference's winding number); bake() releases them once
// the distances are signed.
struct DistancePass {
    std::vector<float> distance;
    bool signedAsAsked = false;
    std::optional<std::vector<std::uint8_t>> inside;
    // The channels the settings ask for (exact method), in Field's layout; the gradient points away
    // from the surface until bake() signs it (see ChannelOutputs).
    std::vector<float> gradient, closest;
    std::vector<std::int32_t> triangle;
};

struct DistanceMethodInfo {
    DistanceMethod id;
    const char* name;
    const char* description;
    DistancePass (*run)(const BakeContext& context, const RunControl& control);
    // The sign this method implies when the settings name none (SignMethod::Default).
    SignMethod defaultSign;
    // Set for methods whose own inside flags are the only sign they allow (the reference).
    bool fixedSign;
    // The sign this method writes as it measures when the context asks for it (its pass is then
    // the whole bake), Default for none.
    SignMethod signsInline;
};

struct SignMethodInfo {
    SignMethod id;
    const char* name;
    const char* description;
    // Signs `pass.distance` in place (negated where inside); may use and fill in `pass`.
    void (*run)(const BakeContext& context, DistancePass& pass, const RunControl& control);
};

// A signed field's magnitudes (in place) and inside flags (for methods that sign as they measure).
DistancePass splitSigned(std::vector<float> values);
// Negates the distances of the samples flagged inside.
void negateInside(std::vector<float>& distance, const std::vector<std::uint8_t>& inside);

const std::vector<DistanceMethodInfo>& distanceMethods();
const std::vector<SignMethodInfo>& signMethods(); // Auto and Default are decided in bake(), not listed
const DistanceMethodInfo& distanceMethod(DistanceMethod id);
const SignMethodInfo& signMethod(SignMethod id);

} // namespace sdfgen
