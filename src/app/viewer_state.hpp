#pragma once
// The viewer's state and its parts: the window loop and the scene (viewer.cpp), one file per panel
// section (panel_model.cpp, panel_generation.cpp, panel_field.cpp, panel_view.cpp) and the GUI
// test's hooks (test_hooks.cpp).
#include "app/file_browser.hpp"
#include "app/generation.hpp"
#include "app/glfw_context.hpp"
#include "app/input_queue.hpp"
#include "app/probe.hpp"
#include "app/recent_files.hpp"
#include "app/wrapped_text.hpp"
#include "sdfgen/field.hpp"
#include "sdfgen/mesh.hpp"
#include "sdfgen/model.hpp"
#include "sdfgen/sparse_field.hpp"
#include "render/camera.hpp"
#include "render/scene.hpp"
#include "render/views.hpp"

#include <glm/gtc/matrix_transform.hpp>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace sdfgen::app {

// Arrow keys: a tap turns kArrowTapDegrees at once; held longer than kArrowHoldDelay seconds, the
// view turns on at kArrowDegreesPerSecond (timed from the key events, not from frames).
constexpr float kArrowTapDegrees = 3.0f;
constexpr double kArrowHoldDelay = 0.25;
constexpr float kArrowDegreesPerSecond = 90.0f;

// Shortcuts handled in GLFW's key callback itself, so that a tap shorter than a frame still acts.
struct Shortcuts {
    int frameRequests = 0;
    int undoRequests = 0, redoRequests = 0; // Ctrl+Z, Ctrl+Shift+Z (or Ctrl+Y) outside text boxes
    int cancelRequests = 0;                 // Escape outside text boxes, lists and dialogs (which it closes first)
    bool quit = false;
    double arrowPressedAt[4] = {-1.0, -1.0, -1.0, -1.0}; // left, right, up, down: glfwGetTime of the press; < 0 released
    double arrowTurnedUntil[4] = {0.0, 0.0, 0.0, 0.0};   // held turning applied up to this time
    float arrowTurn[2] = {0.0f, 0.0f};                   // degrees of yaw and pitch not yet applied

    bool arrowsHeld() const { return arrowPressedAt[0] >= 0 || arrowPressedAt[1] >= 0 || arrowPressedAt[2] >= 0 || arrowPressedAt[3] >= 0; }
    // Adds the held turning of arrow `a` up to time `now` to arrowTurn.
    void turnHeld(int a, double now);
};

// Everything the GLFW callbacks hand to the viewer (the window's user pointer).
struct Inbox {
    InputQueue input;
    Shortcuts shortcuts;
    std::vector<std::string> drops;
    bool textInput = false; // a text box has the keyboard (last frame): F and arrows are typing
    bool listKeys = false;  // a list (Recent, the file dialog) has the keyboard: arrows move its selection
    bool cursorInside = true;
    int wake = 2;           // frames still to draw (ImGui settles a frame or two after an event)
};

// A message under the control that caused it, as long as its text needs (wrapped); the next
// message of the same kind replaces it; warnings and errors stay until dismissed or replaced.
struct Message {
    enum class Level { Info, Warning, Error } level = Level::Info;
    std::string text;
    std::uint64_t serial = 0; // the order messages were said in (Viewer::messagesSaid_)
};

// One model of the scene, placed by its transform, with its colour and visibility.
struct SceneModel {
    std::shared_ptr<const Mesh> mesh;
    glm::vec3 move{0.0f};
    glm::vec3 rotate{0.0f}; // degrees about x, then y, then z
    float scale = 1.0f;
    glm::vec3 colour{0.0f};
    bool visible = true;

    bool identity() const { return move == glm::vec3(0.0f) && rotate == glm::vec3(0.0f) && scale == 1.0f; }
    bool operator==(const SceneModel& o) const {
        return mesh == o.mesh && move == o.move && rotate == o.rotate && scale == o.scale && colour == o.colour && visible == o.visible;
    }
    bool operator!=(const SceneModel& o) const { return !(*this == o); }
    glm::dmat4 transform() const;
};

// What the panel shows about the current field: the bake's or the loaded file's own figures.
struct FieldInfo {
    std::string origin;  // "baked" or "loaded from PATH"
    std::string method;  // the field's method line
    double seconds = -1; // the bake's time; < 0 for a loaded field
    double rate = 0;
    std::string signSummary;
};

// How a view's colours are scaled: symmetric about 0 from the field's size, from the values the
// view shows (the slice's own, or the whole field's), or fixed limits.
struct RangeChoice {
    int mode = 0; // 0 symmetric, 1 from the values, 2 fixed
    glm::vec2 fixed{-1.0f, 1.0f};
    // The range from the values, for the field version and slice plane it was taken from (a pass
    // over the field, not repeated every frame).
    glm::vec2 fromValues{0.0f};
    int valuesVersion = -1;
    glm::vec4 valuesPlane{0.0f};
};

// The slice's plane: its normal and its place along it across the field's box (0..1).
struct SlicePose {
    glm::vec3 normal{0.0f, 0.0f, 1.0f};
    float position = 0.5f;
    bool operator==(const SlicePose& o) const { return normal == o.normal && position == o.position; }
    bool operator!=(const SlicePose& o) const { return !(*this == o); }
};

// One step of the undo stack: the scene's models, the bake's settings and the slice as they were, and the
// field shown (moved here, not copied) when the step changed it. Undoing swaps it with the
// viewer's own, so the same entry then redoes the step.
struct UndoEntry {
    std::string what; // "remove bunny.obj", "move", "settings", "load field"...
    std::vector<SceneModel> models;
    BakeSettings settings;
    int threads = 0;
    SlicePose slice;
    bool hasField = false;
    std::shared_ptr<const Field> field;
    std::shared_ptr<const SparseField> band;
    std::string bandLine;
    FieldInfo info;
};

bool isFieldPath(const std::string& path); // a field format's extension (formats.hpp)
std::string widgetName(const std::string& label); // a label as the GUI test names it: spaces as underscores
std::string signSummaryOf(const FieldHeader& field);    // "sign: " and how the field's signs were decided

class Viewer {
public:
    Viewer(GlfwContext& context, Inbox& inbox);
    // Opens `paths` (models and fields, by extension) as the scene (replacing it) or adds the
    // models; during a bake, asks first.
    void openPaths(const std::vector<std::string>& paths, bool add);
    int run();

private:
    // viewer.cpp: the loop, the scene, its input and drawing.
    void sceneInput(const FrameInput& input);
    void dragSlice(float dx, float dy);
    // Where `world` is drawn, in window pixels from the top left; false behind the camera.
    bool toPointer(glm::vec3 world, glm::vec2& pointer) const;
    // The part of the slice's gizmo within grabbing distance of the pointer.
    render::SliceGizmo::Part gizmoPartAt(glm::vec2 pointer) const;
    void probeAt(const FrameInput& input);
    std::optional<glm::dvec3> marchedSurfaceAt(glm::ivec2 pixel, glm::vec3 drawn) const;
    void probeOverlay();
    void sceneHint();
    std::string probeText(const char* separator) const;
    void panel();
    void drawScene();
    bool imguiSettling();
    void setMessage(Message& slot, Message::Level level, const std::string& text);
    void messageLine(const char* id, Message& m);
    void updateTitle();
    void frameCamera();
    void saveScreenshot();

    // panel_model.cpp
    void openModels(const std::vector<std::string>& paths, bool add);
    void rememberRecent(const std::string& path);
    void openPathFromModel(const std::string& path);
    void rebuildScene(bool reframe);
    void undoButtons();

    // undo.cpp: the undo stack of scene edits.
    SlicePose slice() const { return {scene_.sliceNormal, scene_.slicePosition}; }
    bool draggingSlice() const { return sceneDrag_[0] && leftDrag_ != LeftDrag::Orbit; }
    // A bake runs and was not cancelled (a cancelled one may take a moment to stop: the scene can
    // change meanwhile, its result is dropped).
    bool baking() const { return generation_.running() && !generation_.cancelled(); }
    void fieldChanging(const char* what);
    void commitEdits();
    void undoStep(bool redo);
    std::string describeEdit() const;
    void handleDrops();
    void cancelTasks();
    void modelSection();

    // panel_generation.cpp
    std::string validateSettings(Grid& grid, double& bytes) const;
    void generationSection();
    void collectGeneration();
    void bakeQuestion();

    // panel_field.cpp
    void checkFieldAgainstScene();
    void showField(Field field, FieldInfo info);
    void showBand(SparseField band, FieldInfo info);
    void showBand(SparseField band, Field shown, std::string line, FieldInfo info); // shown: its render::bandDisplay
    void loadSavedField(const std::string& meshPath);
    // Loads a field file; its messages go to `slot` (the section the action was taken in).
    void loadFieldFile(const std::string& path, Message* slot = nullptr);
    // A background task's Cancel and progress bar (`doing` on the bar; `name` for the GUI test).
    void taskProgress(BackgroundTask& task, const char* doing, const char* name);
    void fieldLoadProgress(const Message& slot);
    void collectFieldLoad();
    void collectSavedField(std::optional<LoadedField> loaded, const std::string& error);
    void collectComparison();
    void askOverwrite(const std::string& path, int action);
    void overwriteQuestion();
    void saveFieldNow();
    void fieldSection();
    void exportSurface();
    void compareWith(const std::string& path);
    void signErrorsLine();
    void fileChosen();

    // panel_view.cpp
    class PanelOptions;
    void viewSection();
    void slicePose();
    // A histogram of the field's values (log counts), made once per field version.
    struct ValueHistogram {
        int fieldVersion = -1;
        float low = 0.0f, high = 0.0f;
        std::vector<float> bins;
        float tallest = 0.0f;
    };
    const ValueHistogram& valueHistogram();
    void rangeHistogram(const char* name, RangeChoice& choice, glm::vec2& sceneRange);
    void rangeControls(const char* label, const char* name, RangeChoice& choice, glm::vec2& sceneRange, bool slice);
    void cameraSection();
    void probeSection();

    // test_hooks.cpp: for the GUI test (SDFGEN_SCREENSHOT_DIR set).
    void track(const char* name);
    void debugScreenshot(bool sceneOnly);
    void writeDebugState();

    GlfwContext& context_;
    Inbox& inbox_;
    render::Scene scene_;
    render::OrbitCamera camera_;
    std::vector<SceneModel> models_;
    std::shared_ptr<const Mesh> sceneMesh_;
    std::shared_ptr<MeshModel> sceneModel_; // sceneMesh_'s, for bakes and the probe
    // What the views show: for a band field, render::bandDisplay's field (shared with a comparison
    // reading it on its thread).
    std::shared_ptr<const Field> field_;
    std::shared_ptr<const SparseField> band_; // the band field shown, if it is one
    std::string bandLine_;                    // render::BandDisplay::line of band_
    FieldInfo fieldInfo_;
    std::string fieldWarning_;
    Generation generation_;
    FieldLoad fieldLoad_;
    FieldComparison comparison_;
    // The field saved beside a model (MODEL.sdf) while the running load reads it: the model's
    // path and what was said of the model (the load's outcome is said after it); empty otherwise.
    struct SavedFieldLoad {
        std::string model, said;
    } savedField_;
    // The last comparison's sign differences, for the field (version) it was made with.
    struct SignErrors {
        std::string against; // the compared file's name; empty: none
        std::size_t count = 0, samples = 0;
        int fieldVersion = -1;
    } signErrors_;
    int comparisons_ = 0; // for redrawing: the crosses changed
    int comparedVersion_ = -1; // the field version the running comparison reads
    Message* loadSlot_ = nullptr; // where the running load was asked for (modelMessage_ or fieldMessage_)
    BakeSettings settings_;
    int threads_ = 0;
    int textureLimit_ = 2048;
    char meshPath_[1024] = "";
    char fieldPath_[1024] = "";
    char comparePath_[1024] = "";
    char surfacePath_[1024] = "";
    Message modelMessage_, generationMessage_, fieldMessage_, screenshotMessage_, sliceMessage_;
    std::uint64_t messagesSaid_ = 0; // an info message said before the last message is stale: greyed
    RecentFiles recent_;
    FileBrowser fileBrowser_;
    std::vector<std::string> pendingPaths_;
    // Undo: the steps back and forward, the state the last step left (edits are compared with it
    // once no widget is active), and the field a step in progress replaced.
    std::vector<UndoEntry> undo_, redo_;
    std::vector<SceneModel> committedModels_;
    BakeSettings committedSettings_;
    int committedThreads_ = 0;
    SlicePose committedSlice_;
    std::optional<UndoEntry> fieldStep_;
    // The scene changes without a step of its own: an undo or redo, or the saved field completing
    // a model's load.
    bool noUndoStep_ = false;
    // Overwrite confirmation: the file and the action (1 save the field, 2 export the surface).
    std::string overwritePath_;
    int overwriteAction_ = 0;
    bool askOverwrite_ = false;
    int recentSelected_ = -1;
    // The band bake's memory estimate for the scene and settings it was made for.
    struct BandEstimate {
        int meshVersion = -1, res = 0;
        double padding = 0.0, band = 0.0, bytes = 0.0, available = 0.0;
    };
    mutable BandEstimate bandEstimate_;
    int sliceCut_ = 0; // the user's cut-away choice; applied while the slice is shown
    bool pendingAdd_ = false, askAboutBake_ = false;
    bool userChoseViews_ = false;
    bool sceneDrag_[3] = {false, false, false};
    // What a left-drag does, from the modifiers at its press: orbit (as in MeshLab and polyscope),
    // or with Ctrl over a shown slice move it along its normal, with Ctrl+Shift tilt it.
    // A press on the slice's gizmo drags the plane without Ctrl: its arrow moves it, its ring tilts it.
    enum class LeftDrag { Orbit, MoveSlice, TiltSlice } leftDrag_ = LeftDrag::Orbit;
    render::SliceGizmo::Part gizmoDragged_ = render::SliceGizmo::Part::None;
    char slicePointText_[96] = "", sliceNormalText_[96] = ""; // the pose as typed (refreshed while not edited)
    bool probeOn_ = true, probeValid_ = false;
    // probe_ holds a reading of the scene shown (the last one, once the pointer left the scene):
    // the panel keeps it, so that its top line does not come and go under the pointer.
    bool probeKept_ = false;
    ProbeResult probe_;
    glm::ivec2 probePointer_{0, 0};
    RangeChoice sliceColours_, volumeColours_;
    ValueHistogram histogram_;
    int screenshotSize_[2] = {0, 0}; // 0 0: the scene area's size
    float panelWidth_ = 300.0f;
    float sceneAspect_ = 0.0f; // of the scene area (beside the panel) in the last frame; 0 before the first
    int meshVersion_ = 0, fieldVersion_ = 0;
    std::string lastSceneState_;
    long sceneDraws_ = 0;
    std::size_t lastDrawHash_ = 0;
    int settleFrames_ = 0;
    // Test hooks.
    std::string debugDir_;
    int frameDelayMs_ = 0;
    int screenshots_ = 0;
    bool announced_ = false;
    std::string layout_, lastLayout_, lastProbeLine_;
    std::string pendingOut_, readyOut_; // message lines for the test, printed a frame late
};

} // namespace sdfgen::app
