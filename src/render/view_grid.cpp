// "Grid": the infinite grid on the plane under the meshes.
#include "render/scene.hpp"

namespace sdfgen::render {
namespace {
class GridView : public View {
public:
    void draw(const ViewContext& c, Pass pass) override {
        if (pass == Pass::Blended) grid_.draw(c.frame, c.scene.gridHeight());
    }

private:
    GridRenderer grid_;
};
} // namespace

extern const ViewType kGridView = {"grid", "Grid", "an infinite grid on the plane under the models (x axis red, z blue)", false, true,
                                   false, [] { return std::unique_ptr<View>(new GridView()); }, nullptr};

} // namespace sdfgen::render
