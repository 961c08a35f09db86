#pragma once
// One renderer per view. Each draws into whatever framebuffer is bound, with the camera of the
// frame; none knows whether that is a window or an offscreen buffer (Scene composes them).
#include "sdfgen/field.hpp"
#include "sdfgen/mesh.hpp"
#include "render/gl.hpp"
#include "render/font.hpp"
#include "render/shader.hpp"

#include <glm/mat4x4.hpp>
#include <memory>
#include <vector>

namespace sdfgen::render {

// What every renderer needs to know about the frame being drawn.
struct FrameInfo {
    glm::mat4 view{1.0f};
    glm::mat4 projection{1.0f};
    glm::mat4 viewProjection{1.0f};
    glm::mat4 inverseViewProjection{1.0f};
    glm::vec3 eye{0.0f};         // the camera (orthographic: far behind it, for the mesh's facing test)
    glm::vec3 lightDirection{0.0f, 1.0f, 0.0f}; // towards the light, world space
    glm::ivec2 size{1, 1};
    float cameraDistance = 1.0f;
    float sceneRadius = 1.0f;
};

// The infinite grid on the plane y = planeY: a full-screen pass that intersects each pixel's ray
// with the plane, draws minor and major lines with the x axis red and the z axis blue, fades them
// with distance and writes the plane's depth, so that anything in front hides it.
class GridRenderer {
public:
    GridRenderer();
    void draw(const FrameInfo& frame, float planeY);

private:
    Program program_;
    GLuint vao_ = 0;
};

// How one mesh of a scene is drawn.
struct MeshStyle {
    glm::vec3 colour{0.85f, 0.62f, 0.42f};
    bool visible = true;
};
// The colour of the scene's mesh number `index` (the first one the single mesh's orange).
glm::vec3 meshColour(std::size_t index);

// The triangle meshes of a scene, flat shaded (Lambert, "Coloured Model") and/or as wireframe
// ("Polygon"), each in its own colour; every pass skips hidden meshes and discards what the cut
// plane (dot(xyz, p) > w) cuts away.
class MeshRenderer {
public:
    MeshRenderer();
    ~MeshRenderer();
    // The meshes, each placed by its transform (applied to its world coordinates).
    void setMeshes(const std::vector<MeshInstance>& parts);
    void clear();
    bool empty() const { return ranges_.empty(); }
    std::size_t partCount() const { return ranges_.size(); }
    float lowestY() const { return lowestY_; } // of every vertex drawn
    void drawShaded(const FrameInfo& frame, const std::vector<MeshStyle>& styles, glm::vec4 cut);
    // Only the depth of the faces, pushed back a little, so that the wireframe drawn over it shows
    // just the visible edges (hidden-line removal).
    void drawDepth(const FrameInfo& frame, const std::vector<MeshStyle>& styles, glm::vec4 cut);
    // Lines over whatever is in the depth buffer (the shaded and depth passes are offset behind them).
    void drawWire(const FrameInfo& frame, const std::vector<MeshStyle>& styles, glm::vec4 cut);

private:
    void drawParts(const std::vector<MeshStyle>& styles);

    Program program_;
    GLuint vao_ = 0, vbo_ = 0;
    std::vector<std::pair<GLint, GLsizei>> ranges_; // first vertex and vertex count of each mesh
    float lowestY_ = 0.0f;
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
    // Field::background: > 0 for a band field, whose values beyond the band only bound the distance.
    float background() const { return background_; }

private:
    GLuint texture_ = 0;
    glm::vec3 boxMin_{0.0f}, boxSize_{0.0f};
    float voxel_ = 1.0f;
    float background_ = 0.0f;
};

// The colour volume: rays marched through the box accumulate colour front to back through a
// transfer function (green shell at the surface, red inside, fading with distance outside),
// stopping at the opaque depth already drawn (sampled from `depthTexture`).
class VolumeRenderer {
public:
    VolumeRenderer();
    // `range`: the distances at which the colour map saturates inside (< 0) and outside (> 0);
    // `colormap` as in colormap.glsl.
    void draw(const FrameInfo& frame, const FieldTexture& field, GLuint depthTexture, float density, glm::vec2 range, int colormap);

private:
    Program program_;
    GLuint vao_ = 0;
};

// The ray march's rule, shared by shaders/raymarch.frag (as uniforms) and the probe, which marches
// the same rays on the CPU to pick the surface drawn: a hit where the field is under iso +
// kRaymarchHit voxels, steps of the sampled distance but at least kRaymarchMinStep voxels, and at
// most raymarchSteps of them.
constexpr float kRaymarchHit = 0.02f, kRaymarchMinStep = 0.05f;
int raymarchSteps(glm::vec3 boxSize, float background);

// Sphere tracing of the level set field = iso (0: the surface): jumps to the box when outside it,
// then steps by the sampled distance; normals from the gradient, Lambert + soft shadows + ambient
// occlusion from the field; writes the hit's depth (a voxel nearer, so it wins over the mesh).
class RaymarchRenderer {
public:
    RaymarchRenderer();
    // `cut`: the part where dot(xyz, p) > w is not marched ((0, 0, 0, 1): nothing is cut); where
    // the cut enters the solid, a flat cap when `capCut` (else nothing: a slice is drawn there).
    void draw(const FrameInfo& frame, const FieldTexture& field, bool shadows, float iso, glm::vec4 cut, bool capCut);

private:
    Program program_;
    GLuint vao_ = 0;
};

// The polygon where a plane cuts the box [boxMin, boxMin + boxSize] (3 to 6 corners in order;
// empty when it misses). The plane has unit `normal` and sits at `position` (0..1) between the
// box's lowest and highest corner along the normal.
std::vector<glm::vec3> slicePolygon(glm::vec3 boxMin, glm::vec3 boxSize, glm::vec3 normal, float position);
// That plane as (normal, level): the points p with dot(normal, p) = level.
glm::vec4 slicePlane(glm::vec3 boxMin, glm::vec3 boxSize, glm::vec3 normal, float position);
// The position (0..1, unclamped) of the plane with unit `normal` through `point`: slicePlane's inverse.
float slicePositionThrough(glm::vec3 boxMin, glm::vec3 boxSize, glm::vec3 normal, glm::vec3 point);

// A plane through the box at any orientation (see slicePolygon), coloured by signed distance with
// the colour map, iso-distance contours and an emphasised zero contour.
class SliceRenderer {
public:
    SliceRenderer();
    void draw(const FrameInfo& frame, const FieldTexture& field, glm::vec3 normal, float position, glm::vec2 range, int colormap);

private:
    Program program_;
    GLuint vao_ = 0;
};

// World-space line segments (pairs of points) in one colour, depth-tested or on top.
class LineRenderer {
public:
    LineRenderer();
    ~LineRenderer();
    void draw(const FrameInfo& frame, const std::vector<glm::vec3>& segments, glm::vec4 colour);

private:
    Program program_;
    GLuint vao_ = 0, vbo_ = 0;
};

// A colour bar: the colour map from range.x (bottom, inside) through 0 to range.y (top, outside),
// named after the view it belongs to (null: not named).
struct ColourBar {
    glm::vec2 range{0.0f};
    const char* name = nullptr;
};

// The colour bars at the right edge of the frame, the first rightmost, each with its values (and
// name) beside it, under a heading with the units, in the interface font (render/font.hpp).
class ColourBarRenderer {
public:
    ColourBarRenderer();
    ~ColourBarRenderer();
    void draw(glm::ivec2 size, const std::vector<ColourBar>& bars, int colormap, const char* units);

private:
    Program program_;
    GLuint vao_ = 0, vbo_ = 0;
    GlyphAtlas atlas_;
};

} // namespace sdfgen::render
