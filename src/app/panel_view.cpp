// The panel's View, Camera and Probe sections.
#include "app/viewer_state.hpp"

#include <imgui.h>
#include <imgui_internal.h>
#include <algorithm>
#include <cmath>
#include <cstdio>

namespace sdfgen::app {

namespace {
// A slider that a double click turns into a text box (as Blender's), as Ctrl+click does: the
// slider sees Ctrl held for the click that completes a double click, and the value that click's
// first half jumped to is put back. Its tooltip says so.
bool typableSlider(const char* label, float& value, float min, float max, const char* format, ImGuiSliderFlags flags = 0) {
    static ImGuiID pressedId = 0;
    static float beforePress = 0.0f;
    ImGuiIO& io = ImGui::GetIO();
    const ImVec2 at = ImGui::GetCursorScreenPos();
    const ImVec2 end(at.x + ImGui::CalcItemWidth(), at.y + ImGui::GetFrameHeight());
    const bool doubleClick = io.MouseDoubleClicked[0] && ImGui::IsWindowHovered() && ImGui::IsMouseHoveringRect(at, end);
    const ImGuiID id = ImGui::GetID(label); // the slider's own
    bool changed = false;
    if (doubleClick && pressedId == id && value != beforePress) { // before the text box shows it
        value = beforePress;
        changed = true;
    }
    const bool ctrl = io.KeyCtrl;
    const float before = value;
    if (doubleClick) io.KeyCtrl = true;
    changed |= ImGui::SliderFloat(label, &value, min, max, format, flags);
    io.KeyCtrl = ctrl;
    if (ImGui::IsItemActivated() && !doubleClick) {
        pressedId = id;
        beforePress = before;
    }
    if (ImGui::IsItemHovered() && !ImGui::IsItemActive()) ImGui::SetTooltip("drag, or double-click (or Ctrl+click) to type a value");
    return changed;
}
} // namespace

// The views' settings as Dear ImGui controls, each reported to the GUI test by its label.
class Viewer::PanelOptions : public render::ViewOptions {
public:
    explicit PanelOptions(Viewer& viewer) : viewer_(viewer) {}
    bool checkbox(const char* label, bool& value, const char* tooltip) override {
        const bool changed = ImGui::Checkbox(label, &value);
        if (tooltip && ImGui::IsItemHovered()) ImGui::SetTooltip("%s", tooltip);
        viewer_.track(widgetName(label).c_str());
        return changed;
    }
    bool slider(const char* label, float& value, float min, float max, const char* format, bool logarithmic) override {
        const bool changed = typableSlider(label, value, min, max, format, logarithmic ? ImGuiSliderFlags_Logarithmic : 0);
        viewer_.track(widgetName(label).c_str());
        return changed;
    }

private:
    Viewer& viewer_;
};

// A view's colour range: symmetric, from the values it shows, or fixed limits.
void Viewer::rangeControls(const char* label, const char* name, RangeChoice& choice, glm::vec2& sceneRange, bool slice) {
    ImGui::PushID(name);
    const char* modes = slice ? "symmetric\0from the slice\0fixed\0" : "symmetric\0from the field\0fixed\0";
    ImGui::Combo(label, &choice.mode, modes);
    if (ImGui::IsItemHovered()) {
        ImGui::SetTooltip("symmetric: +-a quarter of the box; from the %s: its least to greatest value (0 stays in the middle "
                          "of the map); fixed: the limits below",
                          slice ? "slice" : "field");
    }
    track(name);
    if (choice.mode == 2) {
        ImGui::DragFloat2("inside, outside", &choice.fixed.x, std::max(std::abs(choice.fixed.y), 1e-3f) * 0.01f, 0.0f, 0.0f, "%.4g");
        choice.fixed.x = std::min(choice.fixed.x, -1e-9f);
        choice.fixed.y = std::max(choice.fixed.y, 1e-9f);
    }
    ImGui::PopID();
    if (!field_ || choice.mode == 0) {
        sceneRange = glm::vec2(0.0f);
    } else if (choice.mode == 2) {
        sceneRange = choice.fixed;
    } else {
        const glm::vec4 plane = slice ? glm::vec4(glm::normalize(scene_.sliceNormal), scene_.slicePosition) : glm::vec4(0.0f);
        if (choice.valuesVersion != fieldVersion_ || choice.valuesPlane != plane) {
            choice.fromValues = slice ? render::sliceValueRange(*field_, glm::vec3(plane), plane.w) : render::fieldValueRange(*field_);
            choice.valuesVersion = fieldVersion_;
            choice.valuesPlane = plane;
        }
        sceneRange = choice.fromValues;
    }
    // A range with nothing on one side still needs a scale there (the bar shows 0 at that end).
    if (sceneRange != glm::vec2(0.0f)) sceneRange = glm::vec2(std::min(sceneRange.x, 0.0f), std::max(sceneRange.y, 1e-9f));
}

void Viewer::viewSection() {
    if (!ImGui::CollapsingHeader("View", ImGuiTreeNodeFlags_DefaultOpen)) return;
    render::Views& v = scene_.views;
    const float column = std::round(panelWidth_ * 0.5f);
    // A checkbox per registered view (render/view.hpp), two to a row.
    int item = 0;
    for (const render::ViewType& type : render::viewTypes()) {
        if (item++ % 2) ImGui::SameLine(column);
        if (ImGui::Checkbox(type.label, &v[type.name])) userChoseViews_ = true;
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", type.description);
        track(widgetName(type.label).c_str());
    }
    if (item++ % 2) ImGui::SameLine(column);
    ImGui::Checkbox("Headlight", &scene_.headlight);
    track("headlight");
    // Each shown view's own settings (its section, from the registry).
    PanelOptions ui(*this);
    for (const render::ViewType& type : render::viewTypes()) {
        if (type.options && v[type.name]) type.options(ui, scene_);
    }
    // Slice: an axis, or any orientation (dragged in the view: Ctrl+left-drag moves, Ctrl+Shift tilts).
    for (int a = 0; a < 3; ++a) {
        if (a > 0) ImGui::SameLine();
        const char* labels[] = {"Slice X", "Slice Y", "Slice Z"};
        const char* names[] = {"slice_x", "slice_y", "slice_z"};
        if (ImGui::Button(labels[a])) {
            scene_.sliceNormal = render::axisNormal(a);
            if (!v["slice"]) v["slice"] = userChoseViews_ = true;
        }
        track(names[a]);
    }
    // The cut follows the slice: hidden, it cuts nothing (the choice is kept for when it is shown).
    int cut = sliceCut_ == 0 ? 0 : sliceCut_ > 0 ? 1 : 2;
    const char* cuts[] = {"nothing", "the normal's side", "the other side"};
    ImGui::BeginDisabled(!v["slice"]);
    if (ImGui::BeginCombo("Cut away", cuts[cut])) {
        for (int c = 0; c < 3; ++c) {
            if (ImGui::Selectable(cuts[c], c == cut)) cut = c;
            track(("slice_cut_" + std::to_string(c)).c_str());
        }
        ImGui::EndCombo();
    }
    ImGui::EndDisabled();
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) {
        ImGui::SetTooltip(v["slice"] ? "The slice's plane cuts the model and the ray-marched surface away on one side"
                                     : "Show the slice to cut away with its plane");
    }
    sliceCut_ = cut == 0 ? 0 : cut == 1 ? 1 : -1;
    scene_.sliceCut = v["slice"] ? sliceCut_ : 0;
    track("slice_cut");
    const glm::vec3 n = scene_.sliceNormal;
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
    wrappedText("normal (%.2f %.2f %.2f); in the view: Ctrl+left-drag moves, Ctrl+Shift+left-drag tilts", double(n.x), double(n.y), double(n.z));
    ImGui::PopStyleColor();
    ImGui::Combo("Colour map", &scene_.colormap, "diverging\0viridis\0grey\0");
    track("colormap");
    rangeControls("Slice colours", "slice_range", sliceColours_, scene_.sliceRange, true);
    rangeControls("Volume colours", "volume_range", volumeColours_, scene_.volumeRange, false);
    ImGui::Checkbox("Colour bar", &scene_.colourBar);
    track("colour_bar");

    if (ImGui::Button("Screenshot")) saveScreenshot();
    track("screenshot");
    ImGui::SameLine();
    ImGui::TextDisabled("0 0: the scene's size");
    ImGui::InputInt2("Width, height", screenshotSize_);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("The screenshot's width and height in pixels; 0 0: the size of the scene's area");
    track("screenshot_size");
    messageLine("##screenshot_message", screenshotMessage_);
}

void Viewer::cameraSection() {
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
    ImGui::Checkbox("Orthographic", &camera_.orthographic);
    track("ortho");
    typableSlider("Yaw", camera_.yaw, -180.0f, 180.0f, "%.1f");
    track("yaw");
    typableSlider("Pitch", camera_.pitch, -89.0f, 89.0f, "%.1f");
    track("pitch");
    ImGui::DragFloat("Distance", &camera_.distance, camera_.sceneRadius * 0.01f, 1e-4f, 1e6f, "%.4g");
    track("distance");
    ImGui::DragFloat3("Target", &camera_.target.x, camera_.sceneRadius * 0.01f, 0.0f, 0.0f, "%.4g");
    track("target");
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
    wrappedText("left- or right-drag orbit, middle-drag pan, wheel zoom, arrows orbit (a tap 3 degrees, held 90 per second), F frames");
    ImGui::PopStyleColor();
}

void Viewer::probeSection() {
    if (!ImGui::CollapsingHeader("Probe", ImGuiTreeNodeFlags_DefaultOpen)) return;
    ImGui::Checkbox("Probe under the cursor", &probeOn_);
    track("probe");
    if (!probeOn_) return;
    if (!probeValid_) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
        wrappedText(probeKept_ ? "the last reading; move the pointer over the model, the slice or the ray-marched surface for another"
                                      : "move the pointer over the model, the slice or the ray-marched surface");
        ImGui::PopStyleColor();
        if (!probeKept_) return;
    }
    const ProbeResult& p = probe_;
    wrappedText("at (%.4g %.4g %.4g)", p.point.x, p.point.y, p.point.z);
    if (field_) {
        wrappedText("field: %.5g%s", double(p.fieldValue), p.insideField ? "" : " (outside the box: clamped)");
        wrappedText("gradient (%.3f %.3f %.3f)", double(p.gradient.x), double(p.gradient.y), double(p.gradient.z));
    }
    if (p.haveMesh) {
        wrappedText("mesh: unsigned distance %.5g (exact)", p.meshDistance);
        wrappedText("nearest (%.4g %.4g %.4g)", p.nearest.x, p.nearest.y, p.nearest.z);
    }
    track("probe_values");
}

} // namespace sdfgen::app
