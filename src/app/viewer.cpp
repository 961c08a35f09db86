// The viewer: a GLFW window with the scene and a Dear ImGui panel; generation on a worker thread.
#include "app/viewer.hpp"
#include "app/generation.hpp"
#include "app/glfw_context.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/field.hpp"
#include "sdfgen/mesh.hpp"
#include "render/camera.hpp"
#include "render/image.hpp"
#include "render/scene.hpp"

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace sdfgen::app {

namespace {

// Events taken straight from GLFW's callbacks (installed before ImGui's, which chain to them): a
// key pressed and released within one frame still counts, and dropped files arrive here.
struct Inbox {
    std::vector<std::string> drops;
    int screenshotRequests = 0;
    bool quit = false;
};

void onDrop(GLFWwindow* window, int count, const char** paths) {
    auto* inbox = static_cast<Inbox*>(glfwGetWindowUserPointer(window));
    for (int i = 0; i < count; ++i) inbox->drops.emplace_back(paths[i]);
}

void onKey(GLFWwindow* window, int key, int, int action, int mods) {
    auto* inbox = static_cast<Inbox*>(glfwGetWindowUserPointer(window));
    if (action != GLFW_PRESS) return;
    if (key == GLFW_KEY_F12) ++inbox->screenshotRequests;
    if (key == GLFW_KEY_Q && (mods & GLFW_MOD_CONTROL)) inbox->quit = true;
}

void copyPath(char* buffer, std::size_t size, const std::string& text) {
    std::snprintf(buffer, size, "%s", text.c_str());
}

class Viewer {
public:
    Viewer(GlfwContext& context, Inbox& inbox) : context_(context), inbox_(inbox) {}

    void loadMesh(const std::string& path) {
        try {
            auto mesh = std::make_shared<Mesh>(loadObj(path));
            generation_.stop();
            scene_.setMesh(*mesh);
            scene_.clearField();
            mesh_ = mesh;
            field_.reset();
            copyPath(meshPath_, sizeof(meshPath_), path);
            copyPath(fieldPath_, sizeof(fieldPath_), std::filesystem::path(path).replace_extension(".sdf").string());
            camera_.frame(mesh_->bounds);
            error_.clear();
            status_ = "loaded " + std::to_string(mesh_->triangleCount()) + " triangles";
            loadSavedField(path);
        } catch (const std::exception& e) {
            error_ = e.what();
        }
    }

    int run() {
        const char* screenshotDir = std::getenv("SDFGEN_SCREENSHOT_DIR");
        int screenshots = 0, screenshotIn = 0;
        bool announced = false;
        auto last = std::chrono::steady_clock::now();
        while (!glfwWindowShouldClose(context_.window())) {
            glfwPollEvents();
            const auto now = std::chrono::steady_clock::now();
            const float dt = std::chrono::duration<float>(now - last).count();
            last = now;
            frameMs_ = 0.9f * frameMs_ + 0.1f * dt * 1000.0f;
            for (const std::string& path : inbox_.drops) loadMesh(path);
            inbox_.drops.clear();
            if (inbox_.quit) glfwSetWindowShouldClose(context_.window(), GLFW_TRUE);
            collectGeneration();

            ImGui_ImplOpenGL3_NewFrame();
            ImGui_ImplGlfw_NewFrame();
            ImGui::NewFrame();
            handleInput(dt);
            panel();
            ImGui::Render();

            const glm::ivec2 size = context_.framebufferSize();
            scene_.draw(camera_, size, 0);
            // For the GUI test (SDFGEN_SCREENSHOT_DIR set): F12 saves the scene alone (scene-N.png)
            // and the whole window (window-N.png) two frames later, so that a click sent just before
            // it (press and release may arrive in one frame; ImGui acts on the release) is shown.
            if (screenshotDir && inbox_.screenshotRequests > 0 && screenshotIn == 0) {
                --inbox_.screenshotRequests;
                screenshotIn = 2;
            }
            const bool shoot = screenshotIn > 0 && --screenshotIn == 0;
            const std::string name = std::to_string(screenshots);
            glReadBuffer(GL_BACK);
            if (shoot) render::savePng(render::readFramebuffer(size.x, size.y), std::string(screenshotDir) + "/scene-" + name + ".png");
            glViewport(0, 0, size.x, size.y);
            ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
            if (shoot) {
                render::savePng(render::readFramebuffer(size.x, size.y), std::string(screenshotDir) + "/window-" + name + ".png");
                const render::Views& v = scene_.views;
                std::printf("screenshot %d: Grid=%d Polygon=%d Coloured_Model=%d SDF_volume=%d Ray-marched=%d Slice=%d\n",
                            screenshots++, v.grid, v.wire, v.mesh, v.volume, v.raymarch, v.slice);
                std::fflush(stdout);
            }
            context_.present();
            if (screenshotDir && !announced) {
                std::printf("viewer ready\n"); // the GUI test waits for this before sending input
                std::fflush(stdout);
                announced = true;
            }
        }
        generation_.stop();
        return 0;
    }

private:
    // A field saved next to the model (MODEL.sdf) is shown at once instead of being regenerated,
    // when it was made from a file of the same name and is newer than the model; otherwise
    // (stale or unreadable) it is ignored.
    void loadSavedField(const std::string& meshPath) {
        namespace fs = std::filesystem;
        const fs::path saved = fs::path(meshPath).replace_extension(".sdf");
        std::error_code ec;
        if (!fs::exists(saved, ec) || fs::last_write_time(saved, ec) < fs::last_write_time(meshPath, ec)) return;
        try {
            Field field = loadFieldText(saved.string());
            if (fs::path(field.source).filename() != fs::path(meshPath).filename()) return;
            // Made with other settings than the panel's: stale, generate anew instead.
            char padding[32];
            std::snprintf(padding, sizeof(padding), "%g", double(settings_.padding));
            if (field.method != toString(settings_.method) || field.parameter("res") != std::to_string(settings_.res) ||
                field.parameter("padding") != padding) {
                return;
            }
            scene_.setField(field);
            field_ = std::move(field);
            signSummary_ = "sign: " + field_->parameter("sign");
            status_ += "; field " + saved.filename().string() + " loaded";
        } catch (const std::exception&) {
            // A broken saved field is not an error for loading the model: generate a new one.
        }
    }

    void collectGeneration() {
        std::optional<BakeResult> result;
        std::string error;
        double seconds = 0.0;
        if (!generation_.collect(result, error, seconds)) return;
        if (!result) {
            error_ = error;
            status_.clear();
            return;
        }
        try {
            scene_.setField(result->field);
            field_ = std::move(result->field);
            signSummary_ = "sign: " + field_->parameter("sign");
            if (result->checked) signSummary_ += " (" + result->signReason + ")\nmesh check: " + result->check.describe();
            if (!result->deviceReason.empty()) signSummary_ += "\ndevice: " + result->deviceReason;
            const Grid& g = field_->grid;
            lastSeconds_ = seconds;
            lastRate_ = double(g.sampleCount()) / std::max(seconds, 1e-9);
            status_ = "done: " + std::to_string(g.dims.x) + "x" + std::to_string(g.dims.y) + "x" + std::to_string(g.dims.z) +
                      " voxels; turn on SDF volume, Ray-marched or Slice to see it";
            error_.clear();
        } catch (const std::exception& e) {
            error_ = e.what();
        }
    }

    void handleInput(float dt) {
        ImGuiIO& io = ImGui::GetIO();
        if (!io.WantCaptureMouse) {
            const float height = std::max(io.DisplaySize.y, 1.0f);
            if (ImGui::IsMouseDown(ImGuiMouseButton_Right)) camera_.rotate(-io.MouseDelta.x * 0.3f, io.MouseDelta.y * 0.3f);
            if (ImGui::IsMouseDown(ImGuiMouseButton_Middle)) camera_.pan(io.MouseDelta.x / height, io.MouseDelta.y / height);
            if (io.MouseWheel != 0.0f) camera_.zoom(io.MouseWheel);
        }
        if (!io.WantCaptureKeyboard) {
            if (ImGui::IsKeyPressed(GLFW_KEY_F, false) && mesh_) camera_.frame(mesh_->bounds);
            // Arrow keys orbit at a fixed speed in degrees per second, whatever the frame rate.
            const float speed = 90.0f * dt;
            if (ImGui::IsKeyDown(GLFW_KEY_LEFT)) camera_.rotate(-speed, 0.0f);
            if (ImGui::IsKeyDown(GLFW_KEY_RIGHT)) camera_.rotate(speed, 0.0f);
            if (ImGui::IsKeyDown(GLFW_KEY_UP)) camera_.rotate(0.0f, speed);
            if (ImGui::IsKeyDown(GLFW_KEY_DOWN)) camera_.rotate(0.0f, -speed);
        }
    }

    void panel() {
        ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
        ImGui::SetNextWindowSize(ImVec2(400, 700), ImGuiCond_FirstUseEver);
        ImGui::Begin("sdfgen");
        ImGui::PushItemWidth(-140.0f);
        if (!std::getenv("SDFGEN_SCREENSHOT_DIR")) ImGui::Text("%.1f ms/frame", double(frameMs_));
        if (!error_.empty()) ImGui::TextColored(ImVec4(1.0f, 0.35f, 0.3f, 1.0f), "%s", error_.c_str());
        if (!status_.empty()) ImGui::TextColored(ImVec4(0.5f, 0.9f, 0.5f, 1.0f), "%s", status_.c_str());

        if (ImGui::CollapsingHeader("Visibility", ImGuiTreeNodeFlags_DefaultOpen)) {
            render::Views& v = scene_.views;
            ImGui::Checkbox("Grid", &v.grid);
            ImGui::Checkbox("Polygon", &v.wire);
            ImGui::Checkbox("Coloured Model", &v.mesh);
            ImGui::Checkbox("SDF volume", &v.volume);
            ImGui::Checkbox("Ray-marched", &v.raymarch);
            ImGui::Checkbox("Slice", &v.slice);
            ImGui::SliderFloat("Volume density", &scene_.volumeDensity, 0.1f, 5.0f, "%.2f", ImGuiSliderFlags_Logarithmic);
            ImGui::Checkbox("Shadows + AO", &scene_.shadows);
            ImGui::Combo("Slice axis", &scene_.sliceAxis, "x\0y\0z\0");
            ImGui::SliderFloat("Slice position", &scene_.slicePosition, 0.0f, 1.0f);
            if (!field_ && (v.volume || v.raymarch || v.slice)) ImGui::TextDisabled("(no field yet: Generate or Load one)");
        }
        if (ImGui::CollapsingHeader("Camera", ImGuiTreeNodeFlags_DefaultOpen)) {
            ImGui::SliderFloat("Yaw", &camera_.yaw, -180.0f, 180.0f);
            ImGui::SliderFloat("Pitch", &camera_.pitch, -89.0f, 89.0f);
            ImGui::DragFloat("Distance", &camera_.distance, camera_.sceneRadius * 0.01f, 1e-3f, 1e6f);
            ImGui::DragFloat3("Target", &camera_.target.x, camera_.sceneRadius * 0.01f);
            if (ImGui::Button("Frame (F)") && mesh_) camera_.frame(mesh_->bounds);
            ImGui::TextDisabled("right-drag rotate, middle-drag pan, wheel zoom");
        }
        if (ImGui::CollapsingHeader("Model", ImGuiTreeNodeFlags_DefaultOpen)) {
            ImGui::InputText("##mesh", meshPath_, sizeof(meshPath_));
            ImGui::SameLine();
            if (ImGui::Button("Load")) loadMesh(meshPath_);
            if (mesh_) {
                const Bounds& b = mesh_->bounds;
                ImGui::Text("%zu triangles", mesh_->triangleCount());
                ImGui::Text("bounds (%.3g %.3g %.3g) - (%.3g %.3g %.3g)", double(b.min.x), double(b.min.y), double(b.min.z),
                            double(b.max.x), double(b.max.y), double(b.max.z));
            } else {
                ImGui::TextDisabled("no model: type a path or drop an OBJ on the window");
            }
        }
        if (ImGui::CollapsingHeader("Generation", ImGuiTreeNodeFlags_DefaultOpen)) {
            const bool busy = generation_.running();
            ImGui::BeginDisabled(busy);
            ImGui::InputInt("Resolution", &settings_.res);
            settings_.res = std::clamp(settings_.res, 1, 2048);
            ImGui::InputInt("Rays", &settings_.rays);
            settings_.rays = std::clamp(settings_.rays, 1, 65536);
            ImGui::InputFloat("Padding", &settings_.padding, 0.01f, 0.1f, "%.3f");
            settings_.padding = std::clamp(settings_.padding, 0.0f, 100.0f);
            ImGui::InputInt("Threads (0 = all)", &threads_);
            threads_ = std::clamp(threads_, 0, 1024);
            int method = int(settings_.method);
            ImGui::Combo("Method", &method, "rays\0exact\0brute\0");
            settings_.method = DistanceMethod(method);
            int sign = int(settings_.sign);
            ImGui::Combo("Sign", &sign, "default\0auto\0rays\0pseudonormal\0winding\0");
            settings_.sign = SignMethod(sign);
            int device = int(settings_.device); // the GPU device has its own context, so it runs on the worker thread
            ImGui::Combo("Device", &device, "cpu\0gpu\0auto\0");
            settings_.device = Device(device);
            if (ImGui::Button("Generate")) {
                if (!mesh_) {
                    error_ = "load a model first";
                } else {
                    error_.clear();
                    status_ = "generating...";
                    generation_.start(mesh_, settings_, threads_);
                }
            }
            ImGui::EndDisabled();
            if (busy) {
                ImGui::SameLine();
                if (ImGui::Button("Cancel")) generation_.cancel();
                ImGui::ProgressBar(float(generation_.progress()));
                ImGui::Text("elapsed %.1f s", generation_.elapsed());
            } else if (field_) {
                const Grid& g = field_->grid;
                ImGui::Text("%dx%dx%d voxels, %.2f s, %.0f voxels/s", g.dims.x, g.dims.y, g.dims.z, lastSeconds_, lastRate_);
                if (!signSummary_.empty()) ImGui::TextWrapped("%s", signSummary_.c_str());
            }
        }
        if (ImGui::CollapsingHeader("Field", ImGuiTreeNodeFlags_DefaultOpen)) {
            ImGui::InputText("##field", fieldPath_, sizeof(fieldPath_));
            if (ImGui::Button("Save")) {
                try {
                    if (!field_) throw Error("no field to save: Generate one first");
                    saveFieldText(*field_, fieldPath_);
                    status_ = std::string("saved ") + fieldPath_;
                    error_.clear();
                } catch (const std::exception& e) {
                    error_ = e.what();
                }
            }
            ImGui::SameLine();
            if (ImGui::Button("Load##field")) {
                try {
                    Field field = loadFieldText(fieldPath_);
                    scene_.setField(field);
                    field_ = std::move(field);
                    signSummary_ = "sign: " + field_->parameter("sign");
                    status_ = std::string("loaded ") + fieldPath_;
                    error_.clear();
                } catch (const std::exception& e) {
                    error_ = e.what();
                }
            }
        }
        ImGui::PopItemWidth();
        ImGui::End();
    }

    GlfwContext& context_;
    Inbox& inbox_;
    render::Scene scene_;
    render::OrbitCamera camera_;
    std::shared_ptr<const Mesh> mesh_;
    std::optional<Field> field_;
    Generation generation_;
    BakeSettings settings_;
    int threads_ = 0;
    char meshPath_[1024] = "";
    char fieldPath_[1024] = "";
    std::string error_, status_;
    std::string signSummary_; // the last bake's sign method, auto's reason and the mesh check
    float frameMs_ = 16.0f;
    double lastSeconds_ = 0.0, lastRate_ = 0.0;
};

} // namespace

int runViewer(const std::string& meshPath) {
    if (!haveDisplay()) {
        throw Error("no display (DISPLAY and WAYLAND_DISPLAY are unset): the viewer needs one; `sdfgen render` draws PNGs without");
    }
    GlfwContext context(1280, 720, "sdfgen");
    Inbox inbox;
    glfwSetWindowUserPointer(context.window(), &inbox);
    glfwSetDropCallback(context.window(), onDrop);
    glfwSetKeyCallback(context.window(), onKey);
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr; // no imgui.ini dropped in the working folder
    ImGui::StyleColorsDark();
    // High-DPI monitors: scale the panel with the monitor's content scale (1 on ordinary ones).
    float scaleX = 1.0f, scaleY = 1.0f;
    glfwGetWindowContentScale(context.window(), &scaleX, &scaleY);
    if (scaleX > 1.0f) {
        ImGui::GetStyle().ScaleAllSizes(scaleX);
        ImGui::GetIO().FontGlobalScale = scaleX;
    }
    ImGui_ImplGlfw_InitForOpenGL(context.window(), true);
    ImGui_ImplOpenGL3_Init("#version 450 core");
    int code = 0;
    {
        Viewer viewer(context, inbox);
        if (!meshPath.empty()) viewer.loadMesh(meshPath);
        code = viewer.run();
    }
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    return code;
}

} // namespace sdfgen::app
