// "Ray-marched": the field's level set at the iso level, sphere traced, with shadows and occlusion.
#include "render/scene.hpp"
#include "render/views.hpp"

#include <sstream>

namespace sdfgen::render {

void RaymarchView::draw(const ViewContext& c, Pass pass) {
    // Where the cut enters the solid a view drawing the section there shows it; without one, a cap.
    if (pass == Pass::Opaque) raymarch_.draw(c.frame, c.field, shadows, iso, c.scene.cutPlane(), !c.sectionOnCut);
}

void RaymarchView::options(ViewOptions& ui, Scene& s) {
    const glm::vec2 range = s.hasField() ? s.effectiveRange(glm::vec2(0.0f)) : glm::vec2(-1.0f, 1.0f);
    ui.slider("Iso level", iso, range.x, range.y, "%.4g", false);
    ui.checkbox("Shadows + AO", shadows, "soft shadows and ambient occlusion from the field");
}

std::string RaymarchView::settingsKey() const {
    std::ostringstream key;
    key << iso << ' ' << shadows;
    return key.str();
}

extern const ViewType kRaymarchView = {"raymarch", "Ray-marched", "the field's surface (at the iso level), sphere traced with soft shadows",
                                       true, false, makeView<RaymarchView>};

} // namespace sdfgen::render
