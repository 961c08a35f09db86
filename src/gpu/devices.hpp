#pragma once

namespace sdfgen::gpu {

// Registers every compute device of this build with the core (registerComputeDevice), in the
// order auto prefers them. Programs that bake call it before they list the devices.
void registerDevices();

} // namespace sdfgen::gpu
