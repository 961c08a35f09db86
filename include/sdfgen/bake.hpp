#pragma once
#include "sdfgen/field.hpp"
#include "sdfgen/mesh_check.hpp"

#include <string>
#include <vector>

namespace sdfgen {

// How distances are measured.
enum class DistanceMethod {
    Rays,  // the original report's ray sampling: an upper bound, see generateRayField
    Exact, // the true distance to the nearest triangle (computeNearest)
    Brute, // every triangle for every sample in double, signs from the exact winding number: the reference
};
// How inside is told from outside.
enum class SignMethod {
    Default,      // Rays for the rays method, Auto otherwise
    Auto,         // Pseudonormal where the mesh check proves it right, Winding otherwise
    Rays,         // majority of back-face first hits (rays per sample from BakeSettings::rays)
    Pseudonormal, // angle-weighted pseudonormal of the closest feature
    Winding,      // generalized winding number > 1/2
};
const char* toString(DistanceMethod method);
const char* toString(SignMethod sign);
// The method named `name` ("exact", "winding", ...); throws Error listing the known names.
DistanceMethod parseDistanceMethod(const std::string& name);
SignMethod parseSignMethod(const std::string& name);

// Where a bake runs: exact distances and winding signs on the CPU, or on a compute device that a
// program registers (the viewer and the command line register the GPU; see sdfgen/device.hpp).
enum class Device {
    Cpu,  // the core library's generators
    Gpu,  // the registered compute device; an error when there is none or it cannot start
    Auto, // the compute device when it runs on real GPU hardware, the CPU otherwise
};
const char* toString(Device device);

// What to bake: the grid (see makeGrid), the method and the sign.
struct BakeSettings {
    int res = 64;
    double padding = 0.1;
    DistanceMethod method = DistanceMethod::Exact;
    SignMethod sign = SignMethod::Default;
    int rays = 64; // for the rays method and the rays sign
    // Where exact distances and winding signs run; other methods run on the CPU.
    Device device = Device::Auto;
};

// A bake's field and what was decided on the way.
struct BakeResult {
    Field field;
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
    bool onDevice = false;      // whether the compute device measured the distances (and winding signs)
    std::string deviceReason;   // why the bake runs where it does, e.g. "gpu: GL vendor Mesa, renderer llvmpipe ..."
};


} // namespace sdfgen
