#pragma once
// Where a bake runs: on the CPU (the core library) or on a compute device that another library
// registers at run time (src/gpu: OpenGL 4.5 compute shaders). The core never links OpenGL; it
// only calls this interface.
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

enum class Device {
    Cpu,  // the core library's generators
    Gpu,  // the registered compute device; an error when there is none or it cannot start
    Auto, // the compute device when it runs on real GPU hardware, the CPU otherwise
};
const char* toString(Device device);

// A processor that can do the two heavy parts of an exact bake. Both must give exactly what the
// CPU gives: the same distances (to 1e-4 voxel) and the same winding numbers (not one different).
class ComputeDevice {
public:
    virtual ~ComputeDevice() = default;
    // One line naming the driver, e.g. "GL vendor Mesa, renderer llvmpipe (LLVM 15.0.6, 256 bits), version 4.5 (Core Profile) Mesa 22.3.6".
    virtual std::string description() const = 0;
    // False for drivers that emulate a GPU on the CPU (Mesa's llvmpipe, softpipe): auto skips them.
    virtual bool hardware() const = 0;

    // For every sample of `grid`: the exact distance to the nearest triangle of `mesh` (world
    // units: measured in the mesh's local units at localPosition, times mesh.unit) and that
    // triangle's index, the lowest of equally near ones (the CPU's computeNearest).
    virtual void nearest(const Mesh& mesh, const Grid& grid, const RunControl& control, std::vector<float>& distance,
                         std::vector<std::uint32_t>& triangle) = 0;
    // For every sample of `grid`: the winding number of the closed surface `triangles` (three
    // corners each in `mesh`'s local coordinates, counter-clockwise seen from outside), an
    // integer, counted as the CPU's insideByWinding counts it (signed crossings ahead along +x of
    // the sample's localPosition, robust tie-breaking).
    virtual std::vector<std::int32_t> windingNumbers(const Mesh& mesh, const std::vector<glm::dvec3>& triangles, const Grid& grid,
                                                     const RunControl& control) = 0;
};

// Registers how to open the compute device (called once by a program that links src/gpu). The
// device is opened on first use and kept; `open` throws Error when it cannot open one.
// `mayBeHardware`, when given, tells without opening anything whether the device could be real GPU
// hardware; when it says no, auto takes the CPU at once (no context is made just to be refused).
void registerComputeDevice(std::function<std::unique_ptr<ComputeDevice>()> open, std::function<bool()> mayBeHardware = {});

// The device a bake with `device` runs on: nullptr for the CPU. Gpu throws Error when no device is
// registered or it cannot open; Auto returns nullptr then, or when the device is not hardware.
// `why` (optional) receives a one-line reason for the choice.
ComputeDevice* selectComputeDevice(Device device, std::string* why = nullptr);

} // namespace sdfgen
