// "Slice": signed distance on a plane through the field's box, with contours.
#include "render/scene.hpp"

#include <glm/geometric.hpp>

namespace sdfgen::render {
namespace {
class SliceView : public View {
public:
    void draw(const ViewContext& c, Pass pass) override {
        const Scene& s = c.scene;
        if (pass == Pass::Opaque) slice_.draw(c.frame, c.field, glm::normalize(s.sliceNormal), s.slicePosition, s.effectiveRange(s.sliceRange), s.colormap);
    }

private:
    SliceRenderer slice_;
};
} // namespace

extern const ViewType kSliceView = {"slice", "Slice", "the signed distance on a plane at any orientation, with contours", true, false,
                                    true, [] { return std::unique_ptr<View>(new SliceView()); },
                                    [](ViewOptions& ui, Scene& s) { ui.slider("Slice position", s.slicePosition, 0.0f, 1.0f, "%.3f", false); }};

} // namespace sdfgen::render
