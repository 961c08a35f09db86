#include "render/renderers.hpp"

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

void MeshRenderer::setMesh(const Mesh& mesh) {
    // Flat shading: three vertices per triangle, each with the face normal.
    std::vector<float> data;
    data.reserve(mesh.triangleCount() * 18);
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const glm::vec3 n = mesh.faceNormals[t];
        for (int c = 0; c < 3; ++c) {
            // Drawn in world coordinates, like the field's box.
            const glm::vec3 p(mesh.toWorld(glm::dvec3(mesh.vertex(t, c))));
            data.insert(data.end(), {p.x, p.y, p.z, n.x, n.y, n.z});
        }
    }
    glNamedBufferData(vbo_, GLsizeiptr(data.size() * sizeof(float)), data.data(), GL_STATIC_DRAW);
    vertexCount_ = GLsizei(mesh.triangleCount() * 3);
}

void MeshRenderer::clear() {
    glNamedBufferData(vbo_, 0, nullptr, GL_STATIC_DRAW);
    vertexCount_ = 0;
}

void MeshRenderer::drawShaded(const FrameInfo& frame) {
    if (empty()) return;
    program_.use();
    program_.set("viewProjection", frame.viewProjection);
    program_.set("eye", frame.eye);
    program_.set("lightDirection", frame.lightDirection);
    program_.set("wire", 0);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.0f, 1.0f); // behind the wireframe drawn over it
    glBindVertexArray(vao_);
    glDrawArrays(GL_TRIANGLES, 0, vertexCount_);
    glDisable(GL_POLYGON_OFFSET_FILL);
}

void MeshRenderer::drawDepth(const FrameInfo& frame) {
    if (empty()) return;
    program_.use();
    program_.set("viewProjection", frame.viewProjection);
    program_.set("wire", 0);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.0f, 1.0f);
    glBindVertexArray(vao_);
    glDrawArrays(GL_TRIANGLES, 0, vertexCount_);
    glDisable(GL_POLYGON_OFFSET_FILL);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
}

void MeshRenderer::drawWire(const FrameInfo& frame) {
    if (empty()) return;
    program_.use();
    program_.set("viewProjection", frame.viewProjection);
    program_.set("eye", frame.eye);
    program_.set("wire", 1);
    glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    glBindVertexArray(vao_);
    glDrawArrays(GL_TRIANGLES, 0, vertexCount_);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
}

} // namespace sdfgen::render
