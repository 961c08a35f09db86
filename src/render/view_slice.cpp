// "Slice": signed distance on the scene's cut plane through the field's box, with contours.
#include "render/scene.hpp"
#include "render/views.hpp"

#include <glm/geometric.hpp>
#include <sstream>

namespace sdfgen::render {

void SliceView::draw(const ViewContext& c, Pass pass) {
    const Scene& s = c.scene;
    if (pass == Pass::Opaque) slice_.draw(c.frame, c.field, glm::normalize(s.sliceNormal), s.slicePosition, s.effectiveRange(range), s.colormap);
}

void SliceView::options(ViewOptions& ui, Scene& s) { ui.slider("Slice position", s.slicePosition, 0.0f, 1.0f, "%.3f", false); }

std::string SliceView::settingsKey() const {
    std::ostringstream key;
    key << range.x << ' ' << range.y;
    return key.str();
}

extern const ViewType kSliceView = {"slice", "Slice", "the signed distance on a plane at any orientation, with contours", true, false,
                                    makeView<SliceView>};

} // namespace sdfgen::render
