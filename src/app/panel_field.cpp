// The panel's Field section: saving and loading fields in every format, exporting the iso-surface,
// comparing with another field; and what the panel knows about the field shown.
#include "app/viewer_state.hpp"
#include "sdfgen/surface.hpp"
#include "render/band_display.hpp"
#include "sdfgen/compare.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/field_match.hpp"
#include "sdfgen/formats.hpp"

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <cstdio>
#include <filesystem>

namespace sdfgen::app {

namespace fs = std::filesystem;

std::string signSummaryOf(const FieldHeader& field) {
    const std::string sign = field.parameter("sign");
    return "sign: " + (sign.empty() ? std::string("not recorded in the file") : sign);
}

namespace {
// A .npy holds the values only: its loader places them with unit voxels at the origin and an
// unknown method and source.
bool hasNoGrid(const Field& field) { return field.source.empty() && field.method == "unknown"; }
} // namespace

// A loaded or baked field that no longer fits the scene (another source, or moved or added
// models) gets a warning in the field's slot when that first happens.
void Viewer::checkFieldAgainstScene() {
    const std::string previous = fieldWarning_;
    fieldWarning_.clear();
    if (field_ && sceneMesh_) fieldWarning_ = hasNoGrid(*field_) ? "" : fieldMismatch(*field_, *sceneMesh_);
    if (!fieldWarning_.empty() && fieldWarning_ != previous) {
        setMessage(fieldMessage_, Message::Level::Warning, "the field shown does not fit the scene: " + fieldWarning_);
    }
}

void Viewer::showField(Field field, FieldInfo info) {
    // The field it replaces goes into the undo step (a load or a bake, undone as one).
    const std::string loadedFrom = "loaded from ";
    const std::string source = info.origin.compare(0, loadedFrom.size(), loadedFrom) == 0 ? info.origin.substr(loadedFrom.size()) : info.origin;
    fieldChanging(info.origin == "baked" ? "bake" : ("load " + fs::path(source).filename().string()).c_str());
    scene_.setField(field);
    field_ = std::make_shared<const Field>(std::move(field));
    band_.reset();
    bandLine_.clear();
    fieldInfo_ = std::move(info);
    ++fieldVersion_;
    probeKept_ = false; // a reading of the last field
    checkFieldAgainstScene();
    // Show it, unless the user has chosen the views.
    using namespace render;
    if (!userChoseViews_ && !scene_.view<VolumeView>().enabled && !scene_.view<RaymarchView>().enabled) scene_.view<SliceView>().enabled = true;
    if (!sceneMesh_) frameCamera(); // nothing else to frame
    updateTitle();
}

// A band field is shown from a dense resampling that fits the GPU (render::bandDisplay) and kept
// for the probe's exact values and for saving.
void Viewer::showBand(SparseField band, FieldInfo info) {
    RunControl control;
    control.threads = threads_;
    render::BandDisplay shown = render::bandDisplay(band, textureLimit_, control);
    showBand(std::move(band), std::move(shown.field), std::move(shown.line), std::move(info));
}

void Viewer::showBand(SparseField band, Field shown, std::string line, FieldInfo info) {
    showField(std::move(shown), std::move(info));
    band_ = std::make_shared<const SparseField>(std::move(band));
    bandLine_ = std::move(line);
}

// A field saved next to the model (MODEL.sdf) is shown instead of being regenerated, when it was
// made from a file of the same name, is newer than the model and was made with the panel's
// settings. It is read in the background as every field is (the model is shown at once), under
// the Model section where the model was opened; what it holds is checked once it is read.
void Viewer::loadSavedField(const std::string& meshPath) {
    const fs::path saved = fs::path(meshPath).replace_extension(".sdf");
    std::error_code ec;
    if (!fs::exists(saved, ec) || fs::last_write_time(saved, ec) < fs::last_write_time(meshPath, ec)) return;
    const std::string said = modelMessage_.text;
    loadFieldFile(saved.string(), &modelMessage_);
    setMessage(modelMessage_, Message::Level::Info, said + "; reading the field saved beside it, " + saved.filename().string() + "...");
    savedField_ = SavedFieldLoad{meshPath, said};
}

namespace {
// Why a field saved beside `meshPath` is not the one the panel's settings would bake ("" when it is).
std::string savedFieldMismatch(const FieldHeader& field, const std::string& meshPath, const BakeSettings& settings) {
    if (fs::path(field.source).filename() != fs::path(meshPath).filename()) return "it was made from " + fs::path(field.source).filename().string();
    char padding[32];
    std::snprintf(padding, sizeof(padding), "%g", double(settings.padding));
    if (field.method != toString(settings.method) || field.parameter("res") != std::to_string(settings.res) || field.parameter("padding") != padding) {
        return "it was made with other settings (" + field.method + " res " + field.parameter("res") + " padding " + field.parameter("padding") + ")";
    }
    return "";
}
} // namespace

// The saved field read: shown when it fits the model and the settings, as part of the model's
// load (that step's undo brings back the field before it too); otherwise the model stays without
// a field, and the Model section says why.
void Viewer::collectSavedField(std::optional<LoadedField> loaded, const std::string& error) {
    const std::string said = savedField_.said + "; the field saved beside it, " + fs::path(fieldLoad_.path()).filename().string() + ", ";
    if (!loaded) {
        if (error == "cancelled") setMessage(modelMessage_, Message::Level::Info, said + "was not loaded (cancelled)");
        else setMessage(modelMessage_, Message::Level::Warning, said + "could not be read: " + error);
        return;
    }
    const std::string mismatch = loaded->band ? savedFieldMismatch(loaded->band->header(), savedField_.model, settings_)
                                              : savedFieldMismatch(*loaded->field, savedField_.model, settings_);
    if (!mismatch.empty()) {
        setMessage(modelMessage_, Message::Level::Info, said + "is not shown: " + mismatch + "; Generate makes one");
        return;
    }
    const std::string origin = "loaded from " + fieldLoad_.path();
    noUndoStep_ = true; // the field completes the model's load, whose step holds the field before it
    if (loaded->band) {
        FieldInfo info{origin, loaded->band->method, -1.0, 0.0, "sign: " + loaded->band->parameter("sign")};
        showBand(std::move(*loaded->band), std::move(*loaded->field), std::move(loaded->bandLine), info);
    } else {
        FieldInfo info{origin, loaded->field->method, -1.0, 0.0, signSummaryOf(*loaded->field)};
        showField(std::move(*loaded->field), info);
    }
    noUndoStep_ = false;
    setMessage(modelMessage_, Message::Level::Info, said + "is shown");
}

// Every field file the user opens is read on a background thread (FieldLoad): the window stays
// live, the section the load was asked in shows its progress and a Cancel, and the scene changes
// only when the field has been read. A load asked for while one runs replaces it.
void Viewer::loadFieldFile(const std::string& path, Message* slot) {
    Message& here = slot ? *slot : fieldMessage_;
    if (fieldLoad_.pending()) setMessage(*loadSlot_, Message::Level::Info, "stopped loading " + fieldLoad_.path() + " to load " + path);
    savedField_ = SavedFieldLoad{};
    loadSlot_ = &here;
    fieldLoad_.start(path, threads_, textureLimit_);
    setMessage(here, Message::Level::Info, "loading " + path + "...");
}

void Viewer::taskProgress(BackgroundTask& task, const char* doing, const char* name) {
    const std::string id = name;
    const float buttonWidth = ImGui::CalcTextSize("Cancel").x + ImGui::GetStyle().FramePadding.x * 2.0f;
    if (ImGui::Button(("Cancel##" + id).c_str(), ImVec2(buttonWidth, 0))) task.cancel();
    track((id + "_cancel").c_str());
    ImGui::SameLine();
    char overlay[64];
    if (task.cancelled()) std::snprintf(overlay, sizeof(overlay), "cancelling, %.1f s", task.elapsed());
    else std::snprintf(overlay, sizeof(overlay), "%s: %.0f%%, %.1f s", doing, 100.0 * task.progress(), task.elapsed());
    ImGui::ProgressBar(float(task.progress()), ImVec2(-1.0f, 0.0f), overlay);
    track((id + "_progress").c_str());
    if (!debugDir_.empty()) {
        char line[64];
        std::snprintf(line, sizeof(line), "text %s_progress %.3f\n", name, task.progress());
        layout_ += line;
    }
}

// The load's progress bar and Cancel, under the message of the section it was asked in.
void Viewer::fieldLoadProgress(const Message& slot) {
    if (fieldLoad_.pending() && loadSlot_ == &slot) taskProgress(fieldLoad_, "loading", "load");
}

// A finished load: the field shown (one undo step), or why not where the load was asked for; an
// error left in the other slot by an earlier try is stale once this one is said.
void Viewer::collectFieldLoad() {
    std::optional<LoadedField> loaded;
    std::string error;
    if (!fieldLoad_.collect(loaded, error)) return;
    if (!savedField_.model.empty()) {
        collectSavedField(std::move(loaded), error);
        savedField_ = SavedFieldLoad{};
        return;
    }
    const std::string path = fieldLoad_.path();
    Message& here = *loadSlot_;
    Message& other = &here == &fieldMessage_ ? modelMessage_ : fieldMessage_;
    if (!loaded) {
        if (error == "cancelled") setMessage(here, Message::Level::Info, "not loaded: " + path + " (cancelled); the scene is as it was");
        else setMessage(here, Message::Level::Error, error);
        return;
    }
    bool noGrid = false;
    fieldWarning_.clear();
    if (loaded->band) {
        const std::string sign = loaded->band->parameter("sign");
        FieldInfo info{"loaded from " + path, loaded->band->method, -1.0, 0.0, "sign: " + (sign.empty() ? std::string("not recorded in the file") : sign)};
        showBand(std::move(*loaded->band), std::move(*loaded->field), std::move(loaded->bandLine), info);
    } else {
        noGrid = hasNoGrid(*loaded->field);
        FieldInfo info{"loaded from " + path, loaded->field->method, -1.0, 0.0, signSummaryOf(*loaded->field)};
        showField(std::move(*loaded->field), info);
    }
    rememberRecent(path);
    setMessage(generationMessage_, Message::Level::Info, ""); // the last bake is no longer shown
    if (other.level == Message::Level::Error) setMessage(other, Message::Level::Info, "");
    if (&here != &fieldMessage_) setMessage(fieldMessage_, Message::Level::Info, ""); // what was said of the last field
    if (noGrid) {
        setMessage(here, Message::Level::Warning,
                   "loaded " + path + ", which has no grid (a .npy holds only the values): shown with unit voxels from the origin; "
                   "save fields as .npz, .sdf, .vdb or .nrrd to keep their place");
    } else if (!fieldWarning_.empty()) {
        setMessage(here, Message::Level::Warning, "loaded " + path + ", but " + fieldWarning_);
    } else {
        setMessage(here, Message::Level::Info, "loaded " + path);
    }
}

// Save and Export ask before they replace a file (a modal question; `action` 1 saves the field,
// 2 exports the surface).
void Viewer::askOverwrite(const std::string& path, int action) {
    std::error_code ec;
    if (!fs::exists(path, ec)) {
        if (action == 1) saveFieldNow();
        else exportSurface();
        return;
    }
    overwritePath_ = path;
    overwriteAction_ = action;
    askOverwrite_ = true;
}

void Viewer::overwriteQuestion() {
    const char* title = "Replace the file?";
    if (askOverwrite_) {
        ImGui::OpenPopup(title);
        askOverwrite_ = false;
    }
    if (!ImGui::BeginPopupModal(title, nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove)) return;
    ImGui::PushTextWrapPos(ImGui::GetFontSize() * 30.0f);
    ImGui::TextWrapped("%s already exists. Replace it with the %s?", overwritePath_.c_str(), overwriteAction_ == 1 ? "field" : "surface");
    ImGui::PopTextWrapPos();
    bool replace = ImGui::Button("Replace");
    track("overwrite_replace");
    ImGui::SameLine();
    bool keep = ImGui::Button("Cancel");
    track("overwrite_cancel");
    if (ImGui::IsKeyPressed(GLFW_KEY_ESCAPE)) keep = true;
    if (replace) {
        ImGui::CloseCurrentPopup();
        if (overwriteAction_ == 1) saveFieldNow();
        else exportSurface();
    } else if (keep) {
        ImGui::CloseCurrentPopup();
        setMessage(fieldMessage_, Message::Level::Info, "not saved: " + overwritePath_ + " is kept as it was");
    }
    ImGui::EndPopup();
}

void Viewer::saveFieldNow() {
    try {
        if (!field_) throw Error("no field to save: Generate one first");
        if (band_) {
            saveSparseField(*band_, fieldPath_); // not the resampling shown
        } else {
            saveField(*field_, fieldPath_);
        }
        rememberRecent(fieldPath_);
        setMessage(fieldMessage_, Message::Level::Info, std::string("saved ") + fieldPath_);
    } catch (const std::exception& e) {
        setMessage(fieldMessage_, Message::Level::Error, e.what());
    }
}

void Viewer::exportSurface() {
    try {
        if (!field_) throw Error("no field to take the surface from: Generate or Load one first");
        const float iso = scene_.view<render::RaymarchView>().iso; // the ray-marched level
        // A band field's own samples, not the resampling shown (an Error when they do not fit densely).
        const SurfaceMesh surface = extractSurface(band_ ? band_->toDense() : *field_, double(iso), 0.0);
        saveSurface(surface, surfacePath_);
        rememberRecent(surfacePath_);
        setMessage(fieldMessage_, Message::Level::Info,
                   "saved the surface at level " + std::to_string(iso).substr(0, 6) + " as " + surfacePath_ + " (" +
                       std::to_string(surface.triangles.size()) + " triangles)");
    } catch (const std::exception& e) {
        setMessage(fieldMessage_, Message::Level::Error, e.what());
    }
}

namespace {
// The "Sign errors" view's crosses: at most this many samples are drawn (evenly chosen among them).
constexpr std::size_t kMostSignErrorCrosses = 200000;

std::vector<glm::vec3> crossesAt(const Grid& grid, const std::vector<std::size_t>& samples, float size) {
    std::vector<glm::vec3> segments;
    const std::size_t step = (samples.size() + kMostSignErrorCrosses - 1) / kMostSignErrorCrosses;
    const std::size_t nx = std::size_t(grid.dims.x), nxy = nx * std::size_t(grid.dims.y);
    for (std::size_t s = 0; s < samples.size(); s += std::max<std::size_t>(step, 1)) {
        const std::size_t i = samples[s];
        const glm::vec3 p(grid.position(int(i % nx), int(i / nx % std::size_t(grid.dims.y)), int(i / nxy)));
        for (int a = 0; a < 3; ++a) {
            glm::vec3 d(0.0f);
            d[a] = size;
            segments.push_back(p - d);
            segments.push_back(p + d);
        }
    }
    return segments;
}
} // namespace

// Compares the field shown with a field file (as `sdfgen compare`) in the background: the figures
// in the panel, and where their signs differ as the "Sign errors" view, shown when there are any.
void Viewer::compareWith(const std::string& path) {
    if (!field_) {
        setMessage(fieldMessage_, Message::Level::Error, "no field to compare: Generate or Load one first");
        return;
    }
    // A comparison still running is cancelled: the newer one is what was asked for.
    const std::string replaced = comparison_.running() ? comparison_.path() : "";
    comparison_.start(field_, band_, path, threads_);
    comparedVersion_ = fieldVersion_;
    setMessage(fieldMessage_, Message::Level::Info,
               "comparing with " + path + "..." + (replaced.empty() ? "" : " (the comparison with " + replaced + " is cancelled)"));
}

// A finished comparison, said under Field, for the field it was made with (a comparison with a
// field no longer shown is dropped).
void Viewer::collectComparison() {
    std::optional<ComparedFields> compared;
    std::string error;
    if (!comparison_.collect(compared, error)) return;
    const std::string path = comparison_.path();
    if (!compared) {
        if (error == "cancelled") setMessage(fieldMessage_, Message::Level::Info, "not compared with " + path + " (cancelled)");
        else setMessage(fieldMessage_, Message::Level::Error, error);
        return;
    }
    if (comparedVersion_ != fieldVersion_) {
        setMessage(fieldMessage_, Message::Level::Info, "not compared with " + path + ": the field shown changed meanwhile");
        return;
    }
    const FieldDifference& d = compared->difference;
    char text[320];
    std::snprintf(text, sizeof(text), "against %s: max |difference| %.4g (%.3g voxels), mean %.3g, rms %.3g; signs differ at %zu of %zu samples",
                  fs::path(path).filename().string().c_str(), d.maxAbs, d.maxAbs / d.voxel, d.meanAbs, d.rmsAbs, d.signDifferences, d.compared);
    setMessage(fieldMessage_, Message::Level::Info, text);
    signErrors_ = SignErrors{fs::path(path).filename().string(), d.signDifferences, d.compared + d.signOnly, fieldVersion_};
    render::SignErrorsView& crosses = scene_.view<render::SignErrorsView>();
    crosses.crosses = crossesAt(compared->grid, compared->signDifferences, float(0.4 * compared->grid.voxel));
    ++comparisons_;
    if (!compared->signDifferences.empty()) crosses.enabled = true;
}

// What the last comparison found, while the field it was made with is shown.
void Viewer::signErrorsLine() {
    if (!signErrors_.against.empty() && signErrors_.fieldVersion != fieldVersion_) {
        signErrors_ = SignErrors{};
        scene_.view<render::SignErrorsView>().crosses.clear();
        ++comparisons_;
        return;
    }
    if (signErrors_.against.empty()) return;
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
    if (signErrors_.count > kMostSignErrorCrosses) {
        wrappedText("sign errors against %s: %zu of %zu samples (the Sign errors view shows %zu of them)", signErrors_.against.c_str(),
                    signErrors_.count, signErrors_.samples, kMostSignErrorCrosses);
    } else {
        wrappedText("sign errors against %s: %zu of %zu samples%s", signErrors_.against.c_str(), signErrors_.count, signErrors_.samples,
                    signErrors_.count ? " (the Sign errors view shows them)" : "");
    }
    ImGui::PopStyleColor();
    track("sign_errors");
    if (!debugDir_.empty()) layout_ += "text sign_errors " + std::to_string(signErrors_.count) + " " + std::to_string(scene_.view<render::SignErrorsView>().crosses.size() / 6) + "\n";
}

void Viewer::fieldSection() {
    if (!ImGui::CollapsingHeader("Field", ImGuiTreeNodeFlags_DefaultOpen)) return;
    const float browseWidth = ImGui::CalcTextSize("Browse...").x + ImGui::GetStyle().FramePadding.x * 2 + ImGui::GetStyle().ItemSpacing.x;
    ImGui::SetNextItemWidth(-browseWidth);
    const bool enter = ImGui::InputText("##field", fieldPath_, sizeof(fieldPath_), ImGuiInputTextFlags_EnterReturnsTrue);
    track("field_path");
    ImGui::SameLine();
    if (ImGui::Button("Browse...##field")) fileBrowser_.open("Choose a field file", fieldPath_, fieldFormatExtensions(), "Choose");
    track("field_browse");
    if (ImGui::Button("Save")) {
        if (field_) askOverwrite(fieldPath_, 1);
        else saveFieldNow(); // says there is nothing to save
    }
    track("field_save");
    ImGui::SameLine();
    if (ImGui::Button("Load##field") || enter) loadFieldFile(fieldPath_);
    track("field_load");
    messageLine("##field_message", fieldMessage_);
    fieldLoadProgress(fieldMessage_);

    // The iso-surface (at the ray-marched view's level) as a mesh, and a comparison, as the CLI's
    // `surface` and `compare` do.
    if (!surfacePath_[0] && fieldPath_[0]) std::snprintf(surfacePath_, sizeof(surfacePath_), "%s", fs::path(fieldPath_).replace_extension(".surface.obj").string().c_str());
    ImGui::BeginDisabled(!field_);
    ImGui::SetNextItemWidth(-browseWidth);
    ImGui::InputText("##surface", surfacePath_, sizeof(surfacePath_));
    track("surface_path");
    ImGui::SameLine();
    if (ImGui::Button("Export")) askOverwrite(surfacePath_, 2);
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) ImGui::SetTooltip("Save the surface at the Iso level as OBJ or PLY");
    track("surface_export");
    ImGui::SetNextItemWidth(-browseWidth);
    const bool compareEnter = ImGui::InputTextWithHint("##compare", "another field to compare", comparePath_, sizeof(comparePath_),
                                                       ImGuiInputTextFlags_EnterReturnsTrue);
    track("compare_path");
    ImGui::SameLine();
    if (ImGui::Button("Compare") || compareEnter) compareWith(comparePath_);
    track("compare");
    ImGui::EndDisabled();
    if (comparison_.pending()) taskProgress(comparison_, "comparing", "compare");
    signErrorsLine();
}

void Viewer::fileChosen() {
    const std::string path = fileBrowser_.chosen();
    if (fileBrowser_.title() == "Open a model") {
        std::snprintf(meshPath_, sizeof(meshPath_), "%s", path.c_str());
        openPaths({path}, false);
    } else {
        std::snprintf(fieldPath_, sizeof(fieldPath_), "%s", path.c_str()); // Save or Load it with the buttons
        setMessage(fieldMessage_, Message::Level::Info, "chose " + path + ": Save writes the field there, Load reads it");
    }
}

} // namespace sdfgen::app
