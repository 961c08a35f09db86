#pragma once
#include "render/context.hpp"

#include <memory>

namespace sdfgen::render {

// A headless OpenGL 4.5 core context from EGL, drawing into a pbuffer of the given size (RGBA8,
// 24-bit depth, 8-bit stencil). The display is the first that gives such a context, of: each
// hardware EGL device (EGL_EXT_platform_device: GPU servers without X), Mesa's surfaceless
// platform (EGL_MESA_platform_surfaceless), the default display. Throws Error naming why none did.
std::unique_ptr<GlContext> createEglContext(glm::ivec2 size);

// Whether EGL may reach GPU hardware: it lists a device that is not Mesa's software renderer, or
// cannot list devices at all (then only making a context tells). Makes no context.
bool eglMayHaveHardwareDevice();

// The context headless work uses: EGL first, OSMesa (Mesa's llvmpipe) when EGL gives none; only
// one of them when the environment variable SDFGEN_HEADLESS is egl or osmesa. Throws Error with
// the reasons when none can make a 4.5 core context.
std::unique_ptr<GlContext> createHeadlessContext(glm::ivec2 size);

} // namespace sdfgen::render
