#include "render/renderers.hpp"

#include <cmath>

namespace sdfgen::render {

GridRenderer::GridRenderer() : program_("fullscreen.vert", "grid.frag") { glCreateVertexArrays(1, &vao_); }

void GridRenderer::draw(const FrameInfo& frame, float planeY) {
    program_.use();
    program_.set("inverseViewProjection", frame.inverseViewProjection);
    program_.set("viewProjection", frame.viewProjection);
    program_.set("planeY", planeY);
    // Minor lines a power of ten apart, about 10 to 100 of them across the scene.
    program_.set("cell", std::pow(10.0f, std::floor(std::log10(frame.sceneRadius * 0.2f))));
    program_.set("fadeDistance", std::max(frame.cameraDistance * 2.5f, frame.sceneRadius * 4.0f));
    glBindVertexArray(vao_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

} // namespace sdfgen::render
