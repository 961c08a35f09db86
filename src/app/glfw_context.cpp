#include "app/glfw_context.hpp"
#include "sdfgen/error.hpp"
#include "render/gl.hpp"

#include <GLFW/glfw3.h>
#include <algorithm>
#include <cstdlib>

namespace sdfgen::app {

namespace {
std::string glfwMessage() {
    const char* description = nullptr;
    glfwGetError(&description);
    return description ? description : "unknown GLFW error";
}
} // namespace

bool haveDisplay() {
    const char* x11 = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    return (x11 && *x11) || (wayland && *wayland);
}

GlfwContext::GlfwContext(int width, int height, const std::string& title) {
    if (!glfwInit()) throw Error("GLFW: " + glfwMessage());
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    glfwWindowHint(GLFW_SCALE_TO_MONITOR, GLFW_TRUE);
#ifndef NDEBUG
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, GLFW_TRUE);
#endif
    // The first window fits the screen's work area (without the panels of the desktop), with room
    // for its frame; GLFW_SCALE_TO_MONITOR scales the size asked for by the content scale first.
    if (GLFWmonitor* monitor = glfwGetPrimaryMonitor()) {
        int x = 0, y = 0, w = 0, h = 0;
        float scaleX = 1.0f, scaleY = 1.0f;
        glfwGetMonitorWorkarea(monitor, &x, &y, &w, &h);
        glfwGetMonitorContentScale(monitor, &scaleX, &scaleY);
        if (w > 0 && h > 0) {
            width = std::max(1, std::min(width, int(0.92f * float(w) / std::max(scaleX, 1.0f))));
            height = std::max(1, std::min(height, int(0.88f * float(h) / std::max(scaleY, 1.0f))));
        }
    }
    window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (!window_) {
        const std::string message = glfwMessage();
        glfwTerminate();
        throw Error("cannot open an OpenGL 4.5 core window: " + message);
    }
    makeCurrent();
    glfwSwapInterval(1);
    try {
        render::loadGl(reinterpret_cast<GLADloadfunc>(glfwGetProcAddress), "GLFW window");
    } catch (...) {
        glfwDestroyWindow(window_);
        glfwTerminate();
        throw;
    }
}

GlfwContext::~GlfwContext() {
    glfwDestroyWindow(window_);
    glfwTerminate();
}

void GlfwContext::makeCurrent() { glfwMakeContextCurrent(window_); }

glm::ivec2 GlfwContext::framebufferSize() const {
    glm::ivec2 size;
    glfwGetFramebufferSize(window_, &size.x, &size.y);
    return size;
}

void GlfwContext::present() { glfwSwapBuffers(window_); }

} // namespace sdfgen::app
