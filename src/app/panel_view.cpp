// The panel's View, Camera and Probe sections.
#include "app/viewer_state.hpp"

#include <imgui.h>
#include <imgui_internal.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

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
    if (field_) rangeHistogram(name, choice, sceneRange);
}

const Viewer::ValueHistogram& Viewer::valueHistogram() {
    if (histogram_.fieldVersion == fieldVersion_ || !field_) return histogram_;
    constexpr int kBins = 64;
    const glm::vec2 range = render::fieldValueRange(*field_);
    histogram_ = ValueHistogram{fieldVersion_, range.x, std::max(range.y, range.x + 1e-9f), std::vector<float>(kBins, 0.0f), 0.0f};
    const float scale = float(kBins) / (histogram_.high - histogram_.low);
    std::vector<std::size_t> counts(kBins, 0);
    for (const float v : field_->values) ++counts[std::size_t(std::clamp(int((v - histogram_.low) * scale), 0, kBins - 1))];
    // Counts on a log scale: the few samples far from the surface stay visible beside the many near it.
    for (int b = 0; b < kBins; ++b) {
        histogram_.bins[std::size_t(b)] = std::log1p(float(counts[std::size_t(b)]));
        histogram_.tallest = std::max(histogram_.tallest, histogram_.bins[std::size_t(b)]);
    }
    return histogram_;
}

// The field's values as a histogram under a view's range, with the range's ends (inside, left of
// 0; outside, right of it) drawn as lines that can be dragged: dragging one makes the range fixed.
void Viewer::rangeHistogram(const char* name, RangeChoice& choice, glm::vec2& sceneRange) {
    const ValueHistogram& h = valueHistogram();
    ImGui::PushID(name);
    const float height = std::round(3.0f * ImGui::GetFrameHeight());
    const ImVec2 at = ImGui::GetCursorScreenPos();
    const float width = ImGui::GetContentRegionAvail().x;
    // The button that takes the drags first: an item drawn over another is not hovered.
    ImGui::InvisibleButton("##ends", ImVec2(width, height));
    const bool activated = ImGui::IsItemActivated(), active = ImGui::IsItemActive(), deactivated = ImGui::IsItemDeactivated();
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("drag a line to set the colours' limit there (the range becomes fixed)");
    ImGui::SetCursorScreenPos(at);
    ImGui::PlotHistogram("##values", h.bins.data(), int(h.bins.size()), 0, nullptr, 0.0f, h.tallest, ImVec2(width, height));
    const ImVec2 pad = ImGui::GetStyle().FramePadding;
    const float x0 = at.x + pad.x, x1 = at.x + width - pad.x;
    auto toX = [&](float v) { return x0 + (std::clamp(v, h.low, h.high) - h.low) / (h.high - h.low) * (x1 - x0); };
    auto toValue = [&](float x) { return h.low + (std::clamp(x, x0, x1) - x0) / (x1 - x0) * (h.high - h.low); };
    const glm::vec2 shown = scene_.effectiveRange(sceneRange);
    static int dragged = 0; // 1 the inside end, 2 the outside end: one drag at a time in the whole panel
    const float mouseX = ImGui::GetIO().MousePos.x;
    if (activated) dragged = std::abs(mouseX - toX(shown.x)) <= std::abs(mouseX - toX(shown.y)) ? 1 : 2;
    if (active && dragged != 0) {
        choice.mode = 2;
        choice.fixed = shown;
        const float value = toValue(mouseX);
        if (dragged == 1) choice.fixed.x = std::min(value, -1e-9f);
        else choice.fixed.y = std::max(value, 1e-9f);
        sceneRange = choice.fixed;
    }
    if (deactivated) dragged = 0;
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const glm::vec2 ends = scene_.effectiveRange(sceneRange);
    const ImU32 colours[2] = {IM_COL32(90, 140, 255, 255), IM_COL32(255, 120, 80, 255)}; // the diverging map's two sides
    const float xs[2] = {toX(ends.x), toX(ends.y)};
    for (int e = 0; e < 2; ++e) draw->AddLine(ImVec2(xs[e], at.y), ImVec2(xs[e], at.y + height), colours[e], 2.0f);
    draw->AddLine(ImVec2(toX(0.0f), at.y + height - 4.0f), ImVec2(toX(0.0f), at.y + height), IM_COL32(255, 255, 255, 200)); // 0
    track((std::string(name) + "_histogram").c_str());
    ImGui::PopID();
    if (!debugDir_.empty()) {
        char line[160];
        std::snprintf(line, sizeof(line), "text %s_ends %d %d %d %.6g %.6g\n", name, int(xs[0]), int(xs[1]), int(at.y + height / 2), double(ends.x),
                      double(ends.y));
        layout_ += line;
    }
}

namespace {
// "x y z" (commas allowed) as three finite numbers.
bool parseVector(const char* text, glm::vec3& out) {
    std::string s(text);
    std::replace(s.begin(), s.end(), ',', ' ');
    char rest = 0;
    glm::vec3 v;
    if (std::sscanf(s.c_str(), "%f %f %f %c", &v.x, &v.y, &v.z, &rest) != 3) return false;
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) return false;
    out = v;
    return true;
}
} // namespace

// The slice plane's pose, as the gizmo leaves it and as typed: a point on it (the one nearest the
// field box's centre) and its unit normal. A typed normal turns the plane about that point.
void Viewer::slicePose() {
    const render::SliceGizmo gizmo = scene_.sliceGizmo();
    const ImGuiID pointId = ImGui::GetID("Slice point"), normalId = ImGui::GetID("Slice normal");
    // Shown as the plane is, except while being typed into.
    if (ImGui::GetActiveID() != pointId) {
        std::snprintf(slicePointText_, sizeof(slicePointText_), "%.5g %.5g %.5g", double(gizmo.centre.x), double(gizmo.centre.y), double(gizmo.centre.z));
    }
    if (ImGui::GetActiveID() != normalId) {
        std::snprintf(sliceNormalText_, sizeof(sliceNormalText_), "%.4f %.4f %.4f", double(gizmo.normal.x), double(gizmo.normal.y), double(gizmo.normal.z));
    }
    const glm::vec3 boxMin = scene_.fieldBoxMin(), boxSize = scene_.fieldBoxSize();
    if (ImGui::InputText("Slice point", slicePointText_, sizeof(slicePointText_), ImGuiInputTextFlags_EnterReturnsTrue)) {
        glm::vec3 point;
        if (!parseVector(slicePointText_, point)) {
            setMessage(sliceMessage_, Message::Level::Error, std::string("the slice point '") + slicePointText_ + "' is not three numbers");
        } else {
            const float position = render::slicePositionThrough(boxMin, boxSize, gizmo.normal, point);
            scene_.slicePosition = std::clamp(position, 0.0f, 1.0f);
            if (position < 0.0f || position > 1.0f) {
                setMessage(sliceMessage_, Message::Level::Warning, "the plane through that point misses the field's box: it is placed at the box's edge");
            } else {
                setMessage(sliceMessage_, Message::Level::Info, "");
            }
        }
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("A point of the slice's plane (x y z, Enter applies)");
    track("slice_point");
    if (ImGui::InputText("Slice normal", sliceNormalText_, sizeof(sliceNormalText_), ImGuiInputTextFlags_EnterReturnsTrue)) {
        glm::vec3 normal;
        if (!parseVector(sliceNormalText_, normal) || !(glm::length(normal) > 1e-6f)) {
            setMessage(sliceMessage_, Message::Level::Error, std::string("the slice normal '") + sliceNormalText_ + "' is not three numbers, not all 0");
        } else {
            scene_.sliceNormal = glm::normalize(normal);
            scene_.slicePosition = std::clamp(render::slicePositionThrough(boxMin, boxSize, scene_.sliceNormal, gizmo.centre), 0.0f, 1.0f);
            setMessage(sliceMessage_, Message::Level::Info, "");
        }
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("The plane's normal (x y z, made unit length; Enter applies): the plane turns about its point");
    track("slice_normal");
    messageLine("##slice_message", sliceMessage_);
    if (!debugDir_.empty()) {
        const std::string line = "text slice_pose " + std::string(slicePointText_) + " / " + sliceNormalText_ + "\n";
        layout_ += line;
        glm::vec2 arrow, tip, ring;
        const std::vector<glm::vec3> arrowSegments = gizmo.segments(render::SliceGizmo::Part::Arrow);
        const std::vector<glm::vec3> ringSegments = gizmo.segments(render::SliceGizmo::Part::Ring);
        // Points to grab: two thirds up the arrow (with its tip, for the direction to drag it), and
        // the ring's point most to the right on screen.
        if (toPointer(glm::mix(arrowSegments[0], arrowSegments[1], 0.67f), arrow) && toPointer(arrowSegments[1], tip)) {
            layout_ += "text gizmo_arrow " + std::to_string(int(arrow.x)) + " " + std::to_string(int(arrow.y)) + " " + std::to_string(int(tip.x)) + " " +
                       std::to_string(int(tip.y)) + "\n";
        }
        glm::vec2 rightmost(-1e9f);
        for (const glm::vec3& p : ringSegments) {
            if (toPointer(p, ring) && ring.x > rightmost.x) rightmost = ring;
        }
        layout_ += "text gizmo_ring " + std::to_string(int(rightmost.x)) + " " + std::to_string(int(rightmost.y)) + "\n";
    }
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
    wrappedText("in the view: drag the slice's arrow to move it, its ring to tilt it (or Ctrl+left-drag, Ctrl+Shift+left-drag)");
    ImGui::PopStyleColor();
}

void Viewer::viewSection() {
    if (!ImGui::CollapsingHeader("View", ImGuiTreeNodeFlags_DefaultOpen)) return;
    render::SliceView& slice = scene_.view<render::SliceView>();
    const float column = std::round(panelWidth_ * 0.5f);
    // A checkbox per registered view (render/view.hpp), two to a row.
    int item = 0;
    for (const std::unique_ptr<render::View>& v : scene_.views()) {
        if (item++ % 2) ImGui::SameLine(column);
        if (ImGui::Checkbox(v->type().label, &v->enabled)) userChoseViews_ = true;
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", v->type().description);
        track(widgetName(v->type().label).c_str());
    }
    if (item++ % 2) ImGui::SameLine(column);
    ImGui::Checkbox("Headlight", &scene_.headlight);
    track("headlight");
    // Each shown view's own settings (its section, from the registry).
    PanelOptions ui(*this);
    for (const std::unique_ptr<render::View>& v : scene_.views()) {
        if (v->enabled) v->options(ui, scene_);
    }
    // Slice: an axis, or any orientation (dragged in the view: Ctrl+left-drag moves, Ctrl+Shift tilts).
    for (int a = 0; a < 3; ++a) {
        if (a > 0) ImGui::SameLine();
        const char* labels[] = {"Slice X", "Slice Y", "Slice Z"};
        const char* names[] = {"slice_x", "slice_y", "slice_z"};
        if (ImGui::Button(labels[a])) {
            scene_.sliceNormal = render::axisNormal(a);
            if (!slice.enabled) slice.enabled = userChoseViews_ = true;
        }
        track(names[a]);
    }
    // The cut follows the slice: hidden, it cuts nothing (the choice is kept for when it is shown).
    int cut = sliceCut_ == 0 ? 0 : sliceCut_ > 0 ? 1 : 2;
    const char* cuts[] = {"nothing", "the normal's side", "the other side"};
    ImGui::BeginDisabled(!slice.enabled);
    if (ImGui::BeginCombo("Cut away", cuts[cut])) {
        for (int c = 0; c < 3; ++c) {
            if (ImGui::Selectable(cuts[c], c == cut)) cut = c;
            track(("slice_cut_" + std::to_string(c)).c_str());
        }
        ImGui::EndCombo();
    }
    ImGui::EndDisabled();
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) {
        ImGui::SetTooltip(slice.enabled ? "The slice's plane cuts the model and the ray-marched surface away on one side"
                                     : "Show the slice to cut away with its plane");
    }
    sliceCut_ = cut == 0 ? 0 : cut == 1 ? 1 : -1;
    scene_.sliceCut = slice.enabled ? sliceCut_ : 0;
    track("slice_cut");
    if (slice.enabled && field_) slicePose();
    ImGui::Combo("Colour map", &scene_.colormap, "diverging\0viridis\0grey\0");
    track("colormap");
    rangeControls("Slice colours", "slice_range", sliceColours_, slice.range, true);
    rangeControls("Volume colours", "volume_range", volumeColours_, scene_.view<render::VolumeView>().range, false);
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
