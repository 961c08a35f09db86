#include "render/renderers.hpp"
#include "sdfgen/error.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <algorithm>

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
    dims_ = d;
    voxel_ = float(field.grid.voxel);
    boxMin_ = glm::vec3(field.grid.origin);
    boxSize_ = glm::vec3(d) * voxel_;
}

void FieldTexture::setUniforms(Program& program) const {
    bind(0);
    program.set("field", 0);
    program.set("boxMin", boxMin_);
    program.set("boxSize", boxSize_);
    program.set("voxel", voxel_);
}

namespace {
void setRayUniforms(Program& program, const FrameInfo& frame) {
    program.set("inverseViewProjection", frame.inverseViewProjection);
    program.set("viewProjection", frame.viewProjection);
    program.set("eye", frame.eye);
}
} // namespace

VolumeRenderer::VolumeRenderer() : program_("fullscreen.vert", "volume.frag") { glCreateVertexArrays(1, &vao_); }

void VolumeRenderer::draw(const FrameInfo& frame, const FieldTexture& field, GLuint depthTexture, float density) {
    if (field.empty()) return;
    program_.use();
    setRayUniforms(program_, frame);
    field.setUniforms(program_);
    glBindTextureUnit(1, depthTexture);
    program_.set("sceneDepth", 1);
    program_.set("density", density);
    // The transfer function's length scale: the green shell is a few voxels thick.
    program_.set("band", 2.5f * field.voxel());
    glBindVertexArray(vao_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

RaymarchRenderer::RaymarchRenderer() : program_("fullscreen.vert", "raymarch.frag") { glCreateVertexArrays(1, &vao_); }

void RaymarchRenderer::draw(const FrameInfo& frame, const FieldTexture& field, bool shadows) {
    if (field.empty()) return;
    program_.use();
    setRayUniforms(program_, frame);
    field.setUniforms(program_);
    program_.set("shadows", shadows ? 1 : 0);
    glBindVertexArray(vao_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

SliceRenderer::SliceRenderer() : program_("slice.vert", "slice.frag") { glCreateVertexArrays(1, &vao_); }

void SliceRenderer::draw(const FrameInfo& frame, const FieldTexture& field, int axis, float position) {
    if (field.empty()) return;
    program_.use();
    program_.set("viewProjection", frame.viewProjection);
    field.setUniforms(program_);
    program_.set("axis", std::clamp(axis, 0, 2));
    program_.set("position", std::clamp(position, 0.0f, 1.0f));
    // Contours a power-of-two fraction of the box apart, about 24 across its longest side.
    const float longest = std::max({field.boxSize().x, field.boxSize().y, field.boxSize().z});
    program_.set("spacing", longest / 24.0f);
    program_.set("range", longest * 0.25f);
    glBindVertexArray(vao_);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
}

} // namespace sdfgen::render
