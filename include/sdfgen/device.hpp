#pragma once
// The compute device plug-in interface: how a library that can run the heavy parts of an exact
// bake on other hardware (src/gpu: OpenGL 4.5 compute shaders) registers with the core at run
// time, by name, beside any other. The core never links OpenGL; it only calls this interface.
// Programs that only bake and query need not include it: BakeSettings::device picks where a bake
// runs.
#include "sdfgen/bake.hpp"
#include "sdfgen/grid.hpp"
#include "sdfgen/mesh.hpp"
#include "sdfgen/run_control.hpp"

#include <glm/vec3.hpp>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace sdfgen {

// What ComputeDevice::nearest signs by: inside where (p - q)·n < 0 (the other way round when
// `flipped`), q the closest point of the nearest triangle to the sample p and n the angle-weighted
// pseudonormal of q's feature (face, edge or vertex). The CPU's float search rounds differently
// from a device's, so where triangles are nearly as near the two may keep different ones: a device
// signs a sample only when every triangle whose float distance is within the rounding of both
// searches (2^-17 of the coordinates' magnitude) of its nearest gives the same side, each with
// |(p - q)·n| beyond its rounding; the CPU's nearest is among them, so the sign is the CPU's.
struct PseudonormalSign {
    std::vector<glm::dvec3> normals; // 7 per mesh triangle: face, edges AB, BC, CA, vertices A, B, C
    bool flipped = false;
};

// The fans that close a mesh's holes (the core's WindingCaps, flattened), for the winding sign's
// fractional part: w = (crossings ahead) - (the fans' winding number), inside where |w| > 1/2.
// Fan f is the triangles (loop[i + 1], loop[i], centre), the centre at points[first] and the loop
// at points[first + 1 .. first + count], counted `weight` times.
// Nodes: a box tree over the fans (root first; inner: children first and first + 1; leaf: fan
// `first`), `area` the sum of |weight| x area below, which bounds the winding number seen from a
// point at distance d by area / (4π d²).
struct WindingFans {
    struct Fan {
        std::uint32_t first, count;
        std::int32_t weight;
    };
    struct Node {
        glm::dvec3 lo, hi;
        double area;
        std::uint32_t first;
        bool leaf;
    };
    std::vector<glm::dvec3> points;
    std::vector<Fan> fans;
    std::vector<Node> nodes;
};

// A processor that can do the two heavy parts of an exact bake. Both must give exactly what the
// CPU gives: the same distances (to 1e-4 voxel) and the same winding numbers (not one different).
class ComputeDevice {
public:
    virtual ~ComputeDevice() = default;
    // One line naming the driver, e.g. "GL vendor Mesa, renderer llvmpipe (LLVM 15.0.6, 256 bits), version 4.5 (Core Profile) Mesa 22.3.6".
    virtual std::string description() const = 0;
    // The renderer alone, briefly, for status lines: e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
    virtual std::string renderer() const = 0;
    // False for drivers that emulate a GPU on the CPU (Mesa's llvmpipe, softpipe): auto skips them.
    virtual bool hardware() const = 0;

    // For every sample of `grid`: the exact distance to the nearest triangle of `mesh` (world
    // units: measured in the mesh's local units at mesh.toLocal(grid.position(i, j, k)), times mesh.unit), the CPU's
    // computeExactField's to 1e-4 voxel. With `sign`, negative inside by the pseudonormal of the
    // nearest triangle's closest feature, as the CPU signs; a sample the device cannot sign as the
    // CPU would (see PseudonormalSign) is NaN, for the caller to decide.
    virtual void nearest(const Mesh& mesh, const Grid& grid, const PseudonormalSign* sign, const RunControl& control,
                         std::vector<float>& distance) = 0;
    // For every sample of `grid`: the winding number of the closed surface `triangles` (three
    // corners each in `mesh`'s local coordinates, counter-clockwise seen from outside), triangle t
    // counted weights[t] times (copies of a triangle, caps shared by equal loops; negative: the
    // other way round), an integer, counted as the CPU's insideByWinding counts it (signed
    // crossings ahead along +x of the sample's local position, robust tie-breaking).
    // With `fans` (not empty), also `sides` for every sample: 1 inside, 0 outside by the sign of
    // |w| - 1/2 (w as in WindingFans, the fans' part measured where their bounds leave
    // doubt), 2 where the device's float cannot tell it from the CPU's double: the caller decides.
    virtual std::vector<std::int32_t> windingNumbers(const Mesh& mesh, const std::vector<glm::dvec3>& triangles,
                                                     const std::vector<std::int32_t>& weights, const WindingFans* fans,
                                                     const Grid& grid, const RunControl& control, std::vector<std::uint8_t>& sides) = 0;
};

// A compute device as a program registers it (a plug-in, as the distance and sign methods are;
// docs/extending.md). Its texts are static (string literals), as the other registries' names.
struct ComputeDevicePlugin {
    const char* name = nullptr;        // BakeSettings::device's choice (--device, Python's device=, the viewer's combo), e.g. "gpu"
    const char* description = nullptr; // what it is in a line, for help texts and tooltips
    // What it runs through, as auto's description and its status lines name it: "OpenGL 4.5 driver".
    const char* driver = nullptr;
    // Tells without opening anything whether the device could be real GPU hardware; when it says
    // no, auto passes the device over at once (no context is made just to be refused). Unset: auto
    // opens the device and asks it (ComputeDevice::hardware).
    std::function<bool()> mayBeHardware;
    // Opens the device; throws Error when it cannot. Called on first use, once: the device is kept,
    // or the failure remembered.
    std::function<std::unique_ptr<ComputeDevice>()> open;
};

// Adds `plugin` to the devices a bake may run on, after those registered before it (auto takes
// the first on hardware), or replaces the one of the same name (its device is closed). Called by
// a program that links devices (src/gpu/devices.cpp) before its front end lists the choices.
// Throws Error for a plugin without a name, texts or opener, or named cpu or auto.
void registerComputeDevice(ComputeDevicePlugin plugin);
// Removes the device named `name` (closing it, if open); nothing when there is none.
void unregisterComputeDevice(const std::string& name);

// The device a bake with BakeSettings::device `device` runs on: nullptr for the CPU. A device's
// name gives that device, and throws Error ("device NAME: why") when it cannot open; "auto" gives
// the first registered device that runs on hardware, nullptr when none does; another name throws
// parseDevice's Error. `why` (optional) receives a one-line reason for the choice, starting with
// where the bake runs: "cpu: asked for", "gpu: GL vendor ...".
ComputeDevice* selectComputeDevice(const std::string& device, std::string* why = nullptr);

} // namespace sdfgen
