#pragma once
// Distance and sign methods as plug-ins: each is an object of named members (its passes for dense
// grids, a band's bricks, single points and a compute device, what they read, their memory),
// listed in one registry (distance_methods.cpp, sign_methods.cpp). bake(), the band bake, the
// memory estimate, point queries and every front end only ask these objects, so adding a method is
// its functions plus one registry entry (and its enum value in sdfgen/bake.hpp): docs/extending.md.
#include "core/accel/bvh.hpp"
#include "core/accel/wide_bvh.hpp"
#include "core/mesh/geometry.hpp"
#include "core/accel/topology.hpp"
#include "sdfgen/bake.hpp"
#include "sdfgen/device.hpp"
#include "sdfgen/grid.hpp"
#include "sdfgen/mesh.hpp"
#include "sdfgen/run_control.hpp"

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace sdfgen {

// Receives rows of up to four samples (i.., j, k) with each sample's nearest triangle (the
// float-nearest, the least index on ties); called from several threads at once.
using NearestRowStore = std::function<void(int i, int j, int k, int count, const std::uint32_t* triangles)>;

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
    // Every sample's nearest triangle by the exact distance's own search, for a sign that reads
    // closest features after a pass that found none (bake() hands it down; distance/ and sign/
    // are siblings).
    std::function<void(const NearestRowStore&, const RunControl&)> nearestRows = nullptr;
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
    // The channels the settings ask for (exact method), in Field's layout, unsigned until bake()
    // signs them (signChannels).
    std::vector<ChannelValues> channels;
};

// What the memory estimate (core/bake/memory_estimate.cpp) is made of, for the registries' own parts of it.
struct MemoryTerms {
    double samples = 0, triangles = 0;
    double topology = 0; // MeshTopology's bytes
    double winding = 0;  // the winding sign's: the topology and the crossings it collects
};

// A point query's nearest triangle and its closest point on it (local coordinates).
struct NearestPoint {
    std::uint32_t triangle;
    ClosestPoint closest;
};

// What a sign's point queries may use: the mesh and its structures, built on first use and cached
// by whoever owns the mesh (sdfgen::Model). The functions serve only while atPoint runs: a
// PointSide takes what it keeps then.
struct PointContext {
    const Mesh& mesh;
    const Bvh& tree;
    std::function<const WideBvh&()> wide;
    std::function<const MeshTopology&()> topology;
};

// A sign's answer for single points (Model::query), made once per mesh and kept by its Model, so
// that what it prepares (the winding sign's fans) serves every later query.
class PointSide {
public:
    virtual ~PointSide() = default;
    // Whether each of `count` points (local coordinates) is inside, given its nearest point; `flipped`
    // as BakeContext's. Model::query hands over the points of a block in Morton order, so that
    // neighbours follow each other and a method may share work between them; each answer is the
    // point's own, whatever its neighbours.
    virtual void inside(const glm::dvec3* points, const NearestPoint* nearest, std::size_t count, bool flipped,
                        std::uint8_t* inside) const = 0;
};

// A distance method: how it measures a dense grid, a band's bricks and on a compute device, and
// what that reads and holds. Members left unset are capabilities it lacks.
struct DistanceMethodPlugin {
    DistanceMethod id;
    const char* name;
    const char* description;

    // The dense grid's distances.
    DistancePass (*dense)(const BakeContext& context, const RunControl& control) = nullptr;
    // The narrow band's (core/bake/band_bake.hpp): the samples of `count` bricks of SparseField's
    // (brick b's at values[kBrickSamples b + its offset in the brick]) as `dense` measures them, bit
    // for bit, but for those farther than `skipBeyond` (local units), which it may leave unwritten.
    // Returns whether it signed them as it measured (context.sign is its signsInline). Null: the
    // band bake refuses the method.
    bool (*bricks)(const BakeContext& context, const glm::ivec3* bricks, std::size_t count, double skipBeyond, float* values,
                   const RunControl& control) = nullptr;
    // The dense grid's distances on context.device; null where the device cannot run the method.
    DistancePass (*onDevice)(const BakeContext& context, const RunControl& control) = nullptr;

    // The sign this method implies when the settings name none (SignMethod::Default).
    SignMethod defaultSign = SignMethod::Auto;
    // Its own inside flags are the only sign it allows (the reference): no sign method runs.
    bool fixedSign = false;
    // The sign it writes as it measures when the context asks for it (its pass is then the whole
    // bake), Default for none.
    SignMethod signsInline = SignMethod::Default;
    bool readsWideTree = false; // on the CPU its pass searches the closest-point tree (core/accel/wide_bvh.hpp)
    bool castsRays = false;     // casts BakeSettings::rays rays per sample (recorded in the field)
    bool makesChannels = false; // fills the channels the settings ask for (DistancePass::channels)

    // Bytes its pass holds besides the field and the shared trees; a fixed-sign method's whole
    // bake besides the field.
    double (*memory)(const MemoryTerms& terms) = [](const MemoryTerms&) { return 0.0; };
    // With onDevice: the host-side tables of its device pass, `signing` when it signs as it measures.
    double (*deviceMemory)(const MemoryTerms& terms, bool signing) = nullptr;

    DistanceMethodPlugin(DistanceMethod id, const char* name, const char* description) : id(id), name(name), description(description) {}
};

// Whether a sign can side a narrow band's samples, most of which have no distance pass. Every band
// takes its sides beyond its bricks from the winding number's crossing counts (BandSides in
// core/sign/winding_sign.hpp), as OpenVDB's level sets take theirs from an interior test: a sign
// serves bands where its sides are those.
enum class BandSigning {
    Never,       // it decides per sample from that sample's own pass (ray votes)
    Sides,       // the band's sides, in its bricks too (or, for auto and default, a sign settled to one that can)
    Own,         // its own signs in the bricks (as the distance pass measures, or its `bricks`), the band's sides beyond
    WhereProven, // as Own, only where the mesh check proves its sides the winding number's
};

// A sign method: how it signs a dense grid, a band's bricks, single points and on a compute
// device, and what that reads and holds. Members left unset are capabilities it lacks.
struct SignMethodPlugin {
    SignMethod id;
    const char* name;
    const char* description;

    // The dense grid: signs `pass.distance` in place (negated where inside); may use and fill in
    // `pass`. Null for the signs decideSign settles to another (auto, default).
    void (*dense)(const BakeContext& context, DistancePass& pass, const RunControl& control) = nullptr;
    // How a narrow band's samples are signed; for Own, `bricks` signs the bricks' samples (laid
    // out as DistanceMethodPlugin::bricks has them) where the distance pass did not.
    BandSigning band = BandSigning::Never;
    void (*bricks)(const BakeContext& context, const glm::ivec3* bricks, std::size_t count, float* values, const RunControl& control) = nullptr;
    // Point queries: its PointSide for the mesh; null where Model::query does not sign by it.
    std::unique_ptr<PointSide> (*atPoint)(const PointContext& context) = nullptr;
    // `dense` on context.device; null: `dense` runs on the CPU even when the distances were measured on the device.
    void (*onDevice)(const BakeContext& context, DistancePass& pass, const RunControl& control) = nullptr;

    // A choice that decideSign settles to another sign before anything is signed (auto, default);
    // `settlesForQueries`: point queries list it too (default is left out: there it means auto).
    bool settles = false, settlesForQueries = false;
    bool readsWideTree = false; // its pass searches the closest-point tree
    bool readsTopology = false; // its pass (or auto's mesh check) reads MeshTopology
    bool castsRays = false;     // casts BakeSettings::rays rays per sample (recorded in the field)

    // Bytes its pass holds at the peak besides the field, the per-sample buffers and the trees.
    double (*memory)(const MemoryTerms& terms) = [](const MemoryTerms&) { return 0.0; };
    // With onDevice: the host-side tables of its device pass.
    double (*deviceMemory)(const MemoryTerms& terms) = nullptr;

    SignMethodPlugin(SignMethod id, const char* name, const char* description) : id(id), name(name), description(description) {}

    bool servesPointQueries() const { return atPoint != nullptr || settlesForQueries; }
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

const std::vector<DistanceMethodPlugin>& distanceMethods();
const std::vector<SignMethodPlugin>& signMethods(); // auto and default too, which decideSign settles
const DistanceMethodPlugin& distanceMethod(DistanceMethod id);
const SignMethodPlugin& signMethod(SignMethod id);

} // namespace sdfgen
