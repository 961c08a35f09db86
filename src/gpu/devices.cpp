// The compute devices' registry: one line per device (docs/extending.md).
#include "gpu/devices.hpp"
#include "gpu/gl_device.hpp"

namespace sdfgen::gpu {

void registerDevices() {
    for (const ComputeDevicePlugin& plugin : {glDevicePlugin()}) registerComputeDevice(plugin);
}

} // namespace sdfgen::gpu
