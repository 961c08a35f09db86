// The undo stack of scene edits (Ctrl+Z, Ctrl+Shift+Z): models added, removed, moved, rotated,
// scaled, recoloured or hidden, the bake's settings, the slice's pose, and the field shown (loaded
// or baked). Model, setting and slice edits are found by comparing with the state the last step
// left, once no widget is active and the slice is not being dragged (a drag or a typed value is
// one step); a field that is replaced is moved into
// the step that replaced it, so undoing a load or a bake costs no copy of the field.
#include "app/viewer_state.hpp"

#include "sdfgen/memory.hpp"

#include <imgui.h>
#include <algorithm>
#include <filesystem>

namespace sdfgen::app {

namespace fs = std::filesystem;

namespace {
constexpr std::size_t kMaxSteps = 64;     // steps kept
constexpr std::size_t kMaxFieldSteps = 4; // steps that hold a field (the oldest go first)

// The memory the fields kept for undoing may hold: an eighth of the machine's, at most 2 GiB.
double fieldBudget() {
    const double memory = double(physicalMemoryBytes());
    return memory > 0.0 ? std::min(memory / 8.0, 2.0 * 1024 * 1024 * 1024) : 512.0 * 1024 * 1024;
}

double fieldBytes(const UndoEntry& e) {
    double bytes = 0.0;
    if (e.field) {
        bytes += 4.0 * double(e.field->values.size());
        for (const ChannelValues& channel : e.field->channels) bytes += 4.0 * double(channel.size());
    }
    if (e.band) bytes += 4.0 * double(e.band->values().size()) + 12.0 * double(e.band->bricks().size());
    return bytes;
}

bool sameSettings(const BakeSettings& a, const BakeSettings& b) {
    return a.res == b.res && a.padding == b.padding && a.method == b.method && a.sign == b.sign && a.rays == b.rays &&
           a.device == b.device && a.band == b.band;
}

// Drops the oldest steps (each step undoes the one after it, so only from the front) beyond the
// limits. Returns how many were dropped.
std::size_t trim(std::vector<UndoEntry>& steps) {
    std::size_t fields = 0, dropped = 0;
    double bytes = 0.0;
    for (const UndoEntry& e : steps) fields += e.hasField, bytes += fieldBytes(e);
    const double budget = fieldBudget();
    while (!steps.empty() && (steps.size() > kMaxSteps || fields > kMaxFieldSteps || bytes > budget)) {
        fields -= steps.front().hasField;
        bytes -= fieldBytes(steps.front());
        steps.erase(steps.begin());
        ++dropped;
    }
    return dropped;
}
} // namespace

// What differs between the scene and the state the last step left, in a few words.
std::string Viewer::describeEdit() const {
    if (models_.size() < committedModels_.size()) {
        for (const SceneModel& m : committedModels_) {
            bool kept = false;
            for (const SceneModel& n : models_) kept |= n.mesh == m.mesh;
            if (!kept) return "remove " + fs::path(m.mesh->source).filename().string();
        }
        return "remove a model";
    }
    if (models_.size() > committedModels_.size()) return "add " + fs::path(models_.back().mesh->source).filename().string();
    for (std::size_t i = 0; i < models_.size(); ++i) {
        const SceneModel &a = committedModels_[i], &b = models_[i];
        if (a.mesh != b.mesh) return "load " + fs::path(b.mesh->source).filename().string();
        if (a.move != b.move) return "move";
        if (a.rotate != b.rotate) return "rotate";
        if (a.scale != b.scale) return "scale";
        if (a.colour != b.colour) return "colour";
        if (a.visible != b.visible) return b.visible ? "show" : "hide";
    }
    if (!sameSettings(settings_, committedSettings_) || threads_ != committedThreads_) return "settings";
    if (slice().normal != committedSlice_.normal) return "turn the slice";
    if (slice().position != committedSlice_.position) return "move the slice";
    return "";
}

// The field shown is about to be replaced (a load, a bake, a new scene): it goes into the step
// being made, with the models and settings as they were.
void Viewer::fieldChanging(const char* what) {
    if (noUndoStep_ || fieldStep_) return;
    UndoEntry step;
    step.what = what;
    step.hasField = true;
    step.field = std::move(field_);
    field_.reset();
    step.band = band_;
    step.bandLine = bandLine_;
    step.info = fieldInfo_;
    fieldStep_ = std::move(step);
}

// Once no widget is active and no slice drag runs (or a field was replaced): one step for what
// changed since the last.
void Viewer::commitEdits() {
    const bool changed = models_ != committedModels_ || !sameSettings(settings_, committedSettings_) || threads_ != committedThreads_ ||
                         slice() != committedSlice_;
    if (!fieldStep_ && (!changed || ImGui::IsAnyItemActive() || draggingSlice())) return;
    UndoEntry step = fieldStep_ ? std::move(*fieldStep_) : UndoEntry{};
    fieldStep_.reset();
    const std::string edit = describeEdit();
    if (!edit.empty() && (step.what.empty() || step.what == "field")) step.what = edit;
    step.models = committedModels_;
    step.settings = committedSettings_;
    step.threads = committedThreads_;
    step.slice = committedSlice_;
    undo_.push_back(std::move(step));
    if (trim(undo_) > 0 && undo_.empty()) {
        // The field replaced was too large to keep: this step cannot be undone.
        setMessage(modelMessage_, Message::Level::Info, "the field replaced was too large to keep for Undo");
    }
    redo_.clear();
    committedModels_ = models_;
    committedSettings_ = settings_;
    committedThreads_ = threads_;
    committedSlice_ = slice();
    if (!debugDir_.empty()) pendingOut_ += "undo step: " + undo_.back().what + "\n";
}

// Ctrl+Z (redo: Ctrl+Shift+Z): swaps the scene with the step's, which then redoes (undoes) it.
void Viewer::undoStep(bool redo) {
    if (baking()) {
        setMessage(modelMessage_, Message::Level::Info, "nothing undone while a bake runs");
        return;
    }
    if (!savedField_.model.empty()) { // the saved field being read belongs to the model's load: undone with it
        fieldLoad_.stop();
        savedField_ = SavedFieldLoad{};
    }
    commitEdits(); // an edit not yet a step becomes one
    std::vector<UndoEntry>& from = redo ? redo_ : undo_;
    std::vector<UndoEntry>& to = redo ? undo_ : redo_;
    if (from.empty()) {
        setMessage(modelMessage_, Message::Level::Info, redo ? "nothing to redo" : "nothing to undo");
        return;
    }
    UndoEntry step = std::move(from.back());
    from.pop_back();
    std::swap(step.models, models_);
    std::swap(step.settings, settings_);
    std::swap(step.threads, threads_);
    const SlicePose shown = slice();
    scene_.sliceNormal = step.slice.normal;
    scene_.slicePosition = step.slice.position;
    step.slice = shown;
    const bool modelsChanged = step.models != models_;
    if (step.hasField) {
        std::swap(step.field, field_);
        std::swap(step.band, band_);
        std::swap(step.bandLine, bandLine_);
        std::swap(step.info, fieldInfo_);
        if (field_) scene_.setField(*field_);
        else scene_.clearField();
        ++fieldVersion_;
        probeKept_ = false;
    }
    committedModels_ = models_;
    committedSettings_ = settings_;
    committedThreads_ = threads_;
    committedSlice_ = slice();
    noUndoStep_ = true;
    if (modelsChanged) rebuildScene(false);
    else if (step.hasField) checkFieldAgainstScene();
    if (modelsChanged) {
        for (std::size_t i = 0; i < models_.size() && i < scene_.meshStyles.size(); ++i) scene_.meshStyles[i] = {models_[i].colour, models_[i].visible};
    }
    noUndoStep_ = false;
    updateTitle();
    const std::string what = step.what;
    to.push_back(std::move(step));
    trim(to);
    setMessage(modelMessage_, Message::Level::Info, std::string(redo ? "redone: " : "undone: ") + what);
}

// Undo and Redo on the panel (the same as Ctrl+Z and Ctrl+Shift+Z), each naming its step.
void Viewer::undoButtons() {
    ImGui::BeginDisabled(undo_.empty() || baking());
    if (ImGui::SmallButton("Undo")) undoStep(false);
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) {
        ImGui::SetTooltip("Ctrl+Z%s%s", undo_.empty() ? "" : ": ", undo_.empty() ? "" : undo_.back().what.c_str());
    }
    ImGui::EndDisabled();
    track("undo");
    ImGui::SameLine();
    ImGui::BeginDisabled(redo_.empty() || baking());
    if (ImGui::SmallButton("Redo")) undoStep(true);
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) {
        ImGui::SetTooltip("Ctrl+Shift+Z%s%s", redo_.empty() ? "" : ": ", redo_.empty() ? "" : redo_.back().what.c_str());
    }
    ImGui::EndDisabled();
    track("redo");
}

} // namespace sdfgen::app
