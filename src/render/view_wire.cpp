// "Polygon": the meshes' edges; alone, only the visible ones (hidden-line removal).
#include "render/scene.hpp"

namespace sdfgen::render {
namespace {
class WireView : public View {
public:
    void draw(const ViewContext& c, Pass pass) override {
        const Scene& s = c.scene;
        if (pass == Pass::Opaque) {
            // Without the shaded faces, their depth alone hides the edges behind them.
            if (!s.views["mesh"] && !s.wireSeeThrough) c.meshes.drawDepth(c.frame, s.meshStyles, s.cutPlane());
            return;
        }
        if (s.wireSeeThrough) glDisable(GL_DEPTH_TEST);
        glDepthFunc(GL_LEQUAL);
        c.meshes.drawWire(c.frame, s.meshStyles, s.cutPlane());
        glDepthFunc(GL_LESS);
        glEnable(GL_DEPTH_TEST);
    }
};
} // namespace

extern const ViewType kWireView = {"wire", "Polygon", "the models' edges (See-through: hidden ones too)", false, false, false,
                                   [] { return std::unique_ptr<View>(new WireView()); },
                                   [](ViewOptions& ui, Scene& s) { ui.checkbox("See-through", s.wireSeeThrough, "Polygon shows hidden edges too"); }};

} // namespace sdfgen::render
