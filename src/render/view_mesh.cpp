// "Coloured Model": the scene's meshes, flat-shaded, each in its colour.
#include "render/scene.hpp"
#include "render/views.hpp"

namespace sdfgen::render {

void MeshView::draw(const ViewContext& c, Pass pass) {
    if (pass == Pass::Opaque) c.meshes.drawShaded(c.frame, c.scene.meshStyles, c.scene.cutPlane());
}

extern const ViewType kMeshView = {"mesh", "Coloured Model", "the models, flat-shaded (Lambert), each in its own colour", false, true,
                                   makeView<MeshView>};

} // namespace sdfgen::render
