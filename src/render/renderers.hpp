#pragma once
// One renderer per view. Each draws into whatever framebuffer is bound, with the camera of the
// frame; none knows whether that is a window or an offscreen buffer (Scene composes them).
#include "sdfgen/field.hpp"
#include "sdfgen/mesh.hpp"
#include "render/gl.hpp"
#include "render/shader.hpp"

#include <glm/mat4x4.hpp>
#include <memory>

namespace sdfgen::render {

// What every renderer needs to know about the frame being drawn.
struct FrameInfo {
    glm::mat4 view{1.0f};
    glm::mat4 projection{1.0f};
    glm::mat4 viewProjection{1.0f};
    glm::mat4 inverseViewProjection{1.0f};
    glm::vec3 eye{0.0f};
    glm::ivec2 size{1, 1};
    float cameraDistance = 1.0f;
    float sceneRadius = 1.0f;
};

// The infinite grid on the y = 0 plane: a full-screen pass that intersects each pixel's ray with
// the plane, draws minor and major lines with the x axis red and the z axis blue, fades them with
// distance and writes the plane's depth, so that anything in front hides it.
class GridRenderer {
public:
    GridRenderer();
    void draw(const FrameInfo& frame);

private:
    Program program_;
    GLuint vao_ = 0;
};

// The triangle mesh, flat shaded (Lambert, "Coloured Model") and/or as wireframe ("Polygon").
class MeshRenderer {
public:
    MeshRenderer();
    ~MeshRenderer();
    void setMesh(const Mesh& mesh);
    void clear();
    bool empty() const { return vertexCount_ == 0; }
    void drawShaded(const FrameInfo& frame);
    // Lines over whatever is in the depth buffer (the shaded pass is offset behind them).
    void drawWire(const FrameInfo& frame);

private:
    Program program_;
    GLuint vao_ = 0, vbo_ = 0;
    GLsizei vertexCount_ = 0;
};

// The field as a GL_R32F 3D texture (trilinear, clamped) and the box it covers: texel centres
// sit on the field's samples, so texture coordinate (p - boxMin) / boxSize reads the field at p.
class FieldTexture {
public:
    FieldTexture() = default;
    ~FieldTexture();
    FieldTexture(const FieldTexture&) = delete;
    FieldTexture& operator=(const FieldTexture&) = delete;
    // Throws Error when the grid is larger than the driver's 3D texture limit.
    void upload(const Field& field);
    void clear();
    bool empty() const { return texture_ == 0; }
    void bind(GLuint unit) const { glBindTextureUnit(unit, texture_); }
    // Sets boxMin, boxSize, voxel, dims and field (sampler on unit 0) on the program in use.
    void setUniforms(Program& program) const;
    glm::vec3 boxMin() const { return boxMin_; }
    glm::vec3 boxSize() const { return boxSize_; }
    float voxel() const { return voxel_; }

private:
    GLuint texture_ = 0;
    glm::vec3 boxMin_{0.0f}, boxSize_{0.0f};
    glm::ivec3 dims_{0};
    float voxel_ = 1.0f;
};

// The colour volume: rays marched through the box accumulate colour front to back through a
// transfer function (green shell at the surface, red inside, fading with distance outside),
// stopping at the opaque depth already drawn (sampled from `depthTexture`).
class VolumeRenderer {
public:
    VolumeRenderer();
    void draw(const FrameInfo& frame, const FieldTexture& field, GLuint depthTexture, float density);

private:
    Program program_;
    GLuint vao_ = 0;
};

// Sphere tracing of the field: jumps to the box when outside it, then steps by the sampled
// distance; normals from the gradient, Lambert + soft shadows + ambient occlusion from the field;
// writes the hit's depth.
class RaymarchRenderer {
public:
    RaymarchRenderer();
    void draw(const FrameInfo& frame, const FieldTexture& field, bool shadows);

private:
    Program program_;
    GLuint vao_ = 0;
};

// An axis-aligned plane through the box at `position` (0..1 along `axis`), coloured by signed
// distance with a diverging map, iso-distance contours and an emphasised zero contour.
class SliceRenderer {
public:
    SliceRenderer();
    void draw(const FrameInfo& frame, const FieldTexture& field, int axis, float position);

private:
    Program program_;
    GLuint vao_ = 0;
};

} // namespace sdfgen::render
