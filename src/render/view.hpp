#pragma once
// The views as objects (polyscope's quantities): each owns whether it is shown, its settings, its
// controls on the viewer's panel and its draw. A view is one file, src/render/view_NAME.cpp,
// defining its View and its ViewType, plus its line in the registry (views.cpp); the Scene makes
// one of each, draws those shown, and the viewer and `sdfgen render` list them from the registry.
// What the views share (the cut plane, the colour map, the meshes' styles) is the Scene's; a view
// never asks for another by name, only for what the frame holds (ViewContext).
#include "render/renderers.hpp"

#include <glm/vec2.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace sdfgen::render {

class Scene;
struct ViewType;

// What a view draws with: the frame, the scene's shared settings and data, and the frame's targets.
struct ViewContext {
    const FrameInfo& frame;
    const Scene& scene;        // the cut plane, the colour map, the meshes' styles, the field's box
    const FieldTexture& field; // empty when there is no field
    MeshRenderer& meshes;
    bool meshFacesDrawn;       // a shown view draws the meshes' faces (View::drawsMeshFaces)
    bool sectionOnCut;         // a shown view draws the field on the cut plane (View::drawsSectionOnCut)
    GLuint depthTexture;       // the opaque pass's depth
    GLuint colourOnlyTarget;   // a framebuffer with the frame's colour and no depth (to read the depth)
    GLuint target;             // the framebuffer of the frame's colour and depth
};

// The panel's controls for a view's settings (the viewer implements them with Dear ImGui); each
// returns whether the value changed.
class ViewOptions {
public:
    virtual ~ViewOptions() = default;
    virtual bool checkbox(const char* label, bool& value, const char* tooltip) = 0;
    virtual bool slider(const char* label, float& value, float min, float max, const char* format, bool logarithmic) = 0;
};

class View {
public:
    // Opaque: depth-tested, not blended; Blended: then, over them, with source-alpha blending.
    enum class Pass { Opaque, Blended };

    explicit View(const ViewType& type);
    virtual ~View() = default;
    View(const View&) = delete;
    View& operator=(const View&) = delete;

    const ViewType& type() const { return type_; }
    bool enabled; // shown: its checkbox (ViewType::shownByDefault at first)

    // Draws the view's part of `pass`; the views draw in the registry's order in each pass.
    virtual void draw(const ViewContext& context, Pass pass) = 0;
    // Its settings on the panel, while it is shown.
    virtual void options(ViewOptions&, Scene&) {}
    // Its settings as text: the viewer redraws the scene when it changes.
    virtual std::string settingsKey() const { return {}; }
    // Where it is coloured by signed distance: the range its colours span as set ((0, 0):
    // Scene::effectiveRange's automatic one), for the colour bar.
    virtual std::optional<glm::vec2> colourRange() const { return std::nullopt; }
    // What other views draw around it: the meshes' faces (whose depth hides edges behind them),
    // and the field's section on the cut plane (where a cut surface then needs no cap).
    virtual bool drawsMeshFaces() const { return false; }
    virtual bool drawsSectionOnCut() const { return false; }

private:
    const ViewType& type_;
};

// A kind of view: its facts (usable without a GL context) and how to make one (with a context).
struct ViewType {
    const char* name;        // e.g. "mesh" (`render --view`)
    const char* label;       // e.g. "Coloured Model" (the panel's checkbox)
    const char* description; // a line for the tooltip and the help
    bool needsField;
    bool shownByDefault;
    std::unique_ptr<View> (*make)(const ViewType& type);
};

template <class V>
std::unique_ptr<View> makeView(const ViewType& type) {
    return std::make_unique<V>(type);
}

// Every view, in drawing order (views.cpp).
const std::vector<ViewType>& viewTypes();

// Which views a comma-separated list of names (or "all", "none") shows: one flag per viewTypes()
// entry. Throws Error naming a word that is not a view.
std::vector<bool> parseViewList(const std::string& list);
// The registered names, comma-separated, for help texts.
std::string viewNames();

} // namespace sdfgen::render
