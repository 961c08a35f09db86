#include "render/scene.hpp"
#include "sdfgen/error.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_inverse.hpp>
#include <algorithm>
#include <cmath>
#include <optional>

namespace sdfgen::render {

Scene::Scene() {
    for (const ViewType& type : viewTypes()) views_.push_back(type.make(type));
}

void Scene::showOnly(const std::vector<bool>& shown) {
    for (std::size_t i = 0; i < views_.size(); ++i) views_[i]->enabled = i < shown.size() && shown[i];
}

bool Scene::sectionOnCut() const {
    for (const std::unique_ptr<View>& v : views_) {
        if (v->enabled && v->drawsSectionOnCut()) return true;
    }
    return false;
}


Scene::~Scene() {
    glDeleteFramebuffers(1, &fbo_);
    glDeleteFramebuffers(1, &colourOnlyFbo_);
    glDeleteTextures(1, &colour_);
    glDeleteTextures(1, &depth_);
}

glm::vec3 axisNormal(int axis) {
    glm::vec3 n(0.0f);
    n[std::clamp(axis, 0, 2)] = 1.0f;
    return n;
}

void Scene::setMesh(const Mesh& mesh) {
    setMeshes({{&mesh, glm::dmat4(1.0)}});
    gridHeight_ = float(mesh.worldBounds().min.y);
}

void Scene::setMeshes(const std::vector<MeshInstance>& parts) {
    mesh_.setMeshes(parts);
    gridHeight_ = mesh_.lowestY();
    meshStyles.clear();
    for (std::size_t i = 0; i < parts.size(); ++i) meshStyles.push_back({meshColour(i), true});
}

glm::vec2 Scene::effectiveRange(glm::vec2 range) const {
    if (range != glm::vec2(0.0f)) return range;
    // A band field's values span the band only: its colours do too.
    if (field_.background() > 0.0f) return glm::vec2(-field_.background(), field_.background());
    const glm::vec3 box = field_.boxSize();
    const float r = std::max(0.25f * std::max({box.x, box.y, box.z}), 1e-6f);
    return glm::vec2(-r, r);
}

glm::vec4 Scene::cutPlane() const {
    if (sliceCut == 0 || field_.empty()) return glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    const glm::vec4 plane = slicePlane(field_.boxMin(), field_.boxSize(), glm::normalize(sliceNormal), slicePosition);
    return sliceCut > 0 ? plane : -plane;
}

std::vector<glm::vec3> SliceGizmo::segments(Part part) const {
    std::vector<glm::vec3> out;
    if (size <= 0.0f || part == Part::None) return out;
    // Two directions in the plane.
    const glm::vec3 helper = std::abs(normal.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    const glm::vec3 u = glm::normalize(glm::cross(normal, helper)), v = glm::cross(normal, u);
    if (part == Part::Arrow) {
        const glm::vec3 tip = centre + normal * size, head = tip - normal * (0.2f * size);
        out = {centre, tip};
        for (int k = 0; k < 4; ++k) { // the head: four barbs
            const float a = float(k) * 1.5707964f;
            out.push_back(tip);
            out.push_back(head + 0.08f * size * (std::cos(a) * u + std::sin(a) * v));
        }
        return out;
    }
    constexpr int kSides = 48;
    for (int k = 0; k < kSides; ++k) {
        const float a0 = float(k) * 6.2831853f / kSides, a1 = float(k + 1) * 6.2831853f / kSides;
        out.push_back(centre + size * (std::cos(a0) * u + std::sin(a0) * v));
        out.push_back(centre + size * (std::cos(a1) * u + std::sin(a1) * v));
    }
    return out;
}

SliceGizmo Scene::sliceGizmo() const {
    SliceGizmo gizmo;
    if (field_.empty()) return gizmo;
    gizmo.normal = glm::normalize(sliceNormal);
    const glm::vec4 plane = slicePlane(field_.boxMin(), field_.boxSize(), gizmo.normal, slicePosition);
    const glm::vec3 centre = field_.boxMin() + 0.5f * field_.boxSize();
    gizmo.centre = centre + gizmo.normal * (plane.w - glm::dot(gizmo.normal, centre));
    gizmo.size = 0.3f * std::min({field_.boxSize().x, field_.boxSize().y, field_.boxSize().z, 0.5f * glm::length(field_.boxSize())});
    return gizmo;
}

std::vector<ColourBar> Scene::colourBars() const {
    std::vector<ColourBar> bars;
    for (const std::unique_ptr<View>& v : views_) {
        const std::optional<glm::vec2> range = v->colourRange();
        if (!v->enabled || !range) continue;
        const ColourBar bar{effectiveRange(*range), v->type().name};
        if (std::none_of(bars.begin(), bars.end(), [&](const ColourBar& b) { return b.range == bar.range; })) bars.push_back(bar);
    }
    if (bars.size() == 1) bars[0].name = nullptr; // one range: the bar needs no name
    return bars;
}

glm::vec2 fieldValueRange(const Field& field) {
    glm::vec2 range(0.0f);
    for (const float v : field.values) range = glm::vec2(std::min(range.x, v), std::max(range.y, v));
    return range;
}

glm::vec2 sliceValueRange(const Field& field, glm::vec3 normal, float position) {
    // The slice shows the field interpolated between the samples around it: every sample at a
    // corner of a voxel cell the plane crosses, i.e. within h * (|nx| + |ny| + |nz|) of it. (Half
    // a voxel would miss both layers when the plane lies midway between them, by rounding.)
    const Grid& g = field.grid;
    const float h = float(g.voxel);
    const glm::vec3 boxMin(g.origin), boxSize = glm::vec3(g.dims) * h;
    const glm::vec4 plane = slicePlane(boxMin, boxSize, normal, position);
    const float reach = h * (std::abs(normal.x) + std::abs(normal.y) + std::abs(normal.z));
    glm::vec2 range(0.0f);
    for (int k = 0; k < g.dims.z; ++k) {
        for (int j = 0; j < g.dims.y; ++j) {
            for (int i = 0; i < g.dims.x; ++i) {
                const glm::vec3 p = boxMin + (glm::vec3(i, j, k) + 0.5f) * h;
                if (std::abs(glm::dot(glm::vec3(plane), p) - plane.w) > reach) continue;
                const float v = field.values[(std::size_t(k) * std::size_t(g.dims.y) + std::size_t(j)) * std::size_t(g.dims.x) + std::size_t(i)];
                range = glm::vec2(std::min(range.x, v), std::max(range.y, v));
            }
        }
    }
    return range;
}
void Scene::clearMesh() {
    mesh_.clear();
    meshStyles.clear();
    gridHeight_ = field_.empty() ? 0.0f : field_.boxMin().y;
}
void Scene::setField(const Field& field) {
    field_.upload(field);
    if (mesh_.empty()) gridHeight_ = field_.boxMin().y; // a field alone stands on the grid too
}
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

    FrameInfo& frame = frame_;
    frame.view = camera.view();
    frame.projection = camera.projection(float(size.x) / float(size.y));
    frame.viewProjection = frame.projection * frame.view;
    frame.inverseViewProjection = glm::inverse(frame.viewProjection);
    frame.eye = camera.orthographic ? camera.target + (camera.eye() - camera.target) * 1e4f : camera.eye();
    // The headlight comes from above and to the right of the camera; the fixed light from above.
    const glm::mat4 cameraToWorld = glm::inverse(frame.view);
    frame.lightDirection = headlight ? glm::normalize(glm::vec3(cameraToWorld * glm::vec4(0.35f, 0.55f, 1.0f, 0.0f)))
                                     : glm::normalize(glm::vec3(0.45f, 0.8f, 0.35f));
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
    bool meshFacesDrawn = false;
    for (const std::unique_ptr<View>& v : views_) meshFacesDrawn |= v->enabled && v->drawsMeshFaces();
    const ViewContext context{frame, *this, field_, mesh_, meshFacesDrawn, sectionOnCut(), depth_, colourOnlyFbo_, fbo_};
    for (const std::unique_ptr<View>& v : views_) {
        if (v->enabled) v->draw(context, View::Pass::Opaque);
    }

    // Then the blended ones, keeping the destination alpha at 1.
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
    for (const std::unique_ptr<View>& v : views_) {
        if (v->enabled) v->draw(context, View::Pass::Blended);
    }
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
    glDisable(GL_DEPTH_TEST);
    if (!markers.empty()) lines_.draw(frame, markers, glm::vec4(1.0f, 0.95f, 0.2f, 1.0f));
    if (sliceGizmoShown && sectionOnCut() && !field_.empty()) {
        const SliceGizmo gizmo = sliceGizmo();
        using Part = SliceGizmo::Part;
        for (const Part part : {Part::Arrow, Part::Ring}) {
            const glm::vec4 colour = part == sliceGizmoHighlight ? glm::vec4(1.0f) : part == Part::Arrow ? glm::vec4(1.0f, 0.55f, 0.15f, 1.0f)
                                                                                                          : glm::vec4(0.3f, 0.8f, 1.0f, 1.0f);
            lines_.draw(frame, gizmo.segments(part), colour);
        }
    }
    if (colourBar && !field_.empty()) {
        const std::vector<ColourBar> bars = colourBars();
        if (!bars.empty()) colourBar_.draw(size, bars, colormap, "(model units)");
    }
    glEnable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    present(target);
}

void Scene::present(GLuint target) {
    if (!fbo_) return;
    const glm::ivec2 size = targetSize_;

    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target);
    glBlitFramebuffer(0, 0, size.x, size.y, 0, 0, size.x, size.y, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, target);
}

Image Scene::image() const {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    Image image = readFramebuffer(targetSize_.x, targetSize_.y);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    return image;
}

namespace {
// The normalized device coordinates of a pixel's centre (pixels from the top left).
glm::vec2 pixelNdc(glm::ivec2 pixel, glm::ivec2 size) {
    return glm::vec2((float(pixel.x) + 0.5f) / float(size.x) * 2.0f - 1.0f, 1.0f - (float(pixel.y) + 0.5f) / float(size.y) * 2.0f);
}
} // namespace

bool Scene::surfaceAt(glm::ivec2 pixel, glm::vec3& point) {
    if (!fbo_ || pixel.x < 0 || pixel.y < 0 || pixel.x >= targetSize_.x || pixel.y >= targetSize_.y) return false;
    float depth = 1.0f;
    glGetTextureSubImage(depth_, 0, pixel.x, targetSize_.y - 1 - pixel.y, 0, 1, 1, 1, GL_DEPTH_COMPONENT, GL_FLOAT, sizeof(depth), &depth);
    if (depth >= 1.0f) return false;
    const glm::vec4 p = frame_.inverseViewProjection * glm::vec4(pixelNdc(pixel, targetSize_), depth * 2.0f - 1.0f, 1.0f);
    point = glm::vec3(p) / p.w;
    return true;
}

bool Scene::pixelRay(glm::ivec2 pixel, glm::vec3& origin, glm::vec3& direction) const {
    if (!fbo_ || pixel.x < 0 || pixel.y < 0 || pixel.x >= targetSize_.x || pixel.y >= targetSize_.y) return false;
    const glm::vec2 ndc = pixelNdc(pixel, targetSize_);
    const glm::vec4 nearPoint = frame_.inverseViewProjection * glm::vec4(ndc, -1.0f, 1.0f);
    const glm::vec4 farPoint = frame_.inverseViewProjection * glm::vec4(ndc, 1.0f, 1.0f);
    origin = glm::vec3(nearPoint) / nearPoint.w;
    direction = glm::normalize(glm::vec3(farPoint) / farPoint.w - origin);
    return true;
}

} // namespace sdfgen::render
