#pragma once
#include "sdfgen/any_field.hpp"
#include "sdfgen/channels.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/field.hpp"
#include "sdfgen/mesh_check.hpp"

#include <cctype>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace sdfgen {

// How distances are measured.
enum class DistanceMethod {
    Rays,  // the nearest hit of rays cast from each sample (Möller–Trumbore): an upper bound, see generateRayField
    Exact, // the true distance to the nearest triangle (computeNearest)
    Brute, // every triangle for every sample in double, signs from the exact winding number: the reference
};
// How inside is told from outside.
enum class SignMethod {
    Default,      // the method's own: Rays for the rays method, Auto otherwise
    Auto,         // Pseudonormal where the mesh check proves it right (flipped for a mesh inside out), Winding otherwise
    Rays,         // majority of back-face first hits (rays per sample from BakeSettings::rays)
    Pseudonormal, // angle-weighted pseudonormal of the closest feature
    Winding,      // |generalized winding number| > 1/2: closed parts solid whichever way their faces point
};
const char* toString(DistanceMethod method);
const char* toString(SignMethod sign);
// The method named `name` ("exact", "winding", ...; any case); throws Error listing the known names.
DistanceMethod parseDistanceMethod(const std::string& name);
SignMethod parseSignMethod(const std::string& name);

// Where a bake runs (BakeSettings::device): "cpu", "auto" or a compute device that the program
// registered (sdfgen/device.hpp; the command line, the viewer and the Python module register the
// OpenGL one as "gpu"). The device `name` names (in any case), as deviceChoices() spells it;
// throws Error listing the choices for another.
std::string parseDevice(const std::string& name);

// A distance method, sign method or device as its registry lists it: the name that toString
// writes and parse* reads, and what it is in a line, for help texts, errors and tooltips. Front
// ends build their options, argument parsing and combos from these lists, in their order.
template <class Id>
struct Choice {
    Id id;
    const char* name;
    const char* description;
};
std::vector<Choice<DistanceMethod>> distanceMethodChoices();
std::vector<Choice<SignMethod>> signMethodChoices(); // auto first, default (the method's own) last
std::vector<Choice<SignMethod>> pointQuerySignChoices(); // those Model::query signs by (it takes default as auto)
// cpu, the registered devices in their order, auto: ids are the names. The texts stay valid until
// the next device is registered or removed.
std::vector<Choice<std::string>> deviceChoices();
// "a (what a is), b (...) or c (...)", for help texts and errors.
template <class Id>
std::string describeChoices(const std::vector<Choice<Id>>& choices) {
    std::string text;
    for (std::size_t i = 0; i < choices.size(); ++i) {
        text += (i == 0 ? "" : i + 1 == choices.size() ? " or " : ", ") + std::string(choices[i].name) + " (" + choices[i].description + ")";
    }
    return text;
}
// The choice named `name`, in any case; else an Error naming it and `what` it should be ("sign
// method"), and listing each choice with what it is.
template <class Id>
Id parseChoice(const std::vector<Choice<Id>>& choices, const std::string& name, const std::string& what) {
    std::string lower = name;
    for (char& c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
    for (const Choice<Id>& choice : choices) {
        if (lower == choice.name) return choice.id;
    }
    throw Error("unknown " + what + " '" + name + "'; known: " + describeChoices(choices));
}

// What to bake: the grid (see makeGrid), the method and the sign.
struct BakeSettings {
    int res = 64;
    double padding = 0.1;
    DistanceMethod method = DistanceMethod::Exact;
    SignMethod sign = SignMethod::Default;
    int rays = 64; // for the rays method and the rays sign
    // Where exact distances and winding signs run (a name of deviceChoices()); other methods run on the CPU.
    std::string device = "cpu"; // the GPU is opt-in: slower than the CPU cores where measured (docs/benchmarks.md#gpu)
    // Per-sample channels besides the distance (sdfgen/channels.hpp), into Field::channels (exact
    // method, on the CPU). The distances are the same, bit for bit, with or without them.
    Channels channels;
    // > 0: a narrow-band bake (exact method, CPU): exact distances only within `band` voxels of the
    // surface, in bricks, a SparseField in BakeResult::field; every other sample gets the winding sign's side and
    // the magnitude band * voxel. The dense grid is never allocated. 0: the dense field.
    double band = 0;
};

// The limits of BakeSettings, the same for every front end (sdfgen bake, the viewer, Python).
constexpr int kMaxRes = 65536;       // voxels along the longest side
constexpr int kMaxRays = 65536;      // rays per sample
constexpr double kMaxPadding = 100;  // the margin, as a fraction of the mesh's longest side
constexpr double kMaxBand = 1e9;     // voxels each side of the surface

// Why settings cannot be baked, in the settings' own names ("rays must be from 1 to 65536 per
// sample (got 100000000)"). `setting` names the BakeSettings member to change ("res", "padding",
// "method", "sign", "rays", "device", "channels" or "band"), for a front end to say it in its own
// words: the command line as its option (--rays), the viewer as its field's label.
struct SettingsProblem {
    std::string setting;
    std::string message;
};
// The first problem of `settings` that shows without a mesh: a value out of its limits, or
// settings that do not go together (a band bake with method rays). bake() refuses these with the
// message; front ends check before they load or start anything. What only a mesh can show (a
// sign it cannot prove, memory) the bake still refuses itself.
std::optional<SettingsProblem> problem(const BakeSettings& settings);

// The grid a bake of `settings` samples around `bounds` (the mesh's worldBounds): makeGrid's, and
// for a band bake the same grid without makeGrid's check that the dense grid fits in memory (a
// band never allocates it).
Grid bakeGrid(const WorldBounds& bounds, const BakeSettings& settings);
// The peak bytes a band bake of `band` voxels on `grid` (bakeGrid's) allocates, estimated from the
// mesh's area: an upper bound, within twice the bake's peak on closed and open meshes. bake()
// refuses a band that needs more than the available memory by it.
std::uint64_t estimateBandBakeBytes(const Mesh& mesh, const Grid& grid, double band);

// A bake's field and what was decided on the way.
struct BakeResult {
    AnyField field; // a SparseField for a band bake (BakeSettings::band > 0), the dense Field otherwise
    SignMethod sign = SignMethod::Default; // the sign method actually used
    bool checked = false;                  // whether the mesh check ran (sign auto)
    MeshCheck check;
    std::string signReason; // why auto chose as it did, for the summary and panel
    std::vector<std::string> warnings; // e.g. an explicit sign on an inside-out mesh, for the summary and panel
    // Time spent building the mesh's search tree for closest points and its topology, the first
    // time a bake needed them (a Model keeps them for the next), together.
    double setupSeconds = 0;
    double distanceSeconds = 0; // time spent on distances (and on rays, when the sign needs them)
    double signSeconds = 0;     // time spent on the mesh check and the sign
    double searchSeconds = 0;   // of that, a band bake's search for its bricks (and the cubes it sides)
    bool onDevice = false;      // whether the compute device measured the distances (and winding signs)
    std::string deviceReason;   // why the bake runs where it does, e.g. "gpu: GL vendor Mesa, renderer llvmpipe ..."
};


} // namespace sdfgen
