#pragma once
#include "sdfgen/field.hpp"
#include "sdfgen/mesh.hpp"
#include "render/camera.hpp"
#include "render/renderers.hpp"

#include <glm/vec3.hpp>
#include <optional>
#include <string>
#include <vector>

namespace sdfgen::render {

// Which views are drawn; any combination.
struct Views {
    bool grid = true;
    bool mesh = true;      // "Coloured Model": flat-shaded Lambert
    bool wire = false;     // "Polygon": wireframe
    bool volume = false;   // "SDF volume": ray-marched colour volume
    bool raymarch = false; // "Ray-marched": sphere tracing with shadows and ambient occlusion
    bool slice = false;    // "Slice": signed distance on an axis-aligned plane

    // Parses a comma-separated list of grid, mesh, wire, volume, raymarch, slice (or "all",
    // "none"); throws Error naming the bad word.
    static Views parse(const std::string& list);
};

// Everything drawn in a frame: the mesh and field on the GPU, the renderers, and the settings
// shared by the window and the headless path. Needs a current GL 4.5 context for its lifetime.
class Scene {
public:
    Scene();
    ~Scene();
    Scene(const Scene&) = delete;
    Scene& operator=(const Scene&) = delete;

    void setMesh(const Mesh& mesh);
    void clearMesh();
    void setField(const Field& field); // throws Error when the driver cannot hold it
    void clearField();
    bool hasField() const { return !field_.empty(); }

    Views views;
    int sliceAxis = 2;         // 0 = x, 1 = y, 2 = z
    float slicePosition = 0.5f; // 0..1 across the field's box
    float volumeDensity = 1.0f;
    bool shadows = true;       // soft shadows and ambient occlusion in the ray-marched view
    glm::vec3 background{0.16f, 0.17f, 0.19f};

    // Draws a frame of `size` pixels with `camera` into framebuffer `target` (0: the context's
    // default framebuffer). Renders into its own colour + depth targets and copies the colour over.
    void draw(const OrbitCamera& camera, glm::ivec2 size, GLuint target = 0);

private:
    void resizeTargets(glm::ivec2 size);

    GridRenderer grid_;
    MeshRenderer mesh_;
    FieldTexture field_;
    VolumeRenderer volume_;
    RaymarchRenderer raymarch_;
    SliceRenderer slice_;
    GLuint fbo_ = 0, colourOnlyFbo_ = 0, colour_ = 0, depth_ = 0;
    glm::ivec2 targetSize_{0, 0};
};

} // namespace sdfgen::render
