#include "render/renderers.hpp"

#include <glm/geometric.hpp>
#include <algorithm>
#include <cmath>
#include <vector>

namespace sdfgen::render {

MeshRenderer::MeshRenderer() : program_("mesh.vert", "mesh.frag") {
    glCreateVertexArrays(1, &vao_);
    glCreateBuffers(1, &vbo_);
    glVertexArrayVertexBuffer(vao_, 0, vbo_, 0, sizeof(float) * 6);
    glEnableVertexArrayAttrib(vao_, 0);
    glEnableVertexArrayAttrib(vao_, 1);
    glVertexArrayAttribFormat(vao_, 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribFormat(vao_, 1, 3, GL_FLOAT, GL_FALSE, sizeof(float) * 3);
    glVertexArrayAttribBinding(vao_, 0, 0);
    glVertexArrayAttribBinding(vao_, 1, 0);
}

MeshRenderer::~MeshRenderer() {
    glDeleteBuffers(1, &vbo_);
    glDeleteVertexArrays(1, &vao_);
}

glm::vec3 meshColour(std::size_t index) {
    // Orange first, then hues far apart and light enough for the shading to read.
    static const glm::vec3 palette[] = {{0.85f, 0.62f, 0.42f}, {0.45f, 0.68f, 0.88f}, {0.55f, 0.8f, 0.45f}, {0.86f, 0.5f, 0.72f},
                                        {0.9f, 0.82f, 0.4f},   {0.55f, 0.82f, 0.8f},  {0.7f, 0.6f, 0.9f},  {0.9f, 0.45f, 0.42f}};
    return palette[index % (sizeof(palette) / sizeof(palette[0]))];
}

void MeshRenderer::setMeshes(const std::vector<MeshInstance>& parts) {
    // Flat shading: three vertices per triangle, each with the face normal.
    std::vector<float> data;
    ranges_.clear();
    lowestY_ = INFINITY;
    for (const MeshInstance& part : parts) {
        const Mesh& mesh = *part.mesh;
        ranges_.emplace_back(GLint(data.size() / 6), GLsizei(mesh.triangleCount() * 3));
        const bool placed = part.transform != glm::dmat4(1.0);
        for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
            glm::dvec3 corners[3];
            for (int c = 0; c < 3; ++c) {
                // Drawn in world coordinates, like the field's box.
                corners[c] = mesh.toWorld(glm::dvec3(mesh.vertex(t, c)));
                if (placed) corners[c] = glm::dvec3(part.transform * glm::dvec4(corners[c], 1.0));
            }
            const glm::vec3 n = placed ? glm::vec3(glm::normalize(glm::cross(corners[1] - corners[0], corners[2] - corners[0])))
                                       : mesh.faceNormals[t];
            for (const glm::dvec3& corner : corners) {
                const glm::vec3 p(corner);
                lowestY_ = std::min(lowestY_, p.y);
                data.insert(data.end(), {p.x, p.y, p.z, n.x, n.y, n.z});
            }
        }
    }
    glNamedBufferData(vbo_, GLsizeiptr(data.size() * sizeof(float)), data.data(), GL_STATIC_DRAW);
    if (data.empty()) lowestY_ = 0.0f;
}

void MeshRenderer::clear() {
    glNamedBufferData(vbo_, 0, nullptr, GL_STATIC_DRAW);
    ranges_.clear();
}

void MeshRenderer::drawParts(const std::vector<MeshStyle>& styles) {
    glBindVertexArray(vao_);
    for (std::size_t p = 0; p < ranges_.size(); ++p) {
        const MeshStyle style = p < styles.size() ? styles[p] : MeshStyle{meshColour(p), true};
        if (!style.visible) continue;
        program_.set("base", style.colour);
        glDrawArrays(GL_TRIANGLES, ranges_[p].first, ranges_[p].second);
    }
}

void MeshRenderer::drawShaded(const FrameInfo& frame, const std::vector<MeshStyle>& styles, glm::vec4 cut) {
    if (empty()) return;
    program_.use();
    program_.set("viewProjection", frame.viewProjection);
    program_.set("eye", frame.eye);
    program_.set("lightDirection", frame.lightDirection);
    program_.set("cutPlane", cut);
    program_.set("wire", 0);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.0f, 1.0f); // behind the wireframe drawn over it
    drawParts(styles);
    glDisable(GL_POLYGON_OFFSET_FILL);
}

void MeshRenderer::drawDepth(const FrameInfo& frame, const std::vector<MeshStyle>& styles, glm::vec4 cut) {
    if (empty()) return;
    program_.use();
    program_.set("viewProjection", frame.viewProjection);
    program_.set("cutPlane", cut);
    program_.set("wire", 0);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.0f, 1.0f);
    drawParts(styles);
    glDisable(GL_POLYGON_OFFSET_FILL);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
}

void MeshRenderer::drawWire(const FrameInfo& frame, const std::vector<MeshStyle>& styles, glm::vec4 cut) {
    if (empty()) return;
    program_.use();
    program_.set("viewProjection", frame.viewProjection);
    program_.set("eye", frame.eye);
    program_.set("cutPlane", cut);
    program_.set("wire", 1);
    glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    drawParts(styles);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
}

} // namespace sdfgen::render
