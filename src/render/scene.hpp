#pragma once
#include "sdfgen/field.hpp"
#include "sdfgen/mesh.hpp"
#include "render/camera.hpp"
#include "render/image.hpp"
#include "render/renderers.hpp"
#include "render/view.hpp"

#include <glm/vec2.hpp>

#include <glm/vec3.hpp>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace sdfgen::render {

// The unit normal of the slice across axis 0 (x), 1 (y) or 2 (z).
glm::vec3 axisNormal(int axis);

// The least and greatest values of `field` (for a colour range from the values themselves):
// of the samples the slice (slicePolygon) passes through, or of the whole field; x <= 0 <= y.
glm::vec2 sliceValueRange(const Field& field, glm::vec3 normal, float position);
glm::vec2 fieldValueRange(const Field& field);

// The slice's gizmo, drawn over the scene while the slice is shown (Scene::sliceGizmoShown): an
// arrow along the normal from the plane's centre, grabbed to move the plane along it, and a ring
// on the plane about that centre, grabbed to turn the normal.
struct SliceGizmo {
    enum class Part { None, Arrow, Ring };
    glm::vec3 centre{0.0f}; // the point of the plane nearest the field box's centre
    glm::vec3 normal{0.0f, 0.0f, 1.0f};
    float size = 0.0f; // the arrow's length and the ring's radius
    // The part's line segments (pairs of points).
    std::vector<glm::vec3> segments(Part part) const;
};

// Everything drawn in a frame: the mesh and field on the GPU, the renderers, and the settings
// shared by the window and the headless path. Needs a current GL 4.5 context for its lifetime.
class Scene {
public:
    Scene();
    ~Scene();
    Scene(const Scene&) = delete;
    Scene& operator=(const Scene&) = delete;

    // The mesh, or the meshes of a scene each placed by its transform (the grid is drawn on the
    // plane under them). meshStyles gets one entry per mesh (meshColour(i), visible).
    void setMesh(const Mesh& mesh);
    void setMeshes(const std::vector<MeshInstance>& parts);
    void clearMesh();
    void setField(const Field& field); // throws Error when the driver cannot hold it
    void clearField();
    bool hasField() const { return !field_.empty(); }

    // The views (view.hpp's registry), in drawing order, each with its flag and settings.
    const std::vector<std::unique_ptr<View>>& views() const { return views_; }
    // The registered view of class V (render/views.hpp).
    template <class V>
    const V& view() const {
        for (const std::unique_ptr<View>& v : views_) {
            if (const V* found = dynamic_cast<const V*>(v.get())) return *found;
        }
        throw std::logic_error("a view type that is not registered");
    }
    template <class V>
    V& view() {
        return const_cast<V&>(std::as_const(*this).template view<V>());
    }
    // Shows the views flagged in `shown` (one flag per viewTypes() entry: parseViewList), hides the others.
    void showOnly(const std::vector<bool>& shown);

    // What the views share. The cut plane: the slice's plane, which cuts the meshes and the
    // ray-marched surface away on one side (sliceCut: 0 nothing, 1 the side its normal points to,
    // -1 the other side), whether the slice is shown or not.
    glm::vec3 sliceNormal{0.0f, 0.0f, 1.0f}; // unit; axisNormal(a) for the axis-aligned slices
    float slicePosition = 0.5f;               // 0..1 across the field's box along the normal
    int sliceCut = 0;
    bool headlight = true;      // the light follows the camera (else a fixed light from above)
    bool colourBar = true;      // drawn when a view coloured by distance is shown, one per range
    int colormap = 0;           // 0 diverging, 1 viridis, 2 grey (shaders/colormap.glsl)
    std::vector<MeshStyle> meshStyles; // one per mesh of setMeshes
    std::vector<glm::vec3> markers; // segments drawn on top (the probe's point and nearest point)
    bool sliceGizmoShown = false;   // the viewer's handle on the slice (not in `sdfgen render`'s images)
    SliceGizmo::Part sliceGizmoHighlight = SliceGizmo::Part::None; // drawn brighter: under the pointer or dragged
    glm::vec3 background{0.16f, 0.17f, 0.19f};

    // The range a view's colours use: `range`, or the symmetric automatic one where it is (0, 0)
    // (a quarter of the box's longest side; a band field's: its background).
    glm::vec2 effectiveRange(glm::vec2 range) const;
    // The colour bars drawn: one per range of the views shown that are coloured by distance
    // (View::colourRange), each named after its view where they differ.
    std::vector<ColourBar> colourBars() const;
    // The plane that cuts (as the shaders take it: dot(xyz, p) > w is cut), (0, 0, 0, 1) for none.
    glm::vec4 cutPlane() const;
    // A shown view draws the field's section on the cut plane (so the ray march caps nothing there).
    bool sectionOnCut() const;
    // The slice plane's gizmo for the field shown (size 0 without a field).
    SliceGizmo sliceGizmo() const;
    float gridHeight() const { return gridHeight_; } // the grid's plane: y = the meshes' lowest point (the field's box's without)
    glm::vec3 fieldBoxMin() const { return field_.boxMin(); }
    glm::vec3 fieldBoxSize() const { return field_.boxSize(); }

    // Draws a frame of `size` pixels with `camera` into framebuffer `target` (0: the context's
    // default framebuffer). Renders into its own colour + depth targets and copies the colour over.
    void draw(const OrbitCamera& camera, glm::ivec2 size, GLuint target = 0);
    // Copies the last frame drawn to `target` again (nothing in the scene changed).
    void present(GLuint target = 0);
    // The world point drawn at `pixel` (from the top left) in the last frame: the nearest opaque
    // surface there (mesh, ray-marched surface, slice or grid), or false where there is none.
    bool surfaceAt(glm::ivec2 pixel, glm::vec3& point);
    // The ray the full-screen passes (the ray march) cast through `pixel` in the last frame: from
    // the near plane through the pixel's centre, `direction` unit; false off the frame.
    bool pixelRay(glm::ivec2 pixel, glm::vec3& origin, glm::vec3& direction) const;
    const FrameInfo& lastFrame() const { return frame_; }
    // The last frame drawn, top row first.
    Image image() const;

private:
    void resizeTargets(glm::ivec2 size);

    MeshRenderer mesh_;
    FieldTexture field_;
    std::vector<std::unique_ptr<View>> views_; // one per viewTypes() entry
    LineRenderer lines_;
    ColourBarRenderer colourBar_;
    float gridHeight_ = 0.0f;
    FrameInfo frame_;
    GLuint fbo_ = 0, colourOnlyFbo_ = 0, colour_ = 0, depth_ = 0;
    glm::ivec2 targetSize_{0, 0};
};

} // namespace sdfgen::render
