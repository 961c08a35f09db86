// "Sign errors": a cross at each sample where the field shown and the field it was compared with
// (the viewer's Compare, compareFields) lie on different sides of the surface.
#include "render/scene.hpp"

namespace sdfgen::render {
namespace {
class SignErrorsView : public View {
public:
    void draw(const ViewContext& c, Pass pass) override {
        if (pass == Pass::Blended) lines_.draw(c.frame, c.scene.signErrors, glm::vec4(1.0f, 0.2f, 0.85f, 1.0f));
    }

private:
    LineRenderer lines_;
};
} // namespace

extern const ViewType kSignErrorsView = {"sign_errors", "Sign errors",
                                         "crosses where the field and the one compared with it (the viewer's Compare) differ in sign", true, false, false,
                                         [] { return std::unique_ptr<View>(new SignErrorsView()); }, nullptr};

} // namespace sdfgen::render
