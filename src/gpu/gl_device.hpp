#pragma once
#include "sdfgen/device.hpp"

#include <memory>

namespace sdfgen::gpu {

// The OpenGL 4.5 compute device (shaders/nearest.comp and nearest_signed.comp, both nearest.glsl;
// winding_rows.comp, winding_prefix.comp, winding_caps.comp) in its own headless context (EGL, else OSMesa). Throws Error when no 4.5 core context can be made.
std::unique_ptr<ComputeDevice> openGlDevice();

// The OpenGL device as the core registers it (src/gpu/devices.cpp): "gpu", opened by openGlDevice.
ComputeDevicePlugin glDevicePlugin();

// Whether a driver name (GL_RENDERER) is a CPU emulation of a GPU: llvmpipe, softpipe, swrast.
bool isSoftwareRenderer(const std::string& renderer);

} // namespace sdfgen::gpu
