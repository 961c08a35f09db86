// "SDF volume": the field ray-marched as a coloured volume, stopping at the opaque views' depth.
#include "render/scene.hpp"
#include "render/views.hpp"

#include <sstream>

namespace sdfgen::render {

void VolumeView::draw(const ViewContext& c, Pass pass) {
    if (pass != Pass::Blended || c.field.empty()) return;
    const Scene& s = c.scene;
    // It reads the depth texture, so it draws through the framebuffer without it.
    glBindFramebuffer(GL_FRAMEBUFFER, c.colourOnlyTarget);
    glDisable(GL_DEPTH_TEST);
    glBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE); // premultiplied
    volume_.draw(c.frame, c.field, c.depthTexture, density, s.effectiveRange(range), s.colormap);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
    glEnable(GL_DEPTH_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, c.target);
}

void VolumeView::options(ViewOptions& ui, Scene&) { ui.slider("Volume density", density, 0.1f, 5.0f, "%.2f", true); }

std::string VolumeView::settingsKey() const {
    std::ostringstream key;
    key << density << ' ' << range.x << ' ' << range.y;
    return key.str();
}

extern const ViewType kVolumeView = {"volume", "SDF volume", "the field as a coloured volume: a shell at the surface, inside and haze", true,
                                     false, makeView<VolumeView>};

} // namespace sdfgen::render
