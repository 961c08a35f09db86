#pragma once
#include "render/context.hpp"

#include <string>

struct GLFWwindow;

namespace sdfgen::app {

// A resizable GLFW window with an OpenGL 4.5 core context (a debug context in debug builds),
// sized in screen coordinates and scaled to the monitor's content scale (high-DPI).
class GlfwContext final : public render::GlContext {
public:
    // Throws Error with GLFW's message when there is no display or no 4.5 core context.
    GlfwContext(int width, int height, const std::string& title);
    ~GlfwContext() override;
    GlfwContext(const GlfwContext&) = delete;
    GlfwContext& operator=(const GlfwContext&) = delete;

    void makeCurrent() override;
    glm::ivec2 framebufferSize() const override;
    void present() override;
    GLFWwindow* window() const { return window_; }

private:
    GLFWwindow* window_ = nullptr;
};

// Whether a display server is named in the environment (DISPLAY or WAYLAND_DISPLAY).
bool haveDisplay();

} // namespace sdfgen::app
