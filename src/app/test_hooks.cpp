// Hooks for the GUI test (tests/gui/test_gui.sh), active only with SDFGEN_SCREENSHOT_DIR set: the
// panel's widgets and messages in widgets.txt, screenshots on F12, the probe and the messages on
// stdout.
#include "app/viewer_state.hpp"
#include "render/image.hpp"

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_internal.h>
#include <cstdio>
#include <fstream>

namespace sdfgen::app {

// Records the last item's rectangle and whether it is fully visible in its window (drawn, not
// scrolled away or hidden while a popup is measured).
void Viewer::track(const char* name) {
    if (debugDir_.empty()) return;
    const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    const ImVec2 wp = ImGui::GetWindowPos(), ws = ImGui::GetWindowSize();
    const bool visible = a.y >= wp.y && b.y <= wp.y + ws.y && a.x >= wp.x && b.x <= wp.x + ws.x && !ImGui::GetCurrentWindowRead()->Hidden;
    char line[256];
    std::snprintf(line, sizeof(line), "%s %d %d %d %d %d\n", name, int(a.x), int(a.y), int(b.x), int(b.y), visible ? 1 : 0);
    layout_ += line;
}

// F12 saves the scene alone (scene-N.png) and the whole window (window-N.png) in the frame that
// takes it from the input queue, after the events queued before it.
void Viewer::debugScreenshot(bool sceneOnly) {
    const glm::ivec2 size = context_.framebufferSize();
    const std::string name = std::to_string(screenshots_);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    render::savePng(render::readFramebuffer(size.x, size.y), debugDir_ + (sceneOnly ? "/scene-" : "/window-") + name + ".png");
    if (sceneOnly) return;
    // The views shown, by their panel labels (spaces as underscores), then the camera.
    std::string views;
    for (const std::unique_ptr<render::View>& v : scene_.views()) views += widgetName(v->type().label) + "=" + (v->enabled ? "1 " : "0 ");
    const glm::vec3 n = scene_.sliceNormal;
    std::printf("screenshot %d: %scut=%d camera=%.3f,%.3f,%.5g slice=%.4f normal=%.5f,%.5f,%.5f target=%.5g,%.5g,%.5g\n", screenshots_++,
                views.c_str(), scene_.sliceCut, double(camera_.yaw), double(camera_.pitch), double(camera_.distance), double(scene_.slicePosition),
                double(n.x), double(n.y), double(n.z), double(camera_.target.x), double(camera_.target.y), double(camera_.target.z));
    std::fflush(stdout);
}

// The panel's widgets (name, rectangle, fully visible) and messages in widgets.txt, the probe on
// stdout, and "viewer ready" once.
void Viewer::writeDebugState() {
    if (debugDir_.empty()) return;
    if (probeValid_) {
        char line[256];
        std::snprintf(line, sizeof(line), "probe %.9g %.9g %.9g field=%.9g mesh=%.9g pointer=%d,%d\n", probe_.point.x, probe_.point.y,
                      probe_.point.z, double(probe_.fieldValue), probe_.meshDistance, probePointer_.x, probePointer_.y);
        if (line != lastProbeLine_) {
            lastProbeLine_ = line;
            std::fputs(line, stdout);
            std::fflush(stdout);
        }
    }
    if (layout_ != lastLayout_) {
        const std::string file = debugDir_ + "/widgets.txt", temporary = file + ".tmp";
        {
            std::ofstream out(temporary, std::ios::trunc);
            out << layout_ << "draws " << sceneDraws_ << "\n";
        }
        std::rename(temporary.c_str(), file.c_str());
        lastLayout_ = layout_;
    }
    // Messages are printed one frame after they were set, once widgets.txt shows the layout
    // that follows the action (an action late in a frame changes the next frame's layout).
    std::fputs(readyOut_.c_str(), stdout);
    std::fflush(stdout);
    readyOut_ = pendingOut_;
    pendingOut_.clear();
    if (!announced_) {
        std::printf("viewer ready\n"); // the GUI test waits for this before sending input
        std::fflush(stdout);
        announced_ = true;
    }
}

} // namespace sdfgen::app
