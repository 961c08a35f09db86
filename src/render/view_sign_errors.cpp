// "Sign errors": a cross at each sample where the field shown and the field it was compared with
// (the viewer's Compare, compareFields) lie on different sides of the surface.
#include "render/scene.hpp"
#include "render/views.hpp"

namespace sdfgen::render {

void SignErrorsView::draw(const ViewContext& c, Pass pass) {
    if (pass == Pass::Blended) lines_.draw(c.frame, crosses, glm::vec4(1.0f, 0.2f, 0.85f, 1.0f));
}

extern const ViewType kSignErrorsView = {"sign_errors", "Sign errors",
                                         "crosses where the field and the one compared with it (the viewer's Compare) differ in sign", true, false,
                                         makeView<SignErrorsView>};

} // namespace sdfgen::render
