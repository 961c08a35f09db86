#pragma once
// A compute device (sdfgen/device.hpp) that answers on the CPU, by the exact search and by brute
// force for the winding numbers, and leaves some samples undecided for the core as a real device
// may: for tests of the device registry and of bakes on a device, with OpenGL or without.
#include "sdfgen/device.hpp"

#include <string>

namespace sdfgen::test {

class StandInDevice final : public ComputeDevice {
public:
    StandInDevice(bool hardware, int* calls) : hardware_(hardware), calls_(calls) {}
    std::string description() const override { return "stand-in"; }
    std::string renderer() const override { return "stand-in"; }
    bool hardware() const override { return hardware_; }
    // Signed as the CPU signs, except every third sample left undecided (NaN) for the core to decide.
    void nearest(const Mesh& mesh, const Grid& grid, const PseudonormalSign* sign, const RunControl& control,
                 std::vector<float>& distance) override;
    // With fans: every other sample's side from w in double, the rest left undecided (2) for the core.
    std::vector<std::int32_t> windingNumbers(const Mesh& mesh, const std::vector<glm::dvec3>& corners, const std::vector<std::int32_t>& weights,
                                             const WindingFans* fans, const Grid& grid, const RunControl&,
                                             std::vector<std::uint8_t>& sides) override;

private:
    bool hardware_;
    int* calls_;
};


// A device named `name` that opens a StandInDevice (`calls`, when given, counts its passes).
ComputeDevicePlugin standInDevice(const char* name, bool hardware, int* calls = nullptr);

// Registers a device for the scope's life: tests leave the registry as they found it.
class ScopedDevice {
public:
    explicit ScopedDevice(ComputeDevicePlugin plugin) : name_(plugin.name) { registerComputeDevice(std::move(plugin)); }
    ~ScopedDevice() { unregisterComputeDevice(name_); }
    ScopedDevice(const ScopedDevice&) = delete;
    ScopedDevice& operator=(const ScopedDevice&) = delete;

private:
    std::string name_;
};

} // namespace sdfgen::test
