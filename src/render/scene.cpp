#include "render/scene.hpp"
#include "sdfgen/error.hpp"

#include <glm/gtc/matrix_inverse.hpp>
#include <sstream>

namespace sdfgen::render {

Views Views::parse(const std::string& list) {
    Views v;
    v.grid = v.mesh = false;
    std::stringstream in(list);
    std::string word;
    while (std::getline(in, word, ',')) {
        if (word == "grid") v.grid = true;
        else if (word == "mesh") v.mesh = true;
        else if (word == "wire") v.wire = true;
        else if (word == "volume") v.volume = true;
        else if (word == "raymarch") v.raymarch = true;
        else if (word == "slice") v.slice = true;
        else if (word == "all") v.grid = v.mesh = v.wire = v.volume = v.raymarch = v.slice = true;
        else if (word == "none" || word.empty()) continue;
        else throw Error("unknown view '" + word + "' (expected grid, mesh, wire, volume, raymarch, slice, all or none)");
    }
    return v;
}

Scene::Scene() = default;

Scene::~Scene() {
    glDeleteFramebuffers(1, &fbo_);
    glDeleteFramebuffers(1, &colourOnlyFbo_);
    glDeleteTextures(1, &colour_);
    glDeleteTextures(1, &depth_);
}

void Scene::setMesh(const Mesh& mesh) { mesh_.setMesh(mesh); }
void Scene::clearMesh() { mesh_.clear(); }
void Scene::setField(const Field& field) { field_.upload(field); }
void Scene::clearField() { field_.clear(); }

void Scene::resizeTargets(glm::ivec2 size) {
    if (size == targetSize_ && fbo_) return;
    glDeleteFramebuffers(1, &fbo_);
    glDeleteFramebuffers(1, &colourOnlyFbo_);
    glDeleteTextures(1, &colour_);
    glDeleteTextures(1, &depth_);
    glCreateTextures(GL_TEXTURE_2D, 1, &colour_);
    glTextureStorage2D(colour_, 1, GL_RGBA8, size.x, size.y);
    glCreateTextures(GL_TEXTURE_2D, 1, &depth_);
    glTextureStorage2D(depth_, 1, GL_DEPTH_COMPONENT32F, size.x, size.y);
    glTextureParameteri(depth_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(depth_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glCreateFramebuffers(1, &fbo_);
    glNamedFramebufferTexture(fbo_, GL_COLOR_ATTACHMENT0, colour_, 0);
    glNamedFramebufferTexture(fbo_, GL_DEPTH_ATTACHMENT, depth_, 0);
    // The volume pass reads the depth texture, so it draws through a framebuffer without it.
    glCreateFramebuffers(1, &colourOnlyFbo_);
    glNamedFramebufferTexture(colourOnlyFbo_, GL_COLOR_ATTACHMENT0, colour_, 0);
    if (glCheckNamedFramebufferStatus(fbo_, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE ||
        glCheckNamedFramebufferStatus(colourOnlyFbo_, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        throw Error("OpenGL: the offscreen framebuffer is incomplete");
    }
    targetSize_ = size;
}

void Scene::draw(const OrbitCamera& camera, glm::ivec2 size, GLuint target) {
    if (size.x < 1 || size.y < 1) return;
    resizeTargets(size);

    FrameInfo frame;
    frame.view = camera.view();
    frame.projection = camera.projection(float(size.x) / float(size.y));
    frame.viewProjection = frame.projection * frame.view;
    frame.inverseViewProjection = glm::inverse(frame.viewProjection);
    frame.eye = camera.eye();
    frame.size = size;
    frame.cameraDistance = camera.distance;
    frame.sceneRadius = camera.sceneRadius;

    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glViewport(0, 0, size.x, size.y);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_CULL_FACE);
    glDepthMask(GL_TRUE);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glClearColor(background.r, background.g, background.b, 1.0f);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

    // Opaque views first, depth-tested against each other.
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_BLEND);
    if (views.mesh) mesh_.drawShaded(frame);
    if (views.slice) slice_.draw(frame, field_, sliceAxis, slicePosition);
    if (views.raymarch) raymarch_.draw(frame, field_, shadows);

    // Then the blended ones, keeping the destination alpha at 1.
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
    if (views.wire) {
        glDepthFunc(GL_LEQUAL);
        mesh_.drawWire(frame);
        glDepthFunc(GL_LESS);
    }
    if (views.grid) grid_.draw(frame);
    if (views.volume && !field_.empty()) {
        glBindFramebuffer(GL_FRAMEBUFFER, colourOnlyFbo_);
        glDisable(GL_DEPTH_TEST);
        glBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE); // premultiplied
        volume_.draw(frame, field_, depth_, volumeDensity);
        glEnable(GL_DEPTH_TEST);
    }
    glDisable(GL_BLEND);

    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target);
    glBlitFramebuffer(0, 0, size.x, size.y, 0, 0, size.x, size.y, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, target);
}

} // namespace sdfgen::render
