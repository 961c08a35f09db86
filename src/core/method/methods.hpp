#pragma once
// Distance and sign methods as plug-ins: each is a name, a description, what it reads and where it
// runs, its memory estimate and a function, listed in one registry (distance_methods.cpp,
// sign_methods.cpp). bake(), the memory estimate, point queries and every front end only look
// them up, so adding a method is its function plus one registry line (and its enum value in
// sdfgen/bake.hpp).
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
#include <string>
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

// What the memory estimate (core/bake/memory_estimate.cpp) is made of, for the registries' own parts of it.
struct MemoryTerms {
    double samples = 0, triangles = 0;
    double topology = 0; // MeshTopology's bytes
    double winding = 0;  // the winding sign's: the topology and the crossings it collects
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
    bool readsWideTree; // on the CPU its pass searches the closest-point tree (core/accel/wide_bvh.hpp)
    bool castsRays;     // casts BakeSettings::rays rays per sample (recorded in the field)
    bool makesChannels; // fills the gradient, closest and triangle channels
    bool measuresBand;  // the narrow-band bake (BakeSettings::band, core/bake/band_bake.hpp) measures by it
    // Bytes its pass holds besides the field and the shared trees; a fixed-sign method's whole
    // bake besides the field.
    double (*memory)(const MemoryTerms& terms);
    // Null where the compute device cannot run it; else the host-side tables of its device pass,
    // `signing` when the device signs as it measures.
    double (*deviceMemory)(const MemoryTerms& terms, bool signing);
};

// Whether a sign can side a narrow-band bake's samples, most of which have no distance pass.
enum class BandSigning {
    Never,       // it decides per sample from that sample's own pass (ray votes)
    Always,      // the winding number's sides (or, for auto and default, a sign settled to one that can)
    WhereProven, // its sides are the winding number's only where the mesh check proves it right
};

struct SignMethodInfo {
    SignMethod id;
    const char* name;
    const char* description;
    // Signs `pass.distance` in place (negated where inside); may use and fill in `pass`. Null for
    // the signs decideSign settles to another (auto, default).
    void (*run)(const BakeContext& context, DistancePass& pass, const RunControl& control);
    bool pointQueries;  // Model::query signs by it (default is left out: there it means auto)
    bool readsWideTree; // its pass searches the closest-point tree
    bool readsTopology; // its pass (or auto's mesh check) reads MeshTopology
    bool castsRays;     // casts BakeSettings::rays rays per sample (recorded in the field)
    BandSigning band;
    // Bytes its pass holds at the peak besides the field, the per-sample buffers and the trees.
    double (*memory)(const MemoryTerms& terms);
    // Null where the compute device does not run it; else the host-side tables of its device pass.
    double (*deviceMemory)(const MemoryTerms& terms);
};

// The sign a bake or point query uses, settled before any distance is measured (see decideSign).
struct SignDecision {
    SignMethod sign = SignMethod::Default;
    bool checked = false; // auto ran the mesh check
    MeshCheck check;
    bool flipped = false; // auto found the mesh inside out: the pseudonormal's inside and outside swap
    std::string reason;   // why auto chose as it did, for the summary and panel
    std::vector<std::string> warnings; // an explicit sign that the mesh defeats
};

// The named sign, `whenDefault` for Default (a method's own sign; Auto for point queries), and for
// Auto the pseudonormal where the mesh check proves it right (flipped on a mesh inside out), the
// winding number otherwise. The topology and check are read only when the choice needs them.
SignDecision decideSign(SignMethod asked, SignMethod whenDefault, const std::function<const MeshTopology&()>& topology,
                        const std::function<const MeshCheck&()>& check);
// The signs decideSign may settle `asked` to without the mesh, for estimates made before it runs.
std::vector<SignMethod> possibleSigns(SignMethod asked, SignMethod whenDefault);

// A signed field's magnitudes (in place) and inside flags (for methods that sign as they measure).
DistancePass splitSigned(std::vector<float> values);
// Negates the distances of the samples flagged inside.
void negateInside(std::vector<float>& distance, const std::vector<std::uint8_t>& inside);

const std::vector<DistanceMethodInfo>& distanceMethods();
const std::vector<SignMethodInfo>& signMethods(); // auto and default too, which decideSign settles
const DistanceMethodInfo& distanceMethod(DistanceMethod id);
const SignMethodInfo& signMethod(SignMethod id);

} // namespace sdfgen
