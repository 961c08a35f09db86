// "Grid": the infinite grid on the plane under the meshes.
#include "render/scene.hpp"
#include "render/views.hpp"

namespace sdfgen::render {

void GridView::draw(const ViewContext& c, Pass pass) {
    if (pass == Pass::Blended) grid_.draw(c.frame, c.scene.gridHeight());
}

extern const ViewType kGridView = {"grid", "Grid", "an infinite grid on the plane under the models (x axis red, z blue)", false, true,
                                   makeView<GridView>};

} // namespace sdfgen::render
