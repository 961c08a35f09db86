// "Ray-marched": the field's level set at the iso level, sphere traced, with shadows and occlusion.
#include "render/scene.hpp"

namespace sdfgen::render {
namespace {
class RaymarchView : public View {
public:
    void draw(const ViewContext& c, Pass pass) override {
        const Scene& s = c.scene;
        // Where the cut enters the solid the slice shows the section; without it, a cap.
        if (pass == Pass::Opaque) raymarch_.draw(c.frame, c.field, s.shadows, s.iso, s.cutPlane(), !s.views["slice"]);
    }

private:
    RaymarchRenderer raymarch_;
};
} // namespace

extern const ViewType kRaymarchView = {"raymarch", "Ray-marched", "the field's surface (at the iso level), sphere traced with soft shadows",
                                       true, false, false, [] { return std::unique_ptr<View>(new RaymarchView()); },
                                       [](ViewOptions& ui, Scene& s) {
                                           const glm::vec2 range = s.hasField() ? s.effectiveRange(glm::vec2(0.0f)) : glm::vec2(-1.0f, 1.0f);
                                           ui.slider("Iso level", s.iso, range.x, range.y, "%.4g", false);
                                           ui.checkbox("Shadows + AO", s.shadows, "soft shadows and ambient occlusion from the field");
                                       }};

} // namespace sdfgen::render
