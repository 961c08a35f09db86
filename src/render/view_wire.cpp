// "Polygon": the meshes' edges; alone, only the visible ones (hidden-line removal).
#include "render/scene.hpp"
#include "render/views.hpp"

namespace sdfgen::render {

void WireView::draw(const ViewContext& c, Pass pass) {
    const Scene& s = c.scene;
    if (pass == Pass::Opaque) {
        // Without the shaded faces, their depth alone hides the edges behind them.
        if (!c.meshFacesDrawn && !seeThrough) c.meshes.drawDepth(c.frame, s.meshStyles, s.cutPlane());
        return;
    }
    if (seeThrough) glDisable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    c.meshes.drawWire(c.frame, s.meshStyles, s.cutPlane());
    glDepthFunc(GL_LESS);
    glEnable(GL_DEPTH_TEST);
}

void WireView::options(ViewOptions& ui, Scene&) { ui.checkbox("See-through", seeThrough, "Polygon shows hidden edges too"); }

extern const ViewType kWireView = {"wire", "Polygon", "the models' edges (See-through: hidden ones too)", false, false, makeView<WireView>};

} // namespace sdfgen::render
