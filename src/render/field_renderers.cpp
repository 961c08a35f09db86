#include "render/renderers.hpp"
#include "sdfgen/error.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <algorithm>
#include <cmath>

namespace sdfgen::render {

FieldTexture::~FieldTexture() { clear(); }

void FieldTexture::clear() {
    if (texture_) glDeleteTextures(1, &texture_);
    texture_ = 0;
}

void FieldTexture::upload(const Field& field) {
    const glm::ivec3 d = field.grid.dims;
    GLint limit = 0;
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &limit);
    if (d.x > limit || d.y > limit || d.z > limit) {
        throw Error("field " + std::to_string(d.x) + "x" + std::to_string(d.y) + "x" + std::to_string(d.z) +
                    " is larger than this OpenGL driver's 3D texture limit of " + std::to_string(limit));
    }
    clear();
    glCreateTextures(GL_TEXTURE_3D, 1, &texture_);
    glTextureStorage3D(texture_, 1, GL_R32F, d.x, d.y, d.z);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage3D(texture_, 0, 0, 0, 0, d.x, d.y, d.z, GL_RED, GL_FLOAT, field.values.data());
    glTextureParameteri(texture_, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(texture_, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R}) {
        glTextureParameteri(texture_, wrap, GL_CLAMP_TO_EDGE);
    }
    voxel_ = float(field.grid.voxel);
    background_ = field.background;
    boxMin_ = glm::vec3(field.grid.origin);
    boxSize_ = glm::vec3(d) * voxel_;
}

void FieldTexture::setUniforms(Program& program) const {
    bind(0);
    program.set("field", 0);
    program.set("boxMin", boxMin_);
    program.set("boxSize", boxSize_);
    program.set("voxel", voxel_);
    program.set("background", background_);
}

namespace {
void setRayUniforms(Program& program, const FrameInfo& frame) {
    program.set("inverseViewProjection", frame.inverseViewProjection);
    program.set("viewProjection", frame.viewProjection);
    program.set("lightDirection", frame.lightDirection);
}
} // namespace

VolumeRenderer::VolumeRenderer() : program_("fullscreen.vert", "volume.frag") { glCreateVertexArrays(1, &vao_); }

void VolumeRenderer::draw(const FrameInfo& frame, const FieldTexture& field, GLuint depthTexture, float density, glm::vec2 range,
                          int colormap) {
    if (field.empty()) return;
    program_.use();
    setRayUniforms(program_, frame);
    field.setUniforms(program_);
    glBindTextureUnit(1, depthTexture);
    program_.set("sceneDepth", 1);
    program_.set("density", density);
    program_.set("range", range);
    program_.set("colormap", colormap);
    // The transfer function's length scale: the green shell is a few voxels thick (within a band
    // field's band).
    const float shell = 2.5f * field.voxel();
    program_.set("band", field.background() > 0.0f ? std::min(shell, 0.5f * field.background()) : shell);
    glBindVertexArray(vao_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

int raymarchSteps(glm::vec3 boxSize, float background) {
    // Beyond a band field's band the value is only the background (a lower bound of the distance),
    // so steps there are at most the background: enough of them to cross the box.
    int steps = 512;
    if (background > 0.0f) steps += int(std::min(glm::length(boxSize) / background, 7680.0f));
    return steps;
}

RaymarchRenderer::RaymarchRenderer() : program_("fullscreen.vert", "raymarch.frag") { glCreateVertexArrays(1, &vao_); }

void RaymarchRenderer::draw(const FrameInfo& frame, const FieldTexture& field, bool shadows, float iso, glm::vec4 cut, bool capCut) {
    if (field.empty()) return;
    program_.use();
    setRayUniforms(program_, frame);
    field.setUniforms(program_);
    program_.set("shadows", shadows ? 1 : 0);
    program_.set("iso", iso);
    program_.set("cutPlane", cut);
    program_.set("capCut", capCut ? 1 : 0);
    program_.set("hitDistance", kRaymarchHit);
    program_.set("minStep", kRaymarchMinStep);
    program_.set("maxSteps", raymarchSteps(field.boxSize(), field.background()));
    glBindVertexArray(vao_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

glm::vec4 slicePlane(glm::vec3 boxMin, glm::vec3 boxSize, glm::vec3 normal, float position) {
    float lowest = INFINITY, highest = -INFINITY;
    for (int c = 0; c < 8; ++c) {
        const glm::vec3 corner = boxMin + boxSize * glm::vec3(float(c & 1), float((c >> 1) & 1), float((c >> 2) & 1));
        lowest = std::min(lowest, glm::dot(normal, corner));
        highest = std::max(highest, glm::dot(normal, corner));
    }
    // Kept a hair inside the box so that an axis-aligned plane at 0 or 1 still cuts it.
    return glm::vec4(normal, lowest + (highest - lowest) * std::clamp(position, 1e-4f, 1.0f - 1e-4f));
}

float slicePositionThrough(glm::vec3 boxMin, glm::vec3 boxSize, glm::vec3 normal, glm::vec3 point) {
    float lowest = INFINITY, highest = -INFINITY;
    for (int c = 0; c < 8; ++c) {
        const glm::vec3 corner = boxMin + boxSize * glm::vec3(float(c & 1), float((c >> 1) & 1), float((c >> 2) & 1));
        lowest = std::min(lowest, glm::dot(normal, corner));
        highest = std::max(highest, glm::dot(normal, corner));
    }
    return highest > lowest ? (glm::dot(normal, point) - lowest) / (highest - lowest) : 0.5f;
}

std::vector<glm::vec3> slicePolygon(glm::vec3 boxMin, glm::vec3 boxSize, glm::vec3 normal, float position) {
    glm::vec3 corners[8];
    for (int c = 0; c < 8; ++c) corners[c] = boxMin + boxSize * glm::vec3(float(c & 1), float((c >> 1) & 1), float((c >> 2) & 1));
    const float level = slicePlane(boxMin, boxSize, normal, position).w;
    std::vector<glm::vec3> points;
    for (int a = 0; a < 8; ++a) {
        for (int axis = 0; axis < 3; ++axis) {
            const int b = a | (1 << axis);
            if (b == a) continue; // each of the 12 edges once, from its lower corner
            const float da = glm::dot(normal, corners[a]) - level, db = glm::dot(normal, corners[b]) - level;
            if ((da < 0.0f) == (db < 0.0f)) continue;
            points.push_back(glm::mix(corners[a], corners[b], da / (da - db)));
        }
    }
    if (points.size() < 3) return {};
    // The cut is convex: order its corners by angle about their centre, in the plane.
    glm::vec3 centre(0.0f);
    for (const glm::vec3& p : points) centre += p;
    centre /= float(points.size());
    const glm::vec3 u = glm::normalize(points[0] - centre + glm::vec3(1e-12f));
    const glm::vec3 v = glm::cross(normal, u);
    std::sort(points.begin(), points.end(), [&](const glm::vec3& p, const glm::vec3& q) {
        return std::atan2(glm::dot(p - centre, v), glm::dot(p - centre, u)) < std::atan2(glm::dot(q - centre, v), glm::dot(q - centre, u));
    });
    return points;
}

SliceRenderer::SliceRenderer() : program_("slice.vert", "slice.frag") { glCreateVertexArrays(1, &vao_); }

void SliceRenderer::draw(const FrameInfo& frame, const FieldTexture& field, glm::vec3 normal, float position, glm::vec2 range,
                         int colormap) {
    if (field.empty()) return;
    const std::vector<glm::vec3> polygon = slicePolygon(field.boxMin(), field.boxSize(), normal, position);
    if (polygon.empty()) return;
    program_.use();
    program_.set("viewProjection", frame.viewProjection);
    field.setUniforms(program_);
    glUniform3fv(glGetUniformLocation(program_.id(), "corners"), GLsizei(polygon.size()), &polygon[0].x);
    // Contours a fixed fraction of the box apart, about 24 across its longest side.
    const float longest = std::max({field.boxSize().x, field.boxSize().y, field.boxSize().z});
    program_.set("spacing", longest / 24.0f);
    program_.set("range", range);
    program_.set("colormap", colormap);
    glBindVertexArray(vao_);
    glDrawArrays(GL_TRIANGLE_FAN, 0, GLsizei(polygon.size()));
}

} // namespace sdfgen::render
