#pragma once
// The views as objects (polyscope's structures): each has a name (`render --view`), a label and a
// description (the viewer's checkbox and its tooltip), what it needs, and its draw. A view is one
// file, src/render/view_NAME.cpp, defining its View and its ViewType, plus its line in the
// registry (views.cpp); the Scene draws the views shown, and the viewer and `sdfgen render` list
// them from the registry.
#include "render/renderers.hpp"

#include <memory>
#include <vector>

namespace sdfgen::render {

class Scene;

// What a view draws with: the frame, the scene's settings and data, and the frame's targets.
struct ViewContext {
    const FrameInfo& frame;
    const Scene& scene;        // shared settings: views shown, slice plane and cut, colours, styles
    const FieldTexture& field; // empty when there is no field
    MeshRenderer& meshes;
    GLuint depthTexture;       // the opaque pass's depth
    GLuint colourOnlyTarget;   // a framebuffer with the frame's colour and no depth (to read the depth)
    GLuint target;             // the framebuffer of the frame's colour and depth
};

class View {
public:
    // Opaque: depth-tested, not blended; Blended: then, over them, with source-alpha blending.
    enum class Pass { Opaque, Blended };

    virtual ~View() = default;
    // Draws the view's part of `pass`; the views draw in the registry's order in each pass.
    virtual void draw(const ViewContext& context, Pass pass) = 0;
};

// The panel's controls for a view's settings (the viewer implements them with Dear ImGui); each
// returns whether the value changed.
class ViewOptions {
public:
    virtual ~ViewOptions() = default;
    virtual bool checkbox(const char* label, bool& value, const char* tooltip) = 0;
    virtual bool slider(const char* label, float& value, float min, float max, const char* format, bool logarithmic) = 0;
};

// A kind of view: its facts (usable without a GL context), how to make one (with a context), and
// its section of the panel.
struct ViewType {
    const char* name;        // e.g. "mesh"
    const char* label;       // e.g. "Coloured Model"
    const char* description; // a line for the tooltip and the help
    bool needsField;
    bool shownByDefault;
    bool colouredByDistance; // the colour bar goes with it
    std::unique_ptr<View> (*make)();
    void (*options)(ViewOptions& ui, Scene& scene); // its settings on the panel, or null
};

// Every view, in drawing order (views.cpp).
const std::vector<ViewType>& viewTypes();

} // namespace sdfgen::render
