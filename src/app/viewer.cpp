// The viewer: a GLFW window with the scene and a Dear ImGui panel docked on the left; generation on
// a worker thread. It draws only when something changes (input, a bake's progress, a finished
// bake, ImGui settling after either) and sleeps on events otherwise.
#include "app/viewer.hpp"
#include "app/viewer_state.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/formats.hpp"
#include "render/font.hpp"
#include "render/image.hpp"
#include "core/runtime/file_extension.hpp"

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_internal.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <thread>

namespace sdfgen::app {

namespace fs = std::filesystem;

bool isFieldPath(const std::string& path) {
    const std::vector<std::string> fields = fieldFormatExtensions();
    return std::find(fields.begin(), fields.end(), lowerExtension(path)) != fields.end();
}

std::string widgetName(const std::string& label) {
    std::string name = label;
    std::replace(name.begin(), name.end(), ' ', '_');
    return name;
}

glm::dmat4 SceneModel::transform() const {
    // About the mesh's own centre in world coordinates (its bounds are local), so that rotating
    // and scaling keep it in place.
    const WorldBounds bounds = mesh->worldBounds();
    const glm::dvec3 centre = 0.5 * (bounds.min + bounds.max);
    glm::dmat4 m = glm::translate(glm::dmat4(1.0), centre + glm::dvec3(move));
    m = glm::rotate(m, glm::radians(double(rotate.z)), glm::dvec3(0, 0, 1));
    m = glm::rotate(m, glm::radians(double(rotate.y)), glm::dvec3(0, 1, 0));
    m = glm::rotate(m, glm::radians(double(rotate.x)), glm::dvec3(1, 0, 0));
    m = glm::scale(m, glm::dvec3(double(scale)));
    return glm::translate(m, -centre);
}

void Shortcuts::turnHeld(int a, double now) {
    if (arrowPressedAt[a] < 0.0) return;
    const double from = std::max(arrowTurnedUntil[a], arrowPressedAt[a] + kArrowHoldDelay);
    if (now > from) arrowTurn[a / 2] += float(now - from) * kArrowDegreesPerSecond * (a % 2 ? 1.0f : -1.0f);
    arrowTurnedUntil[a] = std::max(arrowTurnedUntil[a], now);
}

namespace {

Inbox& inboxOf(GLFWwindow* window) { return *static_cast<Inbox*>(glfwGetWindowUserPointer(window)); }

void onCursor(GLFWwindow* w, double x, double y) {
    Inbox& in = inboxOf(w);
    in.input.push({InputEvent::Type::Move, x, y});
    in.wake = std::max(in.wake, 2);
}
void onButton(GLFWwindow* w, int button, int action, int mods) {
    Inbox& in = inboxOf(w);
    InputEvent e{InputEvent::Type::Button};
    e.code = button;
    e.action = action;
    e.mods = mods;
    in.input.push(e);
    in.wake = std::max(in.wake, 2);
}
void onScroll(GLFWwindow* w, double x, double y) {
    Inbox& in = inboxOf(w);
    in.input.push({InputEvent::Type::Scroll, x, y});
    in.wake = std::max(in.wake, 2);
}
void onChar(GLFWwindow* w, unsigned codepoint) {
    Inbox& in = inboxOf(w);
    InputEvent e{InputEvent::Type::Char};
    e.code = int(codepoint);
    in.input.push(e);
    in.wake = std::max(in.wake, 2);
}
void onKey(GLFWwindow* w, int key, int scancode, int action, int mods) {
    Inbox& in = inboxOf(w);
    in.wake = std::max(in.wake, 2);
    if (key == GLFW_KEY_F12) {
        if (action == GLFW_PRESS) in.input.push({InputEvent::Type::Screenshot}); // in order with the clicks before it
        return;
    }
    InputEvent e{InputEvent::Type::Key};
    e.code = key;
    e.scancode = scancode;
    e.action = action;
    e.mods = mods;
    in.input.push(e);
    Shortcuts& s = in.shortcuts;
    // Shift and Caps Lock do not change what a shortcut does; Ctrl, Alt and Super do.
    const bool plain = (mods & (GLFW_MOD_CONTROL | GLFW_MOD_ALT | GLFW_MOD_SUPER)) == 0;
    if (action == GLFW_PRESS && key == GLFW_KEY_Q && (mods & GLFW_MOD_CONTROL)) s.quit = true;
    // Ctrl+Z undoes a scene edit, Ctrl+Shift+Z (or Ctrl+Y) redoes it; in a text box they are the box's.
    const bool ctrlOnly = (mods & GLFW_MOD_CONTROL) && !(mods & (GLFW_MOD_ALT | GLFW_MOD_SUPER));
    if (action != GLFW_RELEASE && ctrlOnly && !in.textInput && !in.listKeys) { // not behind a dialog
        if (key == GLFW_KEY_Z) ++((mods & GLFW_MOD_SHIFT) ? s.redoRequests : s.undoRequests);
        if (key == GLFW_KEY_Y) ++s.redoRequests;
    }
    const int arrows[4] = {GLFW_KEY_LEFT, GLFW_KEY_RIGHT, GLFW_KEY_UP, GLFW_KEY_DOWN};
    for (int a = 0; a < 4; ++a) {
        if (key != arrows[a] || action == GLFW_REPEAT) continue;
        const double now = glfwGetTime();
        if (action == GLFW_RELEASE) {
            s.turnHeld(a, now); // up to the release, however late the next frame
            s.arrowPressedAt[a] = -1.0;
        } else if (!in.textInput && !in.listKeys && plain) {
            s.arrowPressedAt[a] = s.arrowTurnedUntil[a] = now;
            s.arrowTurn[a / 2] += a % 2 ? kArrowTapDegrees : -kArrowTapDegrees;
        }
    }
    if (in.textInput || in.listKeys) return;
    if (action == GLFW_PRESS && key == GLFW_KEY_F && plain) ++s.frameRequests;
    if (action == GLFW_PRESS && key == GLFW_KEY_ESCAPE) ++s.cancelRequests;
}
void onDrop(GLFWwindow* w, int count, const char** paths) {
    Inbox& in = inboxOf(w);
    for (int i = 0; i < count; ++i) in.drops.emplace_back(paths[i]);
    in.wake = std::max(in.wake, 2);
}
void onCursorEnter(GLFWwindow* w, int entered) {
    Inbox& in = inboxOf(w);
    in.cursorInside = entered != 0;
    in.wake = std::max(in.wake, 2);
}
void onWindowChange(GLFWwindow* w, int, int) { inboxOf(w).wake = std::max(inboxOf(w).wake, 2); }
void onRefresh(GLFWwindow* w) { inboxOf(w).wake = std::max(inboxOf(w).wake, 2); }

// A hash of what ImGui drew (vertices, indices, commands), to see whether another frame changes it.
std::size_t drawDataHash(const ImDrawData* data) {
    std::size_t h = 1469598103934665603ull;
    auto mix = [&](const void* bytes, std::size_t size) {
        const auto* p = static_cast<const unsigned char*>(bytes);
        for (std::size_t i = 0; i < size; ++i) h = (h ^ p[i]) * 1099511628211ull;
    };
    if (!data) return h;
    for (int l = 0; l < data->CmdListsCount; ++l) {
        const ImDrawList* list = data->CmdLists[l];
        mix(list->VtxBuffer.Data, std::size_t(list->VtxBuffer.Size) * sizeof(ImDrawVert));
        mix(list->IdxBuffer.Data, std::size_t(list->IdxBuffer.Size) * sizeof(ImDrawIdx));
        for (const ImDrawCmd& cmd : list->CmdBuffer) mix(&cmd.ClipRect, sizeof(cmd.ClipRect));
    }
    return h;
}

} // namespace

Viewer::Viewer(GlfwContext& context, Inbox& inbox) : context_(context), inbox_(inbox) {
    debugDir_ = std::getenv("SDFGEN_SCREENSHOT_DIR") ? std::getenv("SDFGEN_SCREENSHOT_DIR") : "";
    if (const char* delay = std::getenv("SDFGEN_DEBUG_FRAME_DELAY_MS")) frameDelayMs_ = std::max(0, std::atoi(delay));
    if (const char* delay = std::getenv("SDFGEN_DEBUG_READ_DELAY_MS"); delay && !debugDir_.empty()) fieldLoad_.delayPerReportMs = std::max(0, std::atoi(delay));
    GLint limit = 2048;
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &limit);
    textureLimit_ = limit;
    scene_.view<render::BoxView>().enabled = true;
    scene_.sliceGizmoShown = true;
    if (!debugDir_.empty()) {
        fileBrowser_.onItem = [this](const std::string& name) {
            track(name.c_str());
            if (name == "browse_name") layout_ += "text browse_folder " + fileBrowser_.folder() + "\n";
        };
    }
}

void Viewer::openPaths(const std::vector<std::string>& paths, bool add) {
    std::vector<std::string> meshes;
    for (const std::string& path : paths) {
        if (!isFieldPath(path)) meshes.push_back(path);
    }
    openModels(meshes, add);
    for (const std::string& path : paths) {
        if (isFieldPath(path)) {
            std::snprintf(fieldPath_, sizeof(fieldPath_), "%s", path.c_str());
            loadFieldFile(path);
        }
    }
}

// ImGui needs more frames after an event than the event itself: a popup opened this frame is
// created next frame and shown (measured) the frame after. Draw until nothing is pending and the
// picture stops changing, at most a few frames after the last event.
bool Viewer::imguiSettling() {
    const ImGuiContext& g = *ImGui::GetCurrentContext();
    bool pending = false;
    for (const ImGuiPopupData& popup : g.OpenPopupStack) pending |= popup.Window == nullptr;
    for (const ImGuiWindow* window : g.Windows) {
        pending |= window->Active && (window->HiddenFramesCanSkipItems > 0 || window->HiddenFramesCannotSkipItems > 0 || window->Appearing);
    }
    const std::size_t hash = drawDataHash(ImGui::GetDrawData());
    const bool changed = hash != lastDrawHash_;
    lastDrawHash_ = hash;
    return (pending || changed) && ++settleFrames_ <= 8;
}

int Viewer::run() {
    GLFWwindow* window = context_.window();
    // What the command line opened is where undoing stops.
    committedModels_ = models_;
    committedSettings_ = settings_;
    committedThreads_ = threads_;
    committedSlice_ = slice();
    fieldStep_.reset();
    while (!glfwWindowShouldClose(window)) {
        // Sleep until something happens; while a bake, a field load or a comparison runs, wake ten
        // times a second for its progress.
        const bool busy = !inbox_.input.empty() || inbox_.wake > 0 || inbox_.shortcuts.arrowsHeld();
        if (busy) glfwPollEvents();
        else if (generation_.pending() || fieldLoad_.pending() || comparison_.pending()) glfwWaitEventsTimeout(0.1);
        else glfwWaitEvents();
        if (!inbox_.input.empty()) settleFrames_ = 0;
        if (inbox_.shortcuts.quit) glfwSetWindowShouldClose(window, GLFW_TRUE);
        handleDrops();
        collectGeneration();
        collectFieldLoad();
        collectComparison();

        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        const FrameInput input = inbox_.input.apply(window, inbox_.cursorInside);
        ImGui::NewFrame();
        sceneInput(input);
        for (; inbox_.shortcuts.undoRequests > 0; --inbox_.shortcuts.undoRequests) undoStep(false);
        for (; inbox_.shortcuts.redoRequests > 0; --inbox_.shortcuts.redoRequests) undoStep(true);
        if (inbox_.shortcuts.cancelRequests > 0) cancelTasks();
        inbox_.shortcuts.cancelRequests = 0;
        panel();
        sceneHint();
        probeOverlay();
        ImGui::Render();
        inbox_.textInput = ImGui::GetIO().WantTextInput;
        inbox_.listKeys = fileBrowser_.isOpen() || ImGui::IsPopupOpen("", ImGuiPopupFlags_AnyPopupId);

        drawScene();
        if (input.screenshot && !debugDir_.empty()) debugScreenshot(true);
        glViewport(0, 0, context_.framebufferSize().x, context_.framebufferSize().y);
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        if (input.screenshot && !debugDir_.empty()) debugScreenshot(false);
        context_.present();
        writeDebugState();
        if (inbox_.wake > 0) --inbox_.wake;
        if (imguiSettling()) inbox_.wake = std::max(inbox_.wake, 1);
        if (frameDelayMs_ > 0) std::this_thread::sleep_for(std::chrono::milliseconds(frameDelayMs_));
    }
    generation_.stop();
    fieldLoad_.stop();
    comparison_.stop();
    return 0;
}

// Escape: the bake, the field load and the comparison running are cancelled (each says so when it
// has stopped; the scene stays as it was).
void Viewer::cancelTasks() {
    for (BackgroundTask* task : std::initializer_list<BackgroundTask*>{&generation_, &fieldLoad_, &comparison_}) {
        if (task->running()) task->cancel();
    }
}

void Viewer::setMessage(Message& slot, Message::Level level, const std::string& text) {
    slot = Message{level, text, ++messagesSaid_};
    inbox_.wake = std::max(inbox_.wake, 2); // show it (and what the action changed) next frame too
    if (!debugDir_.empty() && !text.empty()) {
        const char* kind = &slot == &modelMessage_ ? "model" : &slot == &generationMessage_ ? "generation"
                         : &slot == &fieldMessage_ ? "field" : &slot == &sliceMessage_ ? "slice" : "screenshot";
        const char* levels[] = {"info", "warning", "error"};
        pendingOut_ += std::string("message ") + kind + " " + levels[int(level)] + ": " + text + "\n";
    }
}

// A message, wrapped to its full length, with a dismiss button for warnings and errors; nothing
// (no empty space) when there is none. An info message is greyed once another message was said
// (it is about an earlier action), not removed: nothing moves under the pointer. Warnings and
// errors keep their colour until dismissed or replaced (what they say may still hold).
void Viewer::messageLine(const char* id, Message& m) {
    if (m.text.empty()) return;
    const ImVec4 colours[] = {ImVec4(0.55f, 0.9f, 0.55f, 1.0f), ImVec4(1.0f, 0.8f, 0.3f, 1.0f), ImVec4(1.0f, 0.4f, 0.35f, 1.0f)};
    const bool stale = m.level == Message::Level::Info && m.serial != messagesSaid_;
    ImGui::PushID(id);
    ImGui::BeginGroup();
    if (m.level != Message::Level::Info) {
        if (ImGui::SmallButton("x")) m.text.clear();
        ImGui::SameLine();
    }
    ImGui::PushStyleColor(ImGuiCol_Text, stale ? ImGui::GetStyle().Colors[ImGuiCol_TextDisabled] : colours[int(m.level)]);
    wrappedText("%s", m.text.c_str());
    ImGui::PopStyleColor();
    ImGui::EndGroup();
    ImGui::PopID();
    track(id);
    if (!debugDir_.empty()) {
        layout_ += std::string("text ") + id + " " + m.text.substr(0, m.text.find('\n')) + "\n";
        if (stale) layout_ += std::string("stale ") + id + "\n";
    }
}

void Viewer::updateTitle() {
    std::string name;
    for (const SceneModel& m : models_) name += (name.empty() ? "" : " + ") + fs::path(m.mesh->source).filename().string();
    if (name.empty() && field_) name = fs::path(fieldPath_).filename().string();
    const std::string title = name.empty() ? "sdfgen" : name + " - sdfgen";
    glfwSetWindowTitle(context_.window(), title.c_str());
}

// Frames the scene, or the field's box when there is no model.
void Viewer::frameCamera() {
    WorldBounds bounds;
    if (sceneMesh_) {
        bounds = sceneMesh_->worldBounds();
    } else if (field_) {
        bounds.min = glm::dvec3(field_->grid.origin);
        bounds.max = bounds.min + glm::dvec3(field_->grid.dims) * double(field_->grid.voxel);
    } else {
        return;
    }
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    if (display.x <= 0.0f) {
        ++inbox_.shortcuts.frameRequests; // before the first frame: frame once the window's size is known
        return;
    }
    const float freeWidth = std::max(display.x - panelWidth_, 1.0f);
    camera_.frame(bounds, 1.0f, freeWidth / std::max(display.y, 1.0f));
}

// Camera and slice input over the scene (not over the panel), from this frame's queued events.
void Viewer::sceneInput(const FrameInput& input) {
    ImGuiIO& io = ImGui::GetIO();
    // The panel's width for this frame (the camera frames the part of the window it leaves free).
    const float scale = std::max(ImGui::GetFontSize() / 13.0f, 1.0f);
    panelWidth_ = std::min(std::clamp(std::round(io.DisplaySize.x * 0.3f), 290.0f * scale, 520.0f * scale), io.DisplaySize.x);
    // A resized window keeps the framing the user left (the scene area's aspect changed).
    if (io.DisplaySize.x > 0.0f && io.DisplaySize.y > 0.0f) {
        const float aspect = std::max(io.DisplaySize.x - panelWidth_, 1.0f) / io.DisplaySize.y;
        if (sceneAspect_ > 0.0f && aspect != sceneAspect_) camera_.keepFraming(sceneAspect_, aspect);
        sceneAspect_ = aspect;
    }
    // A frame's moves all come before its one button event: they drag with the buttons as
    // they were, then the press or release applies.
    const float dx = float(input.x - input.startX), dy = float(input.y - input.startY);
    const float height = std::max(io.DisplaySize.y, 1.0f);
    if (input.startX >= 0.0 && (dx != 0.0f || dy != 0.0f)) {
        if (sceneDrag_[1] || (sceneDrag_[0] && leftDrag_ == LeftDrag::Orbit)) camera_.rotate(-dx * 0.3f, dy * 0.3f);
        if (sceneDrag_[2]) camera_.pan(dx / height, dy / height);
        if (sceneDrag_[0] && leftDrag_ != LeftDrag::Orbit && scene_.view<render::SliceView>().enabled && field_) dragSlice(dx, dy);
    }
    for (int b = 0; b < 3; ++b) {
        if (input.pressed == b) sceneDrag_[b] = !io.WantCaptureMouse && !fileBrowser_.isOpen();
        if (input.released == b) sceneDrag_[b] = false;
    }
    using Part = render::SliceGizmo::Part;
    const glm::vec2 pointer(float(input.x), float(input.y));
    if (input.pressed == 0) {
        const bool slice = (input.pressMods & GLFW_MOD_CONTROL) != 0 && scene_.view<render::SliceView>().enabled && field_;
        gizmoDragged_ = slice || !sceneDrag_[0] ? Part::None : gizmoPartAt(pointer);
        leftDrag_ = gizmoDragged_ == Part::Arrow ? LeftDrag::MoveSlice
                  : gizmoDragged_ == Part::Ring  ? LeftDrag::TiltSlice
                  : !slice                       ? LeftDrag::Orbit
                  : (input.pressMods & GLFW_MOD_SHIFT) != 0 ? LeftDrag::TiltSlice
                                                            : LeftDrag::MoveSlice;
    }
    if (!sceneDrag_[0]) gizmoDragged_ = Part::None;
    // The part under the pointer (or dragged) is drawn brighter: it shows what a press grabs.
    scene_.sliceGizmoHighlight = gizmoDragged_ != Part::None ? gizmoDragged_
                               : io.WantCaptureMouse || sceneDrag_[0] || sceneDrag_[1] || sceneDrag_[2] ? Part::None
                                                                                                        : gizmoPartAt(pointer);
    if (input.wheel != 0.0 && !io.WantCaptureMouse) camera_.zoom(float(input.wheel));

    Shortcuts& s = inbox_.shortcuts;
    if (s.frameRequests > 0) frameCamera();
    s.frameRequests = 0;
    // Arrow keys: the taps and the held time since the last frame (from the key events' times, so
    // a frame after idle does not count the idle time).
    for (int a = 0; a < 4; ++a) s.turnHeld(a, glfwGetTime());
    camera_.rotate(s.arrowTurn[0], s.arrowTurn[1]);
    s.arrowTurn[0] = s.arrowTurn[1] = 0.0f;

    camera_.offsetX = panelWidth_ / std::max(io.DisplaySize.x, 1.0f);
    probeAt(input);
}

// Ctrl+left-drag moves the slice along its normal (following the normal's direction on screen);
// with Shift too it tilts the plane, 0.15 degrees a pixel (a third of a window's height: about 45):
// fine enough to aim it.
void Viewer::dragSlice(float dx, float dy) {
    glm::vec3& n = scene_.sliceNormal;
    if (leftDrag_ == LeftDrag::TiltSlice) {
        const glm::mat4 view = camera_.view();
        const glm::vec3 right(view[0][0], view[1][0], view[2][0]), up(view[0][1], view[1][1], view[2][1]);
        glm::mat4 r = glm::rotate(glm::mat4(1.0f), glm::radians(dx * 0.15f), up);
        r = glm::rotate(r, glm::radians(dy * 0.15f), right);
        n = glm::normalize(glm::vec3(r * glm::vec4(n, 0.0f)));
        return;
    }
    const glm::vec3 boxMin = scene_.fieldBoxMin(), boxSize = scene_.fieldBoxSize();
    const glm::vec3 centre = boxMin + 0.5f * boxSize;
    const float span = glm::dot(glm::abs(n), boxSize); // the box's extent along n
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    const glm::mat4 vp = camera_.projection(display.x / std::max(display.y, 1.0f)) * camera_.view();
    auto toScreen = [&](glm::vec3 p) {
        const glm::vec4 c = vp * glm::vec4(p, 1.0f);
        return glm::vec2(c.x / c.w * 0.5f * display.x, -c.y / c.w * 0.5f * display.y);
    };
    const glm::vec2 along = toScreen(centre + n * span) - toScreen(centre);
    const float length2 = glm::dot(along, along);
    if (length2 < 1.0f) return; // the normal points at the viewer: no direction to drag along
    scene_.slicePosition = std::clamp(scene_.slicePosition + glm::dot(glm::vec2(dx, dy), along) / length2, 0.0f, 1.0f);
}

bool Viewer::toPointer(glm::vec3 world, glm::vec2& pointer) const {
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    const glm::vec4 c = camera_.projection(display.x / std::max(display.y, 1.0f)) * camera_.view() * glm::vec4(world, 1.0f);
    if (c.w <= 1e-6f) return false;
    pointer = glm::vec2((c.x / c.w * 0.5f + 0.5f) * display.x, (0.5f - c.y / c.w * 0.5f) * display.y);
    return true;
}

render::SliceGizmo::Part Viewer::gizmoPartAt(glm::vec2 pointer) const {
    using Part = render::SliceGizmo::Part;
    if (!scene_.view<render::SliceView>().enabled || !field_ || pointer.x < panelWidth_ || fileBrowser_.isOpen()) return Part::None;
    const render::SliceGizmo gizmo = scene_.sliceGizmo();
    Part nearest = Part::None;
    float best = 8.0f * std::max(ImGui::GetFontSize() / 13.0f, 1.0f); // pixels: grabbing distance
    for (const Part part : {Part::Arrow, Part::Ring}) {
        const std::vector<glm::vec3> segments = gizmo.segments(part);
        for (std::size_t s = 0; s + 1 < segments.size(); s += 2) {
            glm::vec2 a, b;
            if (!toPointer(segments[s], a) || !toPointer(segments[s + 1], b)) continue;
            const glm::vec2 ab = b - a;
            const float t = glm::dot(ab, ab) > 0.0f ? std::clamp(glm::dot(pointer - a, ab) / glm::dot(ab, ab), 0.0f, 1.0f) : 0.0f;
            const float distance = glm::length(pointer - (a + t * ab));
            if (distance < best) {
                best = distance;
                nearest = part;
            }
        }
    }
    return nearest;
}

// The probe follows the cursor over the scene: the surface drawn under it (mesh, ray-marched
// surface or slice; the last frame's depth), the field there and the exact nearest point.
void Viewer::probeAt(const FrameInput& input) {
    scene_.markers.clear();
    probeValid_ = false;
    if (!probeOn_ || ImGui::GetIO().WantCaptureMouse || input.x < panelWidth_ || (!sceneMesh_ && !field_)) return;
    // The scene's model, unless a bake is running: it builds the model and its trees on its own
    // thread, which a query here would wait for (the probe then reads the field alone).
    const std::shared_ptr<const Model> model = sceneModel_ && !generation_.running() ? sceneModel_->getWithoutWaiting({}) : nullptr;
    const glm::ivec2 fb = context_.framebufferSize();
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    const glm::ivec2 pixel(int(input.x * fb.x / std::max(display.x, 1.0f)), int(input.y * fb.y / std::max(display.y, 1.0f)));
    glm::vec3 drawn;
    if (!scene_.surfaceAt(pixel, drawn)) return;
    glm::dvec3 point(drawn);
    const std::optional<glm::dvec3> marched = marchedSurfaceAt(pixel, drawn);
    if (marched) {
        point = *marched;
    } else if (scene_.view<render::GridView>().enabled && std::abs(drawn.y - scene_.gridHeight()) < 1e-4f * camera_.distance) {
        return; // pixels of the grid (the plane under the model, within depth precision) are not probed
    }
    probe_ = probe(point, field_ ? &*field_ : nullptr, model.get(), band_.get());
    probeValid_ = probeKept_ = true;
    probePointer_ = glm::ivec2(int(input.x), int(input.y));
    const float r = camera_.sceneRadius * 0.02f;
    const glm::vec3 at(point);
    scene_.markers = {at - glm::vec3(r, 0, 0), at + glm::vec3(r, 0, 0), at - glm::vec3(0, r, 0), at + glm::vec3(0, r, 0),
                      at - glm::vec3(0, 0, r), at + glm::vec3(0, 0, r)};
    if (probe_.haveMesh) scene_.markers.insert(scene_.markers.end(), {at, glm::vec3(probe_.nearest)});
}

// The ray-marched surface's point at `pixel` when that is what the pixel shows (the depth there,
// `drawn`, is the ray march's, drawn a voxel nearer than its hit, or lies behind it), on the iso
// level: the depth alone reads about a voxel off the level.
std::optional<glm::dvec3> Viewer::marchedSurfaceAt(glm::ivec2 pixel, glm::vec3 drawn) const {
    const render::RaymarchView& marched = scene_.view<render::RaymarchView>();
    if (!field_ || !marched.enabled) return std::nullopt;
    glm::vec3 origin, direction;
    if (!scene_.pixelRay(pixel, origin, direction)) return std::nullopt;
    MarchedRay ray;
    ray.origin = glm::dvec3(origin);
    ray.direction = glm::dvec3(direction);
    ray.iso = marched.iso;
    ray.cut = scene_.cutPlane();
    ray.capCut = !scene_.sectionOnCut();
    ray.maxSteps = render::raymarchSteps(scene_.fieldBoxSize(), field_->background);
    const std::optional<double> t = marchSurface(ray, *field_, band_.get());
    if (!t) return std::nullopt;
    // Something nearer than the drawn depth's voxel (and a quarter for depth precision) hides it.
    const double voxel = field_->grid.voxel;
    if (glm::dot(glm::dvec3(drawn) - ray.origin, ray.direction) < *t - 1.25 * voxel) return std::nullopt;
    return ray.origin + *t * ray.direction;
}

// The probe's values: the field's (clamped outside its box) and the distance to the mesh.
std::string Viewer::probeText(const char* separator) const {
    char text[160];
    int n = 0;
    if (field_) n += std::snprintf(text, sizeof(text), "field %.5g%s", double(probe_.fieldValue), probe_.insideField ? "" : " (clamped)");
    if (probe_.haveMesh) {
        n += std::snprintf(text + n, sizeof(text) - std::size_t(n), "%smesh %.5g (unsigned)", n ? separator : "", probe_.meshDistance);
    }
    return std::string(text, std::size_t(n));
}

// The probe's values beside the cursor (kept inside the window).
void Viewer::probeOverlay() {
    if (!probeValid_) return;
    const std::string text = probeText("\n");
    if (text.empty()) return;
    const ImVec2 size = ImGui::CalcTextSize(text.c_str());
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    const float pad = 4.0f;
    ImVec2 at(float(probePointer_.x) + 16.0f, float(probePointer_.y) + 12.0f);
    if (at.x + size.x + pad > display.x) at.x = float(probePointer_.x) - 12.0f - size.x;
    if (at.y + size.y + pad > display.y) at.y = float(probePointer_.y) - 8.0f - size.y;
    ImDrawList* draw = ImGui::GetForegroundDrawList();
    draw->AddRectFilled(ImVec2(at.x - pad, at.y - pad), ImVec2(at.x + size.x + pad, at.y + size.y + pad), IM_COL32(20, 22, 26, 210), 3.0f);
    draw->AddText(at, IM_COL32(255, 240, 120, 255), text.c_str());
}

// A line in the scene's area when models are loaded but no view draws them (Coloured Model and
// Polygon off, or every model hidden) and no field view is shown: an empty picture says why.
void Viewer::sceneHint() {
    using namespace render;
    if (!sceneMesh_) return;
    bool anyVisible = false;
    for (const SceneModel& m : models_) anyVisible |= m.visible;
    const bool modelShown = anyVisible && (scene_.view<MeshView>().enabled || scene_.view<WireView>().enabled);
    const bool fieldShown = field_ && (scene_.view<SliceView>().enabled || scene_.view<RaymarchView>().enabled || scene_.view<VolumeView>().enabled);
    if (modelShown || fieldShown) return;
    const char* text = !anyVisible ? "every model is hidden: tick a model's checkbox in Model to show it"
                                   : "Coloured Model and Polygon are off: tick one in View to see the model";
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    const float width = std::max(display.x - panelWidth_ - 40.0f, 100.0f);
    const ImVec2 size = ImGui::CalcTextSize(text, nullptr, false, width);
    const ImVec2 at(panelWidth_ + std::max(20.0f, 0.5f * (display.x - panelWidth_ - size.x)), 0.5f * (display.y - size.y));
    ImDrawList* draw = ImGui::GetBackgroundDrawList();
    draw->AddRectFilled(ImVec2(at.x - 6.0f, at.y - 4.0f), ImVec2(at.x + size.x + 6.0f, at.y + size.y + 4.0f), IM_COL32(20, 22, 26, 200), 3.0f);
    draw->AddText(nullptr, 0.0f, at, IM_COL32(230, 230, 230, 255), text, nullptr, width);
    if (!debugDir_.empty()) layout_ += std::string("text scene_hint ") + text + "\n";
}

void Viewer::panel() {
    const ImGuiIO& io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(0, 0), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(panelWidth_, io.DisplaySize.y), ImGuiCond_Always);
    ImGui::Begin("sdfgen", nullptr,
                 ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoTitleBar |
                     ImGuiWindowFlags_NoSavedSettings);
    layout_.clear();
    // The labels' column: 42% of the panel, or the longest label's width where that is more.
    const float labels = ImGui::CalcTextSize("Threads (0 = all)").x + ImGui::GetStyle().ItemInnerSpacing.x +
                         ImGui::GetStyle().ScrollbarSize + ImGui::GetStyle().WindowPadding.x;

    // The probe's reading, pinned above the scrolling sections (the last one, greyed, while the
    // pointer is elsewhere). Its two lines are always there, reading or not, so that nothing below
    // moves under a still pointer when a reading comes or goes (a bake, a load, a new scene).
    {
        const float top = ImGui::GetCursorPosY();
        const float reserved = 2.0f * ImGui::GetTextLineHeight() + ImGui::GetStyle().ItemSpacing.y;
        ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[probeValid_ ? ImGuiCol_Text : ImGuiCol_TextDisabled]);
        if (!probeOn_) ImGui::TextUnformatted("probe: off");
        else if (probeKept_) ImGui::TextWrapped("probe: %s", probeText(", ").c_str());
        else ImGui::TextUnformatted("probe: point at the scene");
        ImGui::PopStyleColor();
        track("probe_pinned");
        if (ImGui::GetCursorPosY() < top + reserved) ImGui::SetCursorPosY(top + reserved);
        ImGui::Separator();
    }
    ImGui::BeginChild("##sections");
    ImGui::PushItemWidth(-std::round(std::max(panelWidth_ * 0.42f, labels)));
    modelSection();
    generationSection();
    fieldSection();
    viewSection();
    cameraSection();
    probeSection();
    // Where the pointer is over the panel and where its scrolling part begins (below the pinned
    // probe line), for the GUI test's scrolling.
    if (!debugDir_.empty()) {
        char line[128];
        std::snprintf(line, sizeof(line), "panel 0 0 %d %d 1\nsections %d\nscroll %d %d\n", int(panelWidth_), int(io.DisplaySize.y),
                      int(ImGui::GetWindowPos().y), int(ImGui::GetScrollY()), int(ImGui::GetScrollMaxY()));
        layout_ += line;
    }
    ImGui::PopItemWidth();
    ImGui::EndChild();
    ImGui::End();
    commitEdits();
    bakeQuestion();
    overwriteQuestion();
    if (fileBrowser_.draw()) fileChosen();
}

// The scene is redrawn only when something it shows changed; otherwise the last image is reused.
void Viewer::drawScene() {
    const glm::ivec2 size = context_.framebufferSize();
    std::ostringstream state;
    state << size.x << ' ' << size.y << ' ' << camera_.yaw << ' ' << camera_.pitch << ' ' << camera_.distance << ' ' << camera_.target.x
          << ' ' << camera_.target.y << ' ' << camera_.target.z << ' ' << camera_.orthographic << ' ' << camera_.offsetX << ' '
          << camera_.sceneRadius << ' ';
    for (const std::unique_ptr<render::View>& v : scene_.views()) state << v->enabled << '(' << v->settingsKey() << ')';
    state << ' '
          << scene_.sliceNormal.x << ' ' << scene_.sliceNormal.y << ' ' << scene_.sliceNormal.z << ' ' << scene_.slicePosition << ' '
          << scene_.headlight << scene_.colourBar << ' ' << scene_.colormap << ' ' << scene_.sliceCut << ' ' << int(scene_.sliceGizmoHighlight)
          << ' ' << comparisons_ << ' ' << meshVersion_ << ' ' << fieldVersion_;
    for (const render::MeshStyle& s : scene_.meshStyles) state << ' ' << s.colour.r << ' ' << s.colour.g << ' ' << s.colour.b << s.visible;
    for (const glm::vec3& m : scene_.markers) state << ' ' << m.x << ' ' << m.y << ' ' << m.z;
    if (state.str() != lastSceneState_) {
        // The probe reads depth without its own markers in it: they are drawn without depth.
        scene_.draw(camera_, size, 0);
        lastSceneState_ = state.str();
        ++sceneDraws_;
    } else {
        scene_.present(0);
    }
}

// The Screenshot button: the scene area alone (not under the panel), at its size or the size
// chosen, as a PNG in the working folder (sdfgen-N.png, the first free N), written atomically.
void Viewer::saveScreenshot() {
    try {
        const glm::ivec2 fb = context_.framebufferSize();
        const float toPixels = float(fb.x) / std::max(ImGui::GetIO().DisplaySize.x, 1.0f);
        glm::ivec2 size(fb.x - int(std::round(panelWidth_ * toPixels)), fb.y);
        if (screenshotSize_[0] > 0 || screenshotSize_[1] > 0) size = glm::ivec2(screenshotSize_[0], screenshotSize_[1]);
        GLint limit = 0;
        glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &limit);
        if (size.x < 16 || size.y < 16 || size.x > limit || size.y > limit) {
            throw Error("the screenshot size " + std::to_string(size.x) + "x" + std::to_string(size.y) + " must be 16 to " +
                        std::to_string(limit) + " pixels a side (0 0: the scene's area)");
        }
        std::error_code ec;
        fs::path path;
        for (int n = 1; n < 100000; ++n) {
            path = fs::absolute("sdfgen-" + std::to_string(n) + ".png", ec);
            if (!fs::exists(path, ec)) break;
        }
        render::OrbitCamera camera = camera_;
        camera.offsetX = 0.0f;                                          // the scene area's own centre
        camera.keepFraming(sceneAspect_, float(size.x) / float(size.y)); // framed as in the window, at the chosen size too
        scene_.draw(camera, size, 0);
        render::savePng(scene_.image(), path.string());
        lastSceneState_.clear();
        setMessage(screenshotMessage_, Message::Level::Info, "saved " + path.string() + " (" + std::to_string(size.x) + "x" + std::to_string(size.y) + ")");
    } catch (const std::exception& e) {
        lastSceneState_.clear();
        setMessage(screenshotMessage_, Message::Level::Error, e.what());
    }
}

int runViewer(const std::vector<std::string>& meshPaths) {
    if (!haveDisplay()) {
        throw Error("no display (DISPLAY and WAYLAND_DISPLAY are unset): the viewer needs one; `sdfgen render` draws PNGs without");
    }
    GlfwContext context(1280, 720, "sdfgen");
    GLFWwindow* window = context.window();
    Inbox inbox;
    glfwSetWindowUserPointer(window, &inbox);
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;              // no imgui.ini dropped in the working folder
    io.ConfigInputTextCursorBlink = false; // a blinking cursor would keep an idle viewer drawing
    ImGui::StyleColorsDark();
    // High-DPI monitors: the panel and its font scale with the monitor's content scale.
    float scaleX = 1.0f, scaleY = 1.0f;
    glfwGetWindowContentScale(window, &scaleX, &scaleY);
    const float scale = std::max(scaleX, 1.0f);
    if (scale > 1.0f) ImGui::GetStyle().ScaleAllSizes(scale);
    const std::string& font = render::uiFontPath();
    if (font.empty() || !io.Fonts->AddFontFromFileTTF(font.c_str(), std::round(15.0f * scale))) {
        io.Fonts->AddFontDefault(); // fonts-dejavu-core missing: Dear ImGui's own, scaled
        io.FontGlobalScale = scale;
    }
    // The backend installs its callbacks (focus, cursor enter, monitors); ours then replace its
    // input callbacks and queue the events (InputQueue), forwarding them one per frame.
    ImGui_ImplGlfw_InitForOpenGL(window, true);
    ImGui_ImplOpenGL3_Init("#version 450 core");
    glfwSetCursorPosCallback(window, onCursor);
    glfwSetMouseButtonCallback(window, onButton);
    glfwSetScrollCallback(window, onScroll);
    glfwSetKeyCallback(window, onKey);
    glfwSetCharCallback(window, onChar);
    glfwSetDropCallback(window, onDrop);
    glfwSetFramebufferSizeCallback(window, onWindowChange);
    glfwSetWindowRefreshCallback(window, onRefresh);
    // Cursor enter: the backend's (it tracks the hovered window), then ours.
    static GLFWcursorenterfun backendEnter = glfwSetCursorEnterCallback(window, nullptr);
    glfwSetCursorEnterCallback(window, [](GLFWwindow* w, int entered) {
        if (backendEnter) backendEnter(w, entered);
        onCursorEnter(w, entered);
    });
    int code = 0;
    {
        Viewer viewer(context, inbox);
        viewer.openPaths(meshPaths, false);
        code = viewer.run();
    }
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    return code;
}

} // namespace sdfgen::app
