#include "app/input_queue.hpp"

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <cfloat>

namespace sdfgen::app {

FrameInput InputQueue::apply(GLFWwindow* window, bool cursorInside) {
    FrameInput frame;
    frame.startX = x_;
    frame.startY = y_;
    while (!events_.empty()) {
        const InputEvent e = events_.front();
        if (e.type == InputEvent::Type::Move) {
            x_ = e.x;
            y_ = e.y;
        } else if (e.type == InputEvent::Type::Char) {
            ImGui_ImplGlfw_CharCallback(window, unsigned(e.code));
        } else {
            // The frame's one discrete event.
            if (e.type == InputEvent::Type::Button && e.code >= 0 && e.code < 3) {
                down_[e.code] = e.action == GLFW_PRESS;
                (e.action == GLFW_PRESS ? frame.pressed : frame.released) = e.code;
                frame.pressMods = e.mods;
            } else if (e.type == InputEvent::Type::Scroll) {
                ImGui_ImplGlfw_ScrollCallback(window, e.x, e.y);
                frame.wheel += e.y;
            } else if (e.type == InputEvent::Type::Key) {
                ImGui_ImplGlfw_KeyCallback(window, e.code, e.scancode, e.action, e.mods);
            } else if (e.type == InputEvent::Type::Screenshot) {
                frame.screenshot = true;
            }
            events_.pop_front();
            break;
        }
        events_.pop_front();
    }
    frame.x = x_;
    frame.y = y_;
    ImGuiIO& io = ImGui::GetIO();
    io.MousePos = cursorInside && x_ >= 0.0 ? ImVec2(float(x_), float(y_)) : ImVec2(-FLT_MAX, -FLT_MAX);
    for (int b = 0; b < 3; ++b) io.MouseDown[b] = down_[b];
    return frame;
}

} // namespace sdfgen::app
