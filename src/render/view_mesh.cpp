// "Coloured Model": the scene's meshes, flat-shaded, each in its colour.
#include "render/scene.hpp"

namespace sdfgen::render {
namespace {
class MeshView : public View {
public:
    void draw(const ViewContext& c, Pass pass) override {
        if (pass == Pass::Opaque) c.meshes.drawShaded(c.frame, c.scene.meshStyles, c.scene.cutPlane());
    }
};
} // namespace

extern const ViewType kMeshView = {"mesh", "Coloured Model", "the models, flat-shaded (Lambert), each in its own colour", false, true,
                                   false, [] { return std::unique_ptr<View>(new MeshView()); }, nullptr};

} // namespace sdfgen::render
