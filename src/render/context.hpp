#pragma once
#include <glm/vec2.hpp>

namespace sdfgen::render {

// An OpenGL 4.5 core context with a default framebuffer to draw into: a GLFW window (src/app), an
// EGL pbuffer (egl_context.hpp) or an OSMesa offscreen buffer (osmesa_context.hpp). Renderers
// never see which one it is.
class GlContext {
public:
    virtual ~GlContext() = default;
    virtual void makeCurrent() = 0;
    // Makes no context current on this thread, so that another thread may make this one current.
    virtual void release() {}
    // Size of the default framebuffer in pixels.
    virtual glm::ivec2 framebufferSize() const = 0;
    // Shows what was drawn (swaps buffers in a window; finishes the frame offscreen).
    virtual void present() = 0;
    // Which kind of context it is, for messages: "EGL", "OSMesa", "window".
    virtual const char* kind() const { return "window"; }
};

} // namespace sdfgen::render
