// The panel's Generation section: the bake's settings (validated), Generate and Cancel with
// progress, the field's figures, and the question asked when loading during a bake.
#include "app/viewer_state.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/run_control.hpp"
#include "sdfgen/memory.hpp"

#include <imgui.h>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <utility>
#include <vector>

namespace sdfgen::app {

namespace fs = std::filesystem;

namespace {
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
std::string formatNumber(double value) {
    char text[32];
    std::snprintf(text, sizeof(text), "%g", value);
    return text;
}
// A combo of a registry's choices (sdfgen/bake.hpp), each with its description as tooltip; the
// chosen entry's id goes into `value`.
template <class Id>
void choiceCombo(const char* label, Id& value, const std::vector<Choice<Id>>& choices) {
    const auto chosen = std::find_if(choices.begin(), choices.end(), [&](const Choice<Id>& choice) { return choice.id == value; });
    const bool open = ImGui::BeginCombo(label, chosen == choices.end() ? "" : chosen->name);
    if (!open && ImGui::IsItemHovered() && chosen != choices.end()) ImGui::SetTooltip("%s", chosen->description);
    if (!open) return;
    for (const Choice<Id>& choice : choices) {
        if (ImGui::Selectable(choice.name, choice.id == value)) value = choice.id;
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", choice.description);
    }
    ImGui::EndCombo();
}
// The panel's label of a setting that problem() names.
const char* settingLabel(const std::string& setting) {
    static const std::pair<const char*, const char*> labels[] = {{"res", "Resolution"}, {"padding", "Padding"}, {"rays", "Rays"},
                                                                 {"band", "Band"},      {"method", "Method"},   {"sign", "Sign"},
                                                                 {"device", "Device"},  {"channels", "Channels"}};
    for (const auto& [name, label] : labels) {
        if (setting == name) return label;
    }
    return "Settings";
}
} // namespace

// The settings' problem, or "" when Generate may run (with a model); `grid` gets the grid they
// describe and `bytes` the bake's memory estimate. The rules every front end shares (problem(),
// sdfgen/bake.hpp), under the panel's label of the setting to change, then the viewer's own: the
// driver's 3D texture limit and the threads. A band bake gets the band's own grid and memory
// estimate (estimateBandBakeBytes against the available memory), a dense one makeGrid's (bakeGrid).
std::string Viewer::validateSettings(Grid& grid, double& bytes) const {
    bytes = 0.0;
    if (const std::optional<SettingsProblem> refused = problem(settings_)) return std::string(settingLabel(refused->setting)) + ": " + refused->message;
    const bool banded = settings_.band > 0;
    // A band field is shown resampled to fit (render::bandDisplay); a dense one as it is.
    if (!banded && settings_.res > textureLimit_) {
        return "Resolution " + std::to_string(settings_.res) + " is above this OpenGL driver's 3D texture limit of " +
               std::to_string(textureLimit_) + ", so the field could not be shown (a band field can be)";
    }
    if (threads_ < 0 || threads_ > kMaxThreads) return "Threads must be 0 (all cores) to " + std::to_string(kMaxThreads);
    if (!sceneMesh_) return "";
    try {
        grid = bakeGrid(sceneMesh_->worldBounds(), settings_);
    } catch (const std::exception& e) {
        return e.what();
    }
    if (!banded) {
        bytes = 4.0 * double(grid.sampleCount());
        return "";
    }
    // The band's estimate reads every triangle: kept for the scene and settings it was made for.
    BandEstimate& cached = bandEstimate_;
    if (cached.meshVersion != meshVersion_ || cached.res != settings_.res || cached.padding != settings_.padding || cached.band != settings_.band) {
        cached = BandEstimate{meshVersion_, settings_.res, settings_.padding, settings_.band,
                              double(estimateBandBakeBytes(*sceneMesh_, grid, settings_.band)), double(availableMemoryBytes())};
    }
    bytes = cached.bytes;
    if (cached.available > 0.0 && cached.bytes > cached.available) {
        return "A band of " + formatNumber(settings_.band) + " voxels on grid " + std::to_string(grid.dims.x) + "x" + std::to_string(grid.dims.y) +
               "x" + std::to_string(grid.dims.z) + " needs about " + mebibytes(cached.bytes) + " but only " + mebibytes(cached.available) +
               " of memory is available";
    }
    return "";
}

void Viewer::generationSection() {
    if (!ImGui::CollapsingHeader("Generation", ImGuiTreeNodeFlags_DefaultOpen)) return;
    const bool busy = generation_.running();
    ImGui::BeginDisabled(busy);
    ImGui::InputInt("Resolution", &settings_.res);
    track("resolution");
    ImGui::InputInt("Rays", &settings_.rays);
    track("rays");
    ImGui::InputDouble("Padding", &settings_.padding, 0.01, 0.1, "%.3f");
    track("padding");
    ImGui::InputDouble("Band (0 = dense)", &settings_.band, 1.0, 1.0, "%g");
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Voxels each side of the surface with exact distances (a sparse field); 0: every voxel");
    track("band");
    ImGui::InputInt("Threads (0 = all)", &threads_);
    track("threads");
    choiceCombo("Method", settings_.method, distanceMethodChoices());
    track("method");
    choiceCombo("Sign", settings_.sign, signMethodChoices());
    track("sign");
    // The GPU device makes its own headless context current on the generation's worker thread.
    choiceCombo("Device", settings_.device, deviceChoices());
    track("device");
    ImGui::EndDisabled();

    Grid grid;
    double bytes = 0.0;
    const std::string problem = validateSettings(grid, bytes);
    // The grid the settings make, or why they cannot be used (only once there is a model to bake).
    if (!problem.empty()) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.4f, 0.35f, 1.0f));
        wrappedText("%s", problem.c_str());
        ImGui::PopStyleColor();
        track("validation");
        if (!debugDir_.empty()) layout_ += "text validation " + problem + "\n";
    } else if (sceneMesh_) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
        if (settings_.band > 0) {
            // The band bake's own estimate (estimateBandBakeBytes, as bake checks it), wrapped.
            wrappedText("grid %dx%dx%d, band of %g voxels each side, about %s", grid.dims.x, grid.dims.y, grid.dims.z, settings_.band,
                        formatBytes(bytes).c_str());
        } else {
            wrappedText("grid %dx%dx%d, %s", grid.dims.x, grid.dims.y, grid.dims.z, formatBytes(bytes).c_str());
        }
        ImGui::PopStyleColor();
        track("validation");
        if (!debugDir_.empty()) {
            char line[160];
            std::snprintf(line, sizeof(line), "text grid %dx%dx%d band %g bytes %.0f\n", grid.dims.x, grid.dims.y, grid.dims.z, settings_.band, bytes);
            layout_ += line;
        }
    }

    const float buttonWidth = ImGui::CalcTextSize("Generate").x + ImGui::GetStyle().FramePadding.x * 2.0f;
    if (busy) {
        if (ImGui::Button("Cancel", ImVec2(buttonWidth, 0))) generation_.cancel();
        track("cancel");
    } else {
        ImGui::BeginDisabled(!problem.empty() || !sceneMesh_);
        if (ImGui::Button("Generate", ImVec2(buttonWidth, 0))) {
            setMessage(generationMessage_, Message::Level::Info, "generating...");
            if (!savedField_.model.empty()) { // a field is baked instead of the saved one being read
                fieldLoad_.stop();
                setMessage(modelMessage_, Message::Level::Info, savedField_.said);
                savedField_ = SavedFieldLoad{};
            }
            generation_.start(sceneModel_, settings_, GenerationOptions{threads_});
        }
        ImGui::EndDisabled();
        if (!sceneMesh_ && ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) ImGui::SetTooltip("Load a model first");
        track("generate");
    }
    ImGui::SameLine();
    char overlay[64];
    if (!busy) std::snprintf(overlay, sizeof(overlay), "idle");
    else if (generation_.cancelled()) std::snprintf(overlay, sizeof(overlay), "cancelling, %.1f s", generation_.elapsed());
    else std::snprintf(overlay, sizeof(overlay), "%.0f%%, %.1f s", 100.0 * generation_.progress(), generation_.elapsed());
    ImGui::ProgressBar(busy ? float(generation_.progress()) : 0.0f, ImVec2(-1.0f, 0.0f), overlay);
    messageLine("##generation_message", generationMessage_);

    // The field's own figures, wrapped.
    if (field_) {
        const Grid& g = band_ ? band_->grid() : field_->grid; // a band field's own, not its resampling's
        ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
        if (fieldInfo_.seconds >= 0) {
            wrappedText("%dx%dx%d voxels, %.2f s, %.3g voxels/s", g.dims.x, g.dims.y, g.dims.z, fieldInfo_.seconds, fieldInfo_.rate);
        } else {
            wrappedText("%dx%dx%d voxels, %s", g.dims.x, g.dims.y, g.dims.z, fieldInfo_.origin.c_str());
        }
        wrappedText("method: %s\n%s", fieldInfo_.method.c_str(), fieldInfo_.signSummary.c_str());
        if (band_) wrappedText("%s", bandLine_.c_str());
        ImGui::PopStyleColor();
        track("stats");
        if (!debugDir_.empty()) {
            layout_ += "text stats method " + fieldInfo_.method + (fieldInfo_.seconds >= 0 ? " baked" : " loaded") + "\n";
            if (band_) layout_ += "text band " + bandLine_ + "\n";
        }
    }
}

void Viewer::collectGeneration() {
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
        const FieldHeader& baked = result->field.header();
        const Grid& g = baked.grid;
        FieldInfo info{"baked", baked.method, seconds, double(g.sampleCount()) / std::max(seconds, 1e-9), signSummaryOf(baked)};
        if (result->checked) info.signSummary += " (" + result->signReason + ")\nmesh check: " + result->check.describe();
        if (!result->deviceReason.empty()) info.signSummary += "\ndevice: " + result->deviceReason;
        const std::string dims = std::to_string(g.dims.x) + "x" + std::to_string(g.dims.y) + "x" + std::to_string(g.dims.z);
        if (result->field.isBand()) {
            showBand(std::move(result->field.band()), info);
        } else {
            showField(std::move(result->field.dense()), info);
        }
        setMessage(fieldMessage_, Message::Level::Info, "");
        char text[160];
        std::snprintf(text, sizeof(text), "done: %s voxels in %.2f s", dims.c_str(), seconds);
        setMessage(generationMessage_, warned.empty() ? Message::Level::Info : Message::Level::Warning, text + warned);
    } catch (const std::exception& e) {
        setMessage(generationMessage_, Message::Level::Error, e.what());
    }
}

void Viewer::bakeQuestion() {
    if (askAboutBake_) {
        ImGui::OpenPopup("A bake is running");
        askAboutBake_ = false;
    }
    if (!ImGui::BeginPopupModal("A bake is running", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) return;
    std::string names;
    for (const std::string& p : pendingPaths_) names += (names.empty() ? "" : ", ") + fs::path(p).filename().string();
    ImGui::Text("Loading %s stops the bake that is running.", names.c_str());
    if (ImGui::Button("Cancel the bake and load")) {
        // Not waited for: a bake notices Cancel soon, but not inside one step (allocating a res-400
        // grid takes seconds on a busy machine), and the window stays live meanwhile.
        generation_.cancel();
        setMessage(generationMessage_, Message::Level::Info, "generation cancelled to load " + names);
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

} // namespace sdfgen::app
