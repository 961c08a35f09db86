// The viewer: a GLFW window with the scene and a Dear ImGui panel docked on the left; generation on
// a worker thread. It draws only when something changes (input, a bake's progress, a finished
// bake) and sleeps on events otherwise.
#include "app/viewer.hpp"
#include "app/file_browser.hpp"
#include "app/generation.hpp"
#include "app/glfw_context.hpp"
#include "app/input_queue.hpp"
#include "app/probe.hpp"
#include "app/recent_files.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/field.hpp"
#include "sdfgen/field_match.hpp"
#include "sdfgen/formats.hpp"
#include "sdfgen/mesh.hpp"
#include "sdfgen/model.hpp"
#include "render/camera.hpp"
#include "render/image.hpp"
#include "render/scene.hpp"

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>
#include <glm/gtc/matrix_transform.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <unistd.h>
#include <vector>

namespace sdfgen::app {

namespace {

namespace fs = std::filesystem;

// Shortcuts handled in GLFW's key callback itself, so that a tap shorter than a frame still acts.
struct Shortcuts {
    int frameRequests = 0;
    bool quit = false;
    bool arrowHeld[4] = {false, false, false, false}; // left, right, up, down
    float arrowTap[2] = {0.0f, 0.0f};                 // degrees of yaw and pitch from taps
};

// Everything the GLFW callbacks hand to the viewer (the window's user pointer).
struct Inbox {
    InputQueue input;
    Shortcuts shortcuts;
    std::vector<std::string> drops;
    bool textInput = false; // a text box has the keyboard (last frame): F and arrows are typing
    bool cursorInside = true;
    int wake = 2;           // frames still to draw (ImGui settles one frame after an event)
};

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
    if (action == GLFW_PRESS && key == GLFW_KEY_Q && (mods & GLFW_MOD_CONTROL)) s.quit = true;
    if (in.textInput) return;
    const int arrows[4] = {GLFW_KEY_LEFT, GLFW_KEY_RIGHT, GLFW_KEY_UP, GLFW_KEY_DOWN};
    for (int a = 0; a < 4; ++a) {
        if (key != arrows[a] || action == GLFW_REPEAT) continue;
        s.arrowHeld[a] = action == GLFW_PRESS;
        if (action == GLFW_PRESS) s.arrowTap[a / 2] += (a % 2 ? 3.0f : -3.0f); // a tap turns a little
    }
    if (action == GLFW_PRESS && key == GLFW_KEY_F && mods == 0) ++s.frameRequests;
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

// A message shown right under the control that caused it, in a slot of fixed height (nothing
// below moves when it appears); the next message of the same kind replaces it, and errors stay
// until dismissed or replaced.
struct Message {
    enum class Level { Info, Warning, Error } level = Level::Info;
    std::string text;
};

std::string formatBytes(double bytes) {
    const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
    int u = 0;
    while (bytes >= 1024.0 && u < 4) {
        bytes /= 1024.0;
        ++u;
    }
    char text[32];
    std::snprintf(text, sizeof(text), "%.3g %s", bytes, units[u]);
    return text;
}

std::string lowerExtension(const std::string& path) {
    std::string e = fs::path(path).extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return e;
}

// One model of the scene, placed by its transform.
struct SceneModel {
    std::shared_ptr<const Mesh> mesh;
    glm::vec3 move{0.0f};
    glm::vec3 rotate{0.0f}; // degrees about x, then y, then z
    float scale = 1.0f;

    bool identity() const { return move == glm::vec3(0.0f) && rotate == glm::vec3(0.0f) && scale == 1.0f; }
    glm::dmat4 transform() const {
        // About the mesh's own centre, so that rotating and scaling keep it in place.
        const glm::dvec3 centre = 0.5 * (glm::dvec3(mesh->bounds.min) + glm::dvec3(mesh->bounds.max));
        glm::dmat4 m = glm::translate(glm::dmat4(1.0), centre + glm::dvec3(move));
        m = glm::rotate(m, glm::radians(double(rotate.z)), glm::dvec3(0, 0, 1));
        m = glm::rotate(m, glm::radians(double(rotate.y)), glm::dvec3(0, 1, 0));
        m = glm::rotate(m, glm::radians(double(rotate.x)), glm::dvec3(1, 0, 0));
        m = glm::scale(m, glm::dvec3(double(scale)));
        return glm::translate(m, -centre);
    }
};

// What the panel shows about the current field: the bake's or the loaded file's own figures.
struct FieldInfo {
    std::string origin;  // "baked" or "loaded from PATH"
    std::string method;  // the field's method line
    double seconds = -1; // the bake's time; < 0 for a loaded field
    double rate = 0;
    std::string signSummary;
};

class Viewer {
public:
    Viewer(GlfwContext& context, Inbox& inbox) : context_(context), inbox_(inbox) {
        debugDir_ = std::getenv("SDFGEN_SCREENSHOT_DIR") ? std::getenv("SDFGEN_SCREENSHOT_DIR") : "";
        if (const char* delay = std::getenv("SDFGEN_DEBUG_FRAME_DELAY_MS")) frameDelayMs_ = std::max(0, std::atoi(delay));
        GLint limit = 2048;
        glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &limit);
        textureLimit_ = limit;
        scene_.views.box = true;
    }

    // Opens `paths` as the scene (replacing it) or adds them; during a bake, asks first.
    void openModels(const std::vector<std::string>& paths, bool add) {
        if (paths.empty()) return;
        if (generation_.running()) {
            pendingPaths_ = paths;
            pendingAdd_ = add;
            askAboutBake_ = true;
            return;
        }
        std::vector<SceneModel> loaded;
        try {
            for (const std::string& path : paths) loaded.push_back({std::make_shared<Mesh>(sdfgen::loadMesh(path))});
        } catch (const std::exception& e) {
            setMessage(modelMessage_, Message::Level::Error, e.what());
            return;
        }
        if (!add) {
            models_.clear();
            field_.reset();
            fieldInfo_ = FieldInfo{};
            scene_.clearField();
            ++fieldVersion_;
            setMessage(fieldMessage_, Message::Level::Info, "");
        }
        std::size_t dropped = 0;
        for (SceneModel& m : loaded) {
            dropped += m.mesh->droppedDegenerate;
            models_.push_back(std::move(m));
        }
        for (const std::string& path : paths) rememberRecent(path);
        rebuildScene(true);
        std::string text = (add ? "added " : "loaded ") + describePaths(paths) + ": " + std::to_string(sceneMesh_->triangleCount()) +
                           " triangles in the scene";
        if (dropped > 0) text += " (" + std::to_string(dropped) + " zero-area triangles dropped)";
        setMessage(modelMessage_, Message::Level::Info, text);
        copyPath(meshPath_, paths.back());
        copyPath(fieldPath_, fs::path(paths.back()).replace_extension(".sdf").string());
        if (!add && paths.size() == 1) loadSavedField(paths[0]);
    }

    int run() {
        auto last = std::chrono::steady_clock::now();
        GLFWwindow* window = context_.window();
        while (!glfwWindowShouldClose(window)) {
            // Sleep until something happens; while a bake runs, wake ten times a second for its progress.
            const bool busy = !inbox_.input.empty() || inbox_.wake > 0 || arrowsHeld();
            if (busy) glfwPollEvents();
            else if (generation_.pending()) glfwWaitEventsTimeout(0.1);
            else glfwWaitEvents();
            const auto now = std::chrono::steady_clock::now();
            const float dt = std::min(std::chrono::duration<float>(now - last).count(), 0.25f);
            last = now;
            if (inbox_.shortcuts.quit) glfwSetWindowShouldClose(window, GLFW_TRUE);
            handleDrops();
            collectGeneration();

            ImGui_ImplOpenGL3_NewFrame();
            ImGui_ImplGlfw_NewFrame();
            const FrameInput input = inbox_.input.apply(window, inbox_.cursorInside);
            ImGui::NewFrame();
            sceneInput(input, dt);
            panel();
            ImGui::Render();
            inbox_.textInput = ImGui::GetIO().WantTextInput;

            drawScene();
            if (input.screenshot && !debugDir_.empty()) debugScreenshot(true);
            glViewport(0, 0, context_.framebufferSize().x, context_.framebufferSize().y);
            ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
            if (input.screenshot && !debugDir_.empty()) debugScreenshot(false);
            context_.present();
            writeDebugState();
            if (inbox_.wake > 0) --inbox_.wake;
            if (frameDelayMs_ > 0) std::this_thread::sleep_for(std::chrono::milliseconds(frameDelayMs_));
        }
        generation_.stop();
        return 0;
    }

private:
    static void copyPath(char (&buffer)[1024], const std::string& text) { std::snprintf(buffer, sizeof(buffer), "%s", text.c_str()); }

    static std::string describePaths(const std::vector<std::string>& paths) {
        std::string text;
        for (const std::string& p : paths) text += (text.empty() ? "" : ", ") + fs::path(p).filename().string();
        return text;
    }

    bool arrowsHeld() const {
        const Shortcuts& s = inbox_.shortcuts;
        return s.arrowHeld[0] || s.arrowHeld[1] || s.arrowHeld[2] || s.arrowHeld[3];
    }

    void setMessage(Message& slot, Message::Level level, const std::string& text) {
        slot = Message{level, text};
        inbox_.wake = std::max(inbox_.wake, 2); // show it (and what the action changed) next frame too
        if (!debugDir_.empty() && !text.empty()) {
            const char* kind = &slot == &modelMessage_ ? "model" : &slot == &generationMessage_ ? "generation"
                             : &slot == &fieldMessage_ ? "field" : "screenshot";
            const char* levels[] = {"info", "warning", "error"};
            pendingOut_ += std::string("message ") + kind + " " + levels[int(level)] + ": " + text + "\n";
        }
    }

    void rememberRecent(const std::string& path) {
        if (const std::string error = recent_.add(path); !error.empty()) setMessage(modelMessage_, Message::Level::Warning, error);
    }

    // The scene mesh from the models and their transforms (one untransformed model is used as is).
    void rebuildScene(bool reframe) {
        if (models_.empty()) {
            sceneMesh_.reset();
            scene_.clearMesh();
        } else if (models_.size() == 1 && models_[0].identity()) {
            sceneMesh_ = models_[0].mesh;
        } else {
            std::vector<MeshInstance> parts;
            std::string name;
            for (const SceneModel& m : models_) {
                parts.push_back({m.mesh.get(), m.transform()});
                name += (name.empty() ? "" : "+") + fs::path(m.mesh->source).filename().string();
            }
            sceneMesh_ = std::make_shared<Mesh>(mergeMeshes(parts, name));
        }
        probeModel_.reset();
        if (sceneMesh_) scene_.setMesh(*sceneMesh_);
        ++meshVersion_;
        if (reframe) frameCamera();
        checkFieldAgainstScene();
    }

    void frameCamera() {
        if (!sceneMesh_) return;
        const ImVec2 display = ImGui::GetIO().DisplaySize;
        const float freeWidth = std::max(display.x - panelWidth_, 1.0f);
        camera_.frame(sceneMesh_->worldBounds(), 1.0f, freeWidth / std::max(display.y, 1.0f));
    }

    // A loaded or baked field that no longer fits the scene (another source, or moved or added
    // models) gets a warning in the field's slot when that first happens.
    void checkFieldAgainstScene() {
        const std::string previous = fieldWarning_;
        fieldWarning_.clear();
        if (field_ && sceneMesh_) fieldWarning_ = fieldMismatch(*field_, *sceneMesh_);
        if (!fieldWarning_.empty() && fieldWarning_ != previous) {
            setMessage(fieldMessage_, Message::Level::Warning, "the field shown does not fit the scene: " + fieldWarning_);
        }
    }

    void showField(Field field, FieldInfo info) {
        scene_.setField(field);
        field_ = std::move(field);
        fieldInfo_ = std::move(info);
        ++fieldVersion_;
        checkFieldAgainstScene();
        // Show it, unless the user has chosen the views.
        render::Views& v = scene_.views;
        if (!userChoseViews_ && !v.volume && !v.raymarch && !v.slice) v.slice = true;
    }

    static std::string signSummaryOf(const Field& field) { return "sign: " + field.parameter("sign"); }

    // A field saved next to the model (MODEL.sdf) is shown at once instead of being regenerated,
    // when it was made from a file of the same name, is newer than the model and was made with the
    // panel's settings; otherwise (stale or unreadable) it is ignored.
    void loadSavedField(const std::string& meshPath) {
        const fs::path saved = fs::path(meshPath).replace_extension(".sdf");
        std::error_code ec;
        if (!fs::exists(saved, ec) || fs::last_write_time(saved, ec) < fs::last_write_time(meshPath, ec)) return;
        try {
            Field field = loadField(saved.string());
            if (fs::path(field.source).filename() != fs::path(meshPath).filename()) return;
            char padding[32];
            std::snprintf(padding, sizeof(padding), "%g", double(settings_.padding));
            if (field.method != toString(settings_.method) || field.parameter("res") != std::to_string(settings_.res) ||
                field.parameter("padding") != padding) {
                return;
            }
            FieldInfo info{"loaded from " + saved.string(), field.method, -1.0, 0.0, signSummaryOf(field)};
            showField(std::move(field), info);
            setMessage(fieldMessage_, Message::Level::Info, "the saved field " + saved.filename().string() + " was loaded with the model");
        } catch (const std::exception&) {
            // A broken saved field is not an error for loading the model: generate a new one.
        }
    }

    void loadFieldFile(const std::string& path) {
        try {
            Field field = loadField(path);
            FieldInfo info{"loaded from " + path, field.method, -1.0, 0.0, signSummaryOf(field)};
            fieldWarning_.clear();
            showField(std::move(field), info);
            rememberRecent(path);
            if (!fieldWarning_.empty()) setMessage(fieldMessage_, Message::Level::Warning, "loaded " + path + ", but " + fieldWarning_);
            else setMessage(fieldMessage_, Message::Level::Info, "loaded " + path);
        } catch (const std::exception& e) {
            setMessage(fieldMessage_, Message::Level::Error, e.what());
        }
    }

    void handleDrops() {
        if (inbox_.drops.empty()) return;
        std::vector<std::string> meshes;
        for (const std::string& path : inbox_.drops) {
            if (lowerExtension(path) == ".sdf") loadFieldFile(path);
            else meshes.push_back(path);
        }
        inbox_.drops.clear();
        // Dropped onto an empty viewer: the scene; otherwise one replaces it, several are added.
        openModels(meshes, !models_.empty() && meshes.size() > 1);
    }

    void collectGeneration() {
        std::optional<BakeResult> result;
        std::string error;
        std::vector<std::string> warnings;
        double seconds = 0.0;
        if (!generation_.collect(result, error, warnings, seconds)) return;
        inbox_.wake = std::max(inbox_.wake, 2);
        std::string warned; // the warnings, on lines after the message
        for (const std::string& warning : warnings) warned += "\nwarning: " + warning;
        if (!result) {
            setMessage(generationMessage_, error == "generation cancelled" ? Message::Level::Info : Message::Level::Error, error + warned);
            return;
        }
        try {
            const Grid& g = result->field.grid;
            FieldInfo info{"baked", result->field.method, seconds, double(g.sampleCount()) / std::max(seconds, 1e-9),
                           signSummaryOf(result->field)};
            if (result->checked) info.signSummary += " (" + result->signReason + ")\nmesh check: " + result->check.describe();
            if (!result->deviceReason.empty()) info.signSummary += "\ndevice: " + result->deviceReason;
            const std::string dims = std::to_string(g.dims.x) + "x" + std::to_string(g.dims.y) + "x" + std::to_string(g.dims.z);
            showField(std::move(result->field), info);
            setMessage(generationMessage_, warned.empty() ? Message::Level::Info : Message::Level::Warning,
                       "done: " + dims + " voxels in " + std::to_string(seconds).substr(0, 5) + " s" + warned);
        } catch (const std::exception& e) {
            setMessage(generationMessage_, Message::Level::Error, e.what());
        }
    }

    // Camera and slice input over the scene (not over the panel), from this frame's queued events.
    void sceneInput(const FrameInput& input, float dt) {
        ImGuiIO& io = ImGui::GetIO();
        // A frame's moves all come before its one button event: they drag with the buttons as
        // they were, then the press or release applies.
        const float dx = float(input.x - input.startX), dy = float(input.y - input.startY);
        const float height = std::max(io.DisplaySize.y, 1.0f);
        if (input.startX >= 0.0 && (dx != 0.0f || dy != 0.0f)) {
            if (sceneDrag_[1]) camera_.rotate(-dx * 0.3f, dy * 0.3f);
            if (sceneDrag_[2]) camera_.pan(dx / height, dy / height);
            if (sceneDrag_[0] && scene_.views.slice && field_) dragSlice(dx, dy);
        }
        for (int b = 0; b < 3; ++b) {
            if (input.pressed == b) sceneDrag_[b] = !io.WantCaptureMouse && !fileBrowser_.isOpen();
            if (input.released == b) sceneDrag_[b] = false;
        }
        if (input.pressed == 0) sliceTilt_ = (input.pressMods & GLFW_MOD_SHIFT) != 0;
        if (input.wheel != 0.0 && !io.WantCaptureMouse) camera_.zoom(float(input.wheel));

        Shortcuts& s = inbox_.shortcuts;
        if (s.frameRequests > 0) frameCamera();
        s.frameRequests = 0;
        // Arrow keys orbit at a fixed speed in degrees per second, whatever the frame rate.
        const float speed = 90.0f * dt;
        camera_.rotate(s.arrowTap[0] + (s.arrowHeld[1] - s.arrowHeld[0]) * speed, s.arrowTap[1] + (s.arrowHeld[2] - s.arrowHeld[3]) * speed);
        s.arrowTap[0] = s.arrowTap[1] = 0.0f;

        camera_.offsetX = panelWidth_ / std::max(io.DisplaySize.x, 1.0f);
        probeAt(input);
    }

    // Left-drag moves the slice along its normal (following the normal's direction on screen);
    // with Shift it tilts the plane.
    void dragSlice(float dx, float dy) {
        glm::vec3& n = scene_.sliceNormal;
        if (sliceTilt_) {
            const glm::mat4 view = camera_.view();
            const glm::vec3 right(view[0][0], view[1][0], view[2][0]), up(view[0][1], view[1][1], view[2][1]);
            glm::mat4 r = glm::rotate(glm::mat4(1.0f), glm::radians(dx * 0.4f), up);
            r = glm::rotate(r, glm::radians(dy * 0.4f), right);
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

    // The probe follows the cursor over the scene: the surface drawn under it (mesh, ray-marched
    // surface or slice; the last frame's depth), the field there and the exact nearest point.
    void probeAt(const FrameInput& input) {
        scene_.markers.clear();
        probeValid_ = false;
        if (!probeOn_ || ImGui::GetIO().WantCaptureMouse || input.x < panelWidth_ || !sceneMesh_) return;
        if (!probeModel_) probeModel_ = std::make_unique<Model>(Mesh(*sceneMesh_));
        const glm::ivec2 fb = context_.framebufferSize();
        const ImVec2 display = ImGui::GetIO().DisplaySize;
        const glm::ivec2 pixel(int(input.x * fb.x / std::max(display.x, 1.0f)), int(input.y * fb.y / std::max(display.y, 1.0f)));
        glm::vec3 point;
        if (!scene_.surfaceAt(pixel, point)) return;
        // Pixels of the grid (the plane under the model, within depth precision) are not probed.
        if (scene_.views.grid && std::abs(double(point.y) - sceneMesh_->worldBounds().min.y) < 1e-4 * double(camera_.distance)) return;
        probe_ = probe(glm::dvec3(point), field_ ? &*field_ : nullptr, probeModel_.get());
        probeValid_ = true;
        probePointer_ = glm::ivec2(int(input.x), int(input.y));
        const float r = camera_.sceneRadius * 0.02f;
        scene_.markers = {point - glm::vec3(r, 0, 0), point + glm::vec3(r, 0, 0), point - glm::vec3(0, r, 0), point + glm::vec3(0, r, 0),
                          point - glm::vec3(0, 0, r), point + glm::vec3(0, 0, r), point, glm::vec3(probe_.nearest)};
    }

    // ---- the panel ----

    void track(const char* name) {
        if (debugDir_.empty()) return;
        const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
        const ImVec2 wp = ImGui::GetWindowPos(), ws = ImGui::GetWindowSize();
        const bool visible = a.y >= wp.y && b.y <= wp.y + ws.y && a.x >= wp.x && b.x <= wp.x + ws.x;
        char line[256];
        std::snprintf(line, sizeof(line), "%s %d %d %d %d %d\n", name, int(a.x), int(a.y), int(b.x), int(b.y), visible ? 1 : 0);
        layout_ += line;
    }

    // A message slot: two lines high whatever it holds (it scrolls when longer), wrapped, with a
    // dismiss button for warnings and errors.
    void messageSlot(const char* id, Message& m) {
        const float height = ImGui::GetTextLineHeightWithSpacing() * 2.0f + 2.0f;
        ImGui::BeginChild(id, ImVec2(0.0f, height), false);
        if (!m.text.empty()) {
            const ImVec4 colours[] = {ImVec4(0.55f, 0.9f, 0.55f, 1.0f), ImVec4(1.0f, 0.8f, 0.3f, 1.0f), ImVec4(1.0f, 0.4f, 0.35f, 1.0f)};
            if (m.level != Message::Level::Info) {
                if (ImGui::SmallButton("x")) m.text.clear();
                ImGui::SameLine();
            }
            ImGui::PushStyleColor(ImGuiCol_Text, colours[int(m.level)]);
            ImGui::TextWrapped("%s", m.text.c_str());
            ImGui::PopStyleColor();
        }
        ImGui::EndChild();
        track(id);
        if (!m.text.empty() && !debugDir_.empty()) layout_ += std::string("text ") + id + " " + m.text.substr(0, m.text.find('\n')) + "\n";
    }

    bool viewCheckbox(const char* label, bool* value, const char* name) {
        const bool changed = ImGui::Checkbox(label, value);
        if (changed) userChoseViews_ = true;
        track(name);
        return changed;
    }

    void panel() {
        const ImGuiIO& io = ImGui::GetIO();
        const float scale = std::max(io.FontGlobalScale, 1.0f);
        panelWidth_ = std::clamp(std::round(io.DisplaySize.x * 0.3f), 290.0f * scale, 520.0f * scale);
        panelWidth_ = std::min(panelWidth_, io.DisplaySize.x);
        ImGui::SetNextWindowPos(ImVec2(0, 0), ImGuiCond_Always);
        ImGui::SetNextWindowSize(ImVec2(panelWidth_, io.DisplaySize.y), ImGuiCond_Always);
        ImGui::Begin("sdfgen", nullptr,
                     ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoTitleBar |
                         ImGuiWindowFlags_NoSavedSettings);
        layout_.clear();
        ImGui::PushItemWidth(-std::round(panelWidth_ * 0.42f));
        modelSection();
        generationSection();
        fieldSection();
        viewSection();
        cameraSection();
        probeSection();
        ImGui::PopItemWidth();
        // Where the pointer is over the panel, for the GUI test's scrolling.
        if (!debugDir_.empty()) {
            char line[96];
            std::snprintf(line, sizeof(line), "panel 0 0 %d %d 1\nscroll %d %d\n", int(panelWidth_), int(io.DisplaySize.y),
                          int(ImGui::GetScrollY()), int(ImGui::GetScrollMaxY()));
            layout_ += line;
        }
        ImGui::End();
        bakeQuestion();
        if (fileBrowser_.draw()) fileChosen();
    }

    void modelSection() {
        if (!ImGui::CollapsingHeader("Model", ImGuiTreeNodeFlags_DefaultOpen)) return;
        ImGui::SetNextItemWidth(-ImGui::CalcTextSize("Browse...").x - ImGui::GetStyle().FramePadding.x * 2 - ImGui::GetStyle().ItemSpacing.x);
        const bool enter = ImGui::InputText("##mesh", meshPath_, sizeof(meshPath_), ImGuiInputTextFlags_EnterReturnsTrue);
        track("model_path");
        ImGui::SameLine();
        if (ImGui::Button("Browse...##mesh")) fileBrowser_.open("Open a model", meshPath_, {".obj"}, false);
        track("model_browse");
        if (ImGui::Button("Load") || enter) openModels({meshPath_}, false);
        track("model_load");
        ImGui::SameLine();
        if (ImGui::Button("Add to scene")) openModels({meshPath_}, true);
        track("model_add");
        ImGui::SameLine();
        ImGui::SetNextItemWidth(-1.0f);
        if (ImGui::BeginCombo("##recent", "Recent", ImGuiComboFlags_HeightLarge)) {
            for (const std::string& path : recent_.paths()) {
                if (ImGui::Selectable(path.c_str())) {
                    if (lowerExtension(path) == ".sdf") {
                        copyPath(fieldPath_, path);
                        loadFieldFile(path);
                    } else {
                        copyPath(meshPath_, path);
                        openModels({path}, false);
                    }
                }
            }
            if (recent_.paths().empty()) ImGui::TextDisabled("(none yet)");
            ImGui::EndCombo();
        }
        track("model_recent");
        messageSlot("##model_message", modelMessage_);

        ImGui::BeginDisabled(generation_.running());
        int remove = -1;
        bool moved = false;
        for (std::size_t i = 0; i < models_.size(); ++i) {
            SceneModel& m = models_[i];
            ImGui::PushID(int(i));
            const std::string label = fs::path(m.mesh->source).filename().string() + " (" + std::to_string(m.mesh->triangleCount()) + " triangles)";
            const bool open = ImGui::TreeNode("##model", "%s", label.c_str());
            track(("model_" + std::to_string(i)).c_str());
            if (open) {
                const float step = std::max(glm::length(m.mesh->bounds.extent()), 1e-6f) * 0.005f;
                moved |= ImGui::DragFloat3("Move", &m.move.x, step);
                moved |= ImGui::DragFloat3("Rotate", &m.rotate.x, 0.5f, -360.0f, 360.0f, "%.1f");
                moved |= ImGui::DragFloat("Scale", &m.scale, 0.005f, 1e-3f, 1e3f, "%.3f", ImGuiSliderFlags_Logarithmic);
                m.scale = std::max(m.scale, 1e-3f);
                if (ImGui::SmallButton("Remove from scene")) remove = int(i);
                ImGui::TreePop();
            }
            ImGui::PopID();
        }
        ImGui::EndDisabled();
        if (remove >= 0) models_.erase(models_.begin() + remove);
        if (moved || remove >= 0) rebuildScene(false);
        if (sceneMesh_) {
            const Bounds& b = sceneMesh_->bounds;
            ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
            ImGui::TextWrapped("scene: %zu triangles, (%.3g %.3g %.3g) - (%.3g %.3g %.3g)", sceneMesh_->triangleCount(), double(b.min.x),
                               double(b.min.y), double(b.min.z), double(b.max.x), double(b.max.y), double(b.max.z));
            ImGui::PopStyleColor();
        } else {
            ImGui::TextDisabled("no model: type a path, Browse, or drop OBJ files on the window");
        }
    }

    // The settings' problem, or "" when Generate may run; `grid` gets the grid they describe.
    std::string validateSettings(Grid& grid) const {
        if (settings_.res < 1) return "Resolution must be at least 1 (voxels along the longest side)";
        if (settings_.res > textureLimit_) {
            return "Resolution " + std::to_string(settings_.res) + " is above this OpenGL driver's 3D texture limit of " +
                   std::to_string(textureLimit_) + ", so the field could not be shown";
        }
        if (settings_.rays < 1 || settings_.rays > 65536) return "Rays must be 1 to 65536";
        if (!(settings_.padding >= 0.0f && settings_.padding <= 100.0f)) return "Padding must be 0 to 100 (a fraction of the longest side)";
        if (threads_ < 0 || threads_ > 1024) return "Threads must be 0 (all cores) to 1024";
        if (!sceneMesh_) return "load a model first";
        try {
            grid = makeGrid(sceneMesh_->worldBounds(), settings_.res, settings_.padding);
        } catch (const std::exception& e) {
            return e.what();
        }
        return "";
    }

    void generationSection() {
        if (!ImGui::CollapsingHeader("Generation", ImGuiTreeNodeFlags_DefaultOpen)) return;
        const bool busy = generation_.running();
        ImGui::BeginDisabled(busy);
        ImGui::InputInt("Resolution", &settings_.res);
        track("resolution");
        ImGui::InputInt("Rays", &settings_.rays);
        track("rays");
        ImGui::InputDouble("Padding", &settings_.padding, 0.01, 0.1, "%.3f");
        track("padding");
        ImGui::InputInt("Threads (0 = all)", &threads_);
        track("threads");
        int method = int(settings_.method);
        ImGui::Combo("Method", &method, "rays\0exact\0brute\0");
        settings_.method = DistanceMethod(method);
        track("method");
        int sign = int(settings_.sign);
        ImGui::Combo("Sign", &sign, "default\0auto\0rays\0pseudonormal\0winding\0");
        settings_.sign = SignMethod(sign);
        track("sign");
        // The GPU device makes its own headless context current on the generation's worker thread.
        int device = int(settings_.device);
        ImGui::Combo("Device", &device, "cpu\0gpu\0auto\0");
        settings_.device = Device(device);
        track("device");
        ImGui::EndDisabled();

        Grid grid;
        const std::string problem = validateSettings(grid);
        // One line, always there: the grid the settings make, or why they cannot be used.
        const float line = ImGui::GetTextLineHeightWithSpacing() * 2.0f;
        ImGui::BeginChild("##validation", ImVec2(0, line), false);
        if (problem.empty()) {
            ImGui::TextDisabled("grid %dx%dx%d, %s", grid.dims.x, grid.dims.y, grid.dims.z, formatBytes(4.0 * double(grid.sampleCount())).c_str());
        } else {
            ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.4f, 0.35f, 1.0f));
            ImGui::TextWrapped("%s", problem.c_str());
            ImGui::PopStyleColor();
        }
        ImGui::EndChild();
        track("validation");
        if (!problem.empty() && !debugDir_.empty()) layout_ += "text validation " + problem + "\n";

        const float buttonWidth = ImGui::CalcTextSize("Generate").x + ImGui::GetStyle().FramePadding.x * 2.0f;
        if (busy) {
            if (ImGui::Button("Cancel", ImVec2(buttonWidth, 0))) generation_.cancel();
            track("cancel");
        } else {
            ImGui::BeginDisabled(!problem.empty());
            if (ImGui::Button("Generate", ImVec2(buttonWidth, 0))) {
                setMessage(generationMessage_, Message::Level::Info, "generating...");
                generation_.start(sceneMesh_, settings_, GenerationOptions{threads_});
            }
            ImGui::EndDisabled();
            track("generate");
        }
        ImGui::SameLine();
        char overlay[64];
        std::snprintf(overlay, sizeof(overlay), busy ? "%.0f%%, %.1f s" : "idle", 100.0 * generation_.progress(), generation_.elapsed());
        ImGui::ProgressBar(busy ? float(generation_.progress()) : 0.0f, ImVec2(-1.0f, 0.0f), overlay);
        messageSlot("##generation_message", generationMessage_);

        // The field's own figures, in a box of fixed height.
        ImGui::BeginChild("##stats", ImVec2(0, ImGui::GetTextLineHeightWithSpacing() * 4.0f + 4.0f), false);
        if (field_) {
            const Grid& g = field_->grid;
            if (fieldInfo_.seconds >= 0) {
                ImGui::Text("%dx%dx%d voxels, %.2f s, %.0f voxels/s", g.dims.x, g.dims.y, g.dims.z, fieldInfo_.seconds, fieldInfo_.rate);
            } else {
                ImGui::TextWrapped("%dx%dx%d voxels, %s", g.dims.x, g.dims.y, g.dims.z, fieldInfo_.origin.c_str());
            }
            ImGui::TextWrapped("method: %s\n%s", fieldInfo_.method.c_str(), fieldInfo_.signSummary.c_str());
        } else {
            ImGui::TextDisabled("no field yet: Generate, or Load one in Field");
        }
        ImGui::EndChild();
        track("stats");
        if (field_ && !debugDir_.empty()) layout_ += "text stats method " + fieldInfo_.method + (fieldInfo_.seconds >= 0 ? " baked" : " loaded") + "\n";
    }

    void fieldSection() {
        if (!ImGui::CollapsingHeader("Field", ImGuiTreeNodeFlags_DefaultOpen)) return;
        ImGui::SetNextItemWidth(-ImGui::CalcTextSize("Browse...").x - ImGui::GetStyle().FramePadding.x * 2 - ImGui::GetStyle().ItemSpacing.x);
        const bool enter = ImGui::InputText("##field", fieldPath_, sizeof(fieldPath_), ImGuiInputTextFlags_EnterReturnsTrue);
        track("field_path");
        ImGui::SameLine();
        if (ImGui::Button("Browse...##field")) fileBrowser_.open("Open or save a field", fieldPath_, {".sdf"}, true);
        track("field_browse");
        if (ImGui::Button("Save")) {
            try {
                if (!field_) throw Error("no field to save: Generate one first");
                saveField(*field_, fieldPath_);
                rememberRecent(fieldPath_);
                setMessage(fieldMessage_, Message::Level::Info, std::string("saved ") + fieldPath_);
            } catch (const std::exception& e) {
                setMessage(fieldMessage_, Message::Level::Error, e.what());
            }
        }
        track("field_save");
        ImGui::SameLine();
        if (ImGui::Button("Load##field") || enter) loadFieldFile(fieldPath_);
        track("field_load");
        messageSlot("##field_message", fieldMessage_);
    }

    void viewSection() {
        if (!ImGui::CollapsingHeader("View", ImGuiTreeNodeFlags_DefaultOpen)) return;
        render::Views& v = scene_.views;
        const float column = std::round(panelWidth_ * 0.5f);
        viewCheckbox("Grid", &v.grid, "Grid");
        ImGui::SameLine(column);
        viewCheckbox("Polygon", &v.wire, "Polygon");
        viewCheckbox("Coloured Model", &v.mesh, "Coloured_Model");
        ImGui::SameLine(column);
        viewCheckbox("SDF volume", &v.volume, "SDF_volume");
        viewCheckbox("Ray-marched", &v.raymarch, "Ray-marched");
        ImGui::SameLine(column);
        viewCheckbox("Slice", &v.slice, "Slice");
        viewCheckbox("Bounding box", &v.box, "Bounding_box");
        ImGui::SameLine(column);
        ImGui::Checkbox("See-through", &scene_.wireSeeThrough);
        track("see_through");
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("Polygon shows hidden edges too");
        ImGui::Checkbox("Headlight", &scene_.headlight);
        track("headlight");
        ImGui::SameLine(column);
        ImGui::Checkbox("Shadows + AO", &scene_.shadows);
        track("shadows");

        const float range = field_ ? scene_.effectiveColourRange() : 1.0f;
        ImGui::SliderFloat("Iso level", &scene_.iso, -range, range, "%.4g");
        track("iso");
        ImGui::SliderFloat("Volume density", &scene_.volumeDensity, 0.1f, 5.0f, "%.2f", ImGuiSliderFlags_Logarithmic);
        track("density");
        // Slice: an axis, or any orientation (dragged in the view: left-drag moves, Shift tilts).
        for (int a = 0; a < 3; ++a) {
            if (a > 0) ImGui::SameLine();
            const char* labels[] = {"Slice X", "Slice Y", "Slice Z"};
            const char* names[] = {"slice_x", "slice_y", "slice_z"};
            if (ImGui::Button(labels[a])) {
                scene_.sliceNormal = render::axisNormal(a);
                if (!v.slice) v.slice = userChoseViews_ = true;
            }
            track(names[a]);
        }
        ImGui::SliderFloat("Slice position", &scene_.slicePosition, 0.0f, 1.0f);
        track("slice_position");
        const glm::vec3 n = scene_.sliceNormal;
        ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
        ImGui::TextWrapped("normal (%.2f %.2f %.2f); in the view: left-drag moves, Shift+left-drag tilts", double(n.x), double(n.y), double(n.z));
        ImGui::PopStyleColor();
        ImGui::Combo("Colour map", &scene_.colormap, "diverging\0viridis\0grey\0");
        track("colormap");
        bool automatic = scene_.colourRange <= 0.0f;
        if (ImGui::Checkbox("Auto range", &automatic)) scene_.colourRange = automatic ? 0.0f : range;
        track("auto_range");
        ImGui::SameLine();
        ImGui::BeginDisabled(automatic);
        float shown = automatic ? range : scene_.colourRange;
        ImGui::SetNextItemWidth(-std::round(panelWidth_ * 0.2f));
        if (ImGui::DragFloat("Range", &shown, range * 0.01f, 1e-6f, 1e6f, "%.4g") && !automatic) scene_.colourRange = std::max(shown, 1e-6f);
        ImGui::EndDisabled();
        track("range");
        ImGui::Checkbox("Colour bar", &scene_.colourBar);
        track("colour_bar");
        ImGui::SameLine();
        if (ImGui::Button("Screenshot")) saveScreenshot();
        track("screenshot");
        messageSlot("##screenshot_message", screenshotMessage_);
    }

    void cameraSection() {
        if (!ImGui::CollapsingHeader("Camera", ImGuiTreeNodeFlags_DefaultOpen)) return;
        const struct {
            const char* label;
            float yaw, pitch;
        } presets[] = {{"Front", 0.0f, 0.0f}, {"Side", 90.0f, 0.0f}, {"Top", 0.0f, 89.0f}};
        for (const auto& p : presets) {
            if (ImGui::Button(p.label)) {
                camera_.yaw = p.yaw;
                camera_.pitch = p.pitch;
            }
            track(p.label);
            ImGui::SameLine();
        }
        if (ImGui::Button("Frame (F)")) frameCamera();
        track("frame");
        ImGui::SameLine();
        ImGui::Checkbox("Ortho", &camera_.orthographic);
        track("ortho");
        ImGui::SliderFloat("Yaw", &camera_.yaw, -180.0f, 180.0f, "%.1f");
        track("yaw");
        ImGui::SliderFloat("Pitch", &camera_.pitch, -89.0f, 89.0f, "%.1f");
        track("pitch");
        ImGui::DragFloat("Distance", &camera_.distance, camera_.sceneRadius * 0.01f, 1e-4f, 1e6f, "%.4g");
        track("distance");
        ImGui::DragFloat3("Target", &camera_.target.x, camera_.sceneRadius * 0.01f, 0.0f, 0.0f, "%.4g");
        track("target");
        ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
        ImGui::TextWrapped("right-drag orbit, middle-drag pan, wheel zoom, arrows orbit, F frames");
        ImGui::PopStyleColor();
    }

    void probeSection() {
        if (!ImGui::CollapsingHeader("Probe", ImGuiTreeNodeFlags_DefaultOpen)) return;
        ImGui::Checkbox("Probe under the cursor", &probeOn_);
        track("probe");
        ImGui::BeginChild("##probe_values", ImVec2(0, ImGui::GetTextLineHeightWithSpacing() * 5.0f + 4.0f), false);
        if (probeValid_) {
            const ProbeResult& p = probe_;
            ImGui::Text("at (%.4g %.4g %.4g)", p.point.x, p.point.y, p.point.z);
            if (field_) {
                ImGui::Text("field: %.5g%s", double(p.fieldValue), p.insideField ? "" : " (outside the box: clamped)");
                ImGui::Text("gradient (%.3f %.3f %.3f)", double(p.gradient.x), double(p.gradient.y), double(p.gradient.z));
            } else {
                ImGui::TextDisabled("field: none yet");
                ImGui::NewLine();
            }
            ImGui::Text("mesh: distance %.5g (exact)", p.meshDistance);
            ImGui::Text("nearest (%.4g %.4g %.4g)", p.nearest.x, p.nearest.y, p.nearest.z);
        } else {
            ImGui::TextDisabled("move the pointer over the model, the slice or the ray-marched surface");
        }
        ImGui::EndChild();
        track("probe_values");
    }

    void bakeQuestion() {
        if (askAboutBake_) {
            ImGui::OpenPopup("A bake is running");
            askAboutBake_ = false;
        }
        if (!ImGui::BeginPopupModal("A bake is running", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) return;
        ImGui::Text("Loading %s stops the bake that is running.", describePaths(pendingPaths_).c_str());
        if (ImGui::Button("Cancel the bake and load")) {
            generation_.stop();
            setMessage(generationMessage_, Message::Level::Info, "generation cancelled to load " + describePaths(pendingPaths_));
            ImGui::CloseCurrentPopup();
            openModels(pendingPaths_, pendingAdd_);
            pendingPaths_.clear();
        }
        track("bake_cancel_and_load");
        ImGui::SameLine();
        if (ImGui::Button("Keep baking")) {
            setMessage(modelMessage_, Message::Level::Info, "not loaded: the bake goes on");
            pendingPaths_.clear();
            ImGui::CloseCurrentPopup();
        }
        track("bake_keep");
        ImGui::EndPopup();
    }

    void fileChosen() {
        const std::string path = fileBrowser_.chosen();
        if (fileBrowser_.title() == "Open a model") {
            copyPath(meshPath_, path);
            openModels({path}, false);
        } else {
            copyPath(fieldPath_, path); // Save or Load it with the buttons
            setMessage(fieldMessage_, Message::Level::Info, "chose " + path + ": Save writes the field there, Load reads it");
        }
    }

    // ---- drawing ----

    // The scene is redrawn only when something it shows changed; otherwise the last image is reused.
    void drawScene() {
        const glm::ivec2 size = context_.framebufferSize();
        std::ostringstream state;
        const render::Views& v = scene_.views;
        state << size.x << ' ' << size.y << ' ' << camera_.yaw << ' ' << camera_.pitch << ' ' << camera_.distance << ' ' << camera_.target.x
              << ' ' << camera_.target.y << ' ' << camera_.target.z << ' ' << camera_.orthographic << ' ' << camera_.offsetX << ' '
              << camera_.sceneRadius << ' ' << v.grid << v.mesh << v.wire << v.volume << v.raymarch << v.slice << v.box << ' '
              << scene_.sliceNormal.x << ' ' << scene_.sliceNormal.y << ' ' << scene_.sliceNormal.z << ' ' << scene_.slicePosition << ' '
              << scene_.volumeDensity << scene_.shadows << scene_.wireSeeThrough << scene_.headlight << scene_.colourBar << ' ' << scene_.iso
              << ' ' << scene_.colormap << ' ' << scene_.colourRange << ' ' << meshVersion_ << ' ' << fieldVersion_;
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

    // The Screenshot button: the scene without the panel, at the window's size, as a PNG in the
    // working folder (sdfgen-N.png, the first free N), written atomically.
    void saveScreenshot() {
        try {
            std::error_code ec;
            fs::path path;
            for (int n = 1; n < 100000; ++n) {
                path = fs::absolute("sdfgen-" + std::to_string(n) + ".png", ec);
                if (!fs::exists(path, ec)) break;
            }
            const glm::ivec2 size = context_.framebufferSize();
            scene_.draw(camera_, size, 0);
            glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
            glReadBuffer(GL_BACK);
            render::savePng(render::readFramebuffer(size.x, size.y), path.string());
            lastSceneState_.clear();
            setMessage(screenshotMessage_, Message::Level::Info, "saved " + path.string() + " (" + std::to_string(size.x) + "x" + std::to_string(size.y) + ")");
        } catch (const std::exception& e) {
            setMessage(screenshotMessage_, Message::Level::Error, e.what());
        }
    }

    // For the GUI test (SDFGEN_SCREENSHOT_DIR set): F12 saves the scene alone (scene-N.png) and the
    // whole window (window-N.png) in the frame that takes it from the input queue, after the
    // events queued before it.
    void debugScreenshot(bool sceneOnly) {
        const glm::ivec2 size = context_.framebufferSize();
        const std::string name = std::to_string(screenshots_);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
        glReadBuffer(GL_BACK);
        render::savePng(render::readFramebuffer(size.x, size.y), debugDir_ + (sceneOnly ? "/scene-" : "/window-") + name + ".png");
        if (sceneOnly) return;
        const render::Views& v = scene_.views;
        std::printf("screenshot %d: Grid=%d Polygon=%d Coloured_Model=%d SDF_volume=%d Ray-marched=%d Slice=%d Bounding_box=%d "
                    "camera=%.3f,%.3f,%.5g slice=%.4f\n",
                    screenshots_++, v.grid, v.wire, v.mesh, v.volume, v.raymarch, v.slice, v.box, double(camera_.yaw),
                    double(camera_.pitch), double(camera_.distance), double(scene_.slicePosition));
        std::fflush(stdout);
    }

    // For the GUI test: the panel's widgets (name, rectangle, fully visible) and messages in
    // widgets.txt, the probe on stdout, and "viewer ready" once.
    void writeDebugState() {
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

    GlfwContext& context_;
    Inbox& inbox_;
    render::Scene scene_;
    render::OrbitCamera camera_;
    std::vector<SceneModel> models_;
    std::shared_ptr<const Mesh> sceneMesh_;
    std::unique_ptr<Model> probeModel_; // the scene mesh's, for the probe; built on first use
    std::optional<Field> field_;
    FieldInfo fieldInfo_;
    std::string fieldWarning_;
    Generation generation_;
    BakeSettings settings_;
    int threads_ = 0;
    int textureLimit_ = 2048;
    char meshPath_[1024] = "";
    char fieldPath_[1024] = "";
    Message modelMessage_, generationMessage_, fieldMessage_, screenshotMessage_;
    RecentFiles recent_;
    FileBrowser fileBrowser_;
    std::vector<std::string> pendingPaths_;
    bool pendingAdd_ = false, askAboutBake_ = false;
    bool userChoseViews_ = false;
    bool sceneDrag_[3] = {false, false, false};
    bool sliceTilt_ = false;
    bool probeOn_ = true, probeValid_ = false;
    ProbeResult probe_;
    glm::ivec2 probePointer_{0, 0};
    float panelWidth_ = 300.0f;
    int meshVersion_ = 0, fieldVersion_ = 0;
    std::string lastSceneState_;
    long sceneDraws_ = 0;
    // Test hooks.
    std::string debugDir_;
    int frameDelayMs_ = 0;
    int screenshots_ = 0;
    bool announced_ = false;
    std::string layout_, lastLayout_, lastProbeLine_;
    std::string pendingOut_, readyOut_; // message lines for the test, printed a frame late
};

} // namespace

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
    ImGui::GetIO().IniFilename = nullptr; // no imgui.ini dropped in the working folder
    ImGui::StyleColorsDark();
    // High-DPI monitors: scale the panel with the monitor's content scale (1 on ordinary ones).
    float scaleX = 1.0f, scaleY = 1.0f;
    glfwGetWindowContentScale(window, &scaleX, &scaleY);
    if (scaleX > 1.0f) {
        ImGui::GetStyle().ScaleAllSizes(scaleX);
        ImGui::GetIO().FontGlobalScale = scaleX;
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
        viewer.openModels(meshPaths, false);
        code = viewer.run();
    }
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    return code;
}

} // namespace sdfgen::app
