#pragma once
#include "render/context.hpp"

#include <memory>

namespace sdfgen::render {

// A headless OpenGL 4.5 core context from OSMesa (Mesa's llvmpipe on the CPU): no display needed.
// Its default framebuffer is an RGBA8 buffer in memory of the given size, with a 24-bit depth buffer.
// Throws Error when OSMesa cannot create a 4.5 core context.
std::unique_ptr<GlContext> createOsMesaContext(glm::ivec2 size);

} // namespace sdfgen::render
