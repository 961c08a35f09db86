// The panel's Model section: loading models (any mesh format), the scene of several, their
// placement, colour and visibility, and the recent files.
#include "app/viewer_state.hpp"

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <algorithm>
#include <cstdio>
#include <filesystem>

namespace sdfgen::app {

namespace fs = std::filesystem;

namespace {
std::string describePaths(const std::vector<std::string>& paths) {
    std::string text;
    for (const std::string& p : paths) text += (text.empty() ? "" : ", ") + fs::path(p).filename().string();
    return text;
}
} // namespace

void Viewer::openModels(const std::vector<std::string>& paths, bool add) {
    if (paths.empty()) return;
    if (baking()) {
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
        if (!savedField_.model.empty()) { // the last model's saved field, still being read
            fieldLoad_.stop();
            savedField_ = SavedFieldLoad{};
        }
        fieldChanging(("load " + describePaths(paths)).c_str()); // undoing the load brings the field back too
        models_.clear();
        field_.reset();
        band_.reset();
        fieldInfo_ = FieldInfo{};
        scene_.clearField();
        ++fieldVersion_;
        // What was said about the last model and its field no longer applies.
        setMessage(fieldMessage_, Message::Level::Info, "");
        setMessage(generationMessage_, Message::Level::Info, "");
    }
    std::size_t dropped = 0;
    for (SceneModel& m : loaded) {
        dropped += m.mesh->droppedDegenerate;
        m.colour = render::meshColour(models_.size());
        models_.push_back(std::move(m));
    }
    for (const std::string& path : paths) rememberRecent(path);
    rebuildScene(true);
    std::string text = (add ? "added " : "loaded ") + describePaths(paths) + ": " + std::to_string(sceneMesh_->triangleCount()) +
                       " triangles in the scene";
    if (dropped > 0) text += " (" + std::to_string(dropped) + " zero-area triangles dropped)";
    setMessage(modelMessage_, Message::Level::Info, text);
    std::snprintf(meshPath_, sizeof(meshPath_), "%s", paths.back().c_str());
    std::snprintf(fieldPath_, sizeof(fieldPath_), "%s", fs::path(paths.back()).replace_extension(".sdf").string().c_str());
    if (!add && paths.size() == 1) loadSavedField(paths[0]);
}

// A path typed into the Model box, or picked from Recent: a model, or a field by its extension;
// either way what goes wrong is said under the Model box, where the action was taken.
void Viewer::openPathFromModel(const std::string& path) {
    if (isFieldPath(path)) {
        std::snprintf(fieldPath_, sizeof(fieldPath_), "%s", path.c_str());
        loadFieldFile(path, &modelMessage_);
    } else {
        openModels({path}, false);
    }
}

void Viewer::rememberRecent(const std::string& path) {
    if (const std::string error = recent_.add(path); !error.empty()) setMessage(modelMessage_, Message::Level::Warning, error);
}

// The scene mesh from the models and their transforms (one untransformed model is used as is),
// drawn model by model in their colours.
void Viewer::rebuildScene(bool reframe) {
    std::vector<MeshInstance> parts;
    for (const SceneModel& m : models_) parts.push_back({m.mesh.get(), m.identity() ? glm::dmat4(1.0) : m.transform()});
    if (models_.empty()) {
        sceneMesh_.reset();
        scene_.clearMesh();
    } else if (models_.size() == 1 && models_[0].identity()) {
        sceneMesh_ = models_[0].mesh;
    } else {
        std::string name;
        for (const SceneModel& m : models_) name += (name.empty() ? "" : "+") + fs::path(m.mesh->source).filename().string();
        sceneMesh_ = std::make_shared<Mesh>(mergeMeshes(parts, name));
    }
    sceneModel_ = sceneMesh_ ? std::make_shared<MeshModel>(sceneMesh_) : nullptr;
    probeKept_ = false; // a reading of the last scene
    if (models_.size() == 1 && models_[0].identity()) scene_.setMesh(*sceneMesh_);
    else if (!models_.empty()) scene_.setMeshes(parts);
    for (std::size_t i = 0; i < models_.size() && i < scene_.meshStyles.size(); ++i) scene_.meshStyles[i] = {models_[i].colour, models_[i].visible};
    ++meshVersion_;
    if (reframe) frameCamera();
    checkFieldAgainstScene();
    updateTitle();
}

void Viewer::handleDrops() {
    if (inbox_.drops.empty()) return;
    std::vector<std::string> paths;
    paths.swap(inbox_.drops);
    // Dropped onto an empty viewer: the scene; otherwise one replaces it, several are added.
    std::size_t meshes = 0;
    for (const std::string& path : paths) meshes += !isFieldPath(path);
    openPaths(paths, !models_.empty() && meshes > 1);
}

void Viewer::modelSection() {
    if (!ImGui::CollapsingHeader("Model", ImGuiTreeNodeFlags_DefaultOpen)) return;
    ImGui::SetNextItemWidth(-ImGui::CalcTextSize("Browse...").x - ImGui::GetStyle().FramePadding.x * 2 - ImGui::GetStyle().ItemSpacing.x);
    const bool enter = ImGui::InputText("##mesh", meshPath_, sizeof(meshPath_), ImGuiInputTextFlags_EnterReturnsTrue);
    track("model_path");
    ImGui::SameLine();
    if (ImGui::Button("Browse...##mesh")) fileBrowser_.open("Open a model", meshPath_, meshFormatExtensions(), "Open");
    track("model_browse");
    if (ImGui::Button("Load") || enter) openPathFromModel(meshPath_);
    track("model_load");
    ImGui::SameLine();
    if (ImGui::Button("Add to scene")) openModels({meshPath_}, true);
    track("model_add");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(-1.0f);
    if (ImGui::BeginCombo("##recent", "Recent", ImGuiComboFlags_HeightLarge)) {
        // Keys: up and down move the selection, Enter opens it, Escape closes the list.
        const int count = int(recent_.paths().size());
        if (ImGui::IsWindowAppearing()) recentSelected_ = -1;
        bool moved = false;
        if (ImGui::IsKeyPressed(GLFW_KEY_DOWN) && count > 0) recentSelected_ = std::min(recentSelected_ + 1, count - 1), moved = true;
        if (ImGui::IsKeyPressed(GLFW_KEY_UP) && count > 0) recentSelected_ = std::max(recentSelected_ - 1, 0), moved = true;
        int open = -1;
        if ((ImGui::IsKeyPressed(GLFW_KEY_ENTER) || ImGui::IsKeyPressed(GLFW_KEY_KP_ENTER)) && recentSelected_ >= 0 && recentSelected_ < count) {
            open = recentSelected_;
        }
        for (int i = 0; i < count; ++i) {
            if (ImGui::Selectable(recent_.paths()[std::size_t(i)].c_str(), i == recentSelected_)) open = i;
            if (moved && i == recentSelected_) ImGui::SetScrollHereY();
            track(("recent_" + std::to_string(i)).c_str());
        }
        if (recent_.paths().empty()) ImGui::TextDisabled("(none yet)");
        if (open >= 0) {
            const std::string path = recent_.paths()[std::size_t(open)];
            ImGui::CloseCurrentPopup();
            if (!isFieldPath(path)) std::snprintf(meshPath_, sizeof(meshPath_), "%s", path.c_str());
            openPathFromModel(path);
        } else if (ImGui::IsKeyPressed(GLFW_KEY_ESCAPE)) {
            ImGui::CloseCurrentPopup();
        }
        ImGui::EndCombo();
    }
    track("model_recent");
    messageLine("##model_message", modelMessage_);
    fieldLoadProgress(modelMessage_);

    ImGui::BeginDisabled(baking());
    int remove = -1;
    bool moved = false, styled = false;
    for (std::size_t i = 0; i < models_.size(); ++i) {
        SceneModel& m = models_[i];
        ImGui::PushID(int(i));
        // Colour and visibility on the model's row; placement inside.
        styled |= ImGui::ColorEdit3("##colour", &m.colour.x, ImGuiColorEditFlags_NoInputs | ImGuiColorEditFlags_NoLabel);
        track(("model_colour_" + std::to_string(i)).c_str());
        ImGui::SameLine();
        styled |= ImGui::Checkbox("##visible", &m.visible);
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("Show this model (it is baked either way)");
        track(("model_visible_" + std::to_string(i)).c_str());
        ImGui::SameLine();
        const std::string label = fs::path(m.mesh->source).filename().string() + " (" + std::to_string(m.mesh->triangleCount()) + " triangles)";
        const bool open = ImGui::TreeNode("##model", "%s", label.c_str());
        track(("model_" + std::to_string(i)).c_str());
        if (open) {
            const float step = float(std::max(glm::length(m.mesh->bounds.extent()) * m.mesh->unit, 1e-6)) * 0.005f; // world units
            moved |= ImGui::DragFloat3("Move", &m.move.x, step);
            moved |= ImGui::DragFloat3("Rotate", &m.rotate.x, 0.5f, -360.0f, 360.0f, "%.1f");
            moved |= ImGui::DragFloat("Scale", &m.scale, 0.005f, 1e-3f, 1e3f, "%.3f", ImGuiSliderFlags_Logarithmic);
            track(("model_scale_" + std::to_string(i)).c_str());
            m.scale = std::max(m.scale, 1e-3f);
            if (ImGui::SmallButton("Remove from scene")) remove = int(i);
            if (ImGui::IsItemHovered()) ImGui::SetTooltip("Ctrl+Z (Undo) brings it back");
            track(("model_remove_" + std::to_string(i)).c_str());
            ImGui::TreePop();
        }
        ImGui::PopID();
    }
    ImGui::EndDisabled();
    if (remove >= 0) {
        const std::string name = fs::path(models_[std::size_t(remove)].mesh->source).filename().string();
        models_.erase(models_.begin() + remove);
        setMessage(modelMessage_, Message::Level::Info, "removed " + name + " from the scene: Undo (Ctrl+Z) brings it back");
    }
    if (moved || remove >= 0) {
        rebuildScene(false);
    } else if (styled) {
        for (std::size_t i = 0; i < models_.size() && i < scene_.meshStyles.size(); ++i) scene_.meshStyles[i] = {models_[i].colour, models_[i].visible};
    }
    if (sceneMesh_) {
        // In the models' own units (the world coordinates the files use).
        const WorldBounds b = sceneMesh_->worldBounds();
        ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
        wrappedText("scene: %zu triangles, (%.4g %.4g %.4g) to (%.4g %.4g %.4g)", sceneMesh_->triangleCount(), b.min.x, b.min.y,
                           b.min.z, b.max.x, b.max.y, b.max.z);
        ImGui::PopStyleColor();
        track("scene_bounds");
        if (!debugDir_.empty()) {
            char line[160];
            std::snprintf(line, sizeof(line), "text scene_bounds %.6g %.6g %.6g %.6g %.6g %.6g\n", b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z);
            layout_ += line;
        }
    } else {
        ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
        wrappedText("no model: type a path, Browse, or drop mesh files on the window");
        ImGui::PopStyleColor();
    }
    undoButtons();
}

} // namespace sdfgen::app
