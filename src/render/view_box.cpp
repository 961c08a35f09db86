// "Bounding box": the field's box as lines.
#include "render/scene.hpp"
#include "render/views.hpp"

namespace sdfgen::render {

void BoxView::draw(const ViewContext& c, Pass pass) {
    if (pass != Pass::Opaque || c.field.empty()) return;
    std::vector<glm::vec3> edges;
    auto corner = [&](int k) { return c.field.boxMin() + c.field.boxSize() * glm::vec3(float(k & 1), float((k >> 1) & 1), float((k >> 2) & 1)); };
    for (int a = 0; a < 8; ++a) {
        for (int axis = 0; axis < 3; ++axis) {
            const int b = a | (1 << axis);
            if (b == a) continue;
            edges.push_back(corner(a));
            edges.push_back(corner(b));
        }
    }
    lines_.draw(c.frame, edges, glm::vec4(0.95f, 0.8f, 0.2f, 1.0f));
}

extern const ViewType kBoxView = {"box", "Bounding box", "the field's box", true, false, makeView<BoxView>};

} // namespace sdfgen::render
