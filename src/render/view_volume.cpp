// "SDF volume": the field ray-marched as a coloured volume, stopping at the opaque views' depth.
#include "render/scene.hpp"

namespace sdfgen::render {
namespace {
class VolumeView : public View {
public:
    void draw(const ViewContext& c, Pass pass) override {
        if (pass != Pass::Blended || c.field.empty()) return;
        const Scene& s = c.scene;
        // It reads the depth texture, so it draws through the framebuffer without it.
        glBindFramebuffer(GL_FRAMEBUFFER, c.colourOnlyTarget);
        glDisable(GL_DEPTH_TEST);
        glBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE); // premultiplied
        volume_.draw(c.frame, c.field, c.depthTexture, s.volumeDensity, s.effectiveRange(s.volumeRange), s.colormap);
        glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
        glEnable(GL_DEPTH_TEST);
        glBindFramebuffer(GL_FRAMEBUFFER, c.target);
    }

private:
    VolumeRenderer volume_;
};
} // namespace

extern const ViewType kVolumeView = {"volume", "SDF volume", "the field as a coloured volume: a shell at the surface, inside and haze",
                                     true, false, true, [] { return std::unique_ptr<View>(new VolumeView()); },
                                     [](ViewOptions& ui, Scene& s) { ui.slider("Volume density", s.volumeDensity, 0.1f, 5.0f, "%.2f", true); }};

} // namespace sdfgen::render
