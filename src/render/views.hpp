#pragma once
// The registered views that the front ends address (the viewer's panel and probe, `sdfgen
// render`, the tests), by type through Scene::view<V>(), with their settings; each is defined in
// its view_NAME.cpp. A view that nothing outside its file addresses is declared there alone.
#include "render/view.hpp"

#include <glm/vec3.hpp>
#include <vector>

namespace sdfgen::render {

// "Coloured Model": the scene's meshes, flat-shaded, each in its colour.
class MeshView final : public View {
public:
    using View::View;
    void draw(const ViewContext& context, Pass pass) override;
    bool drawsMeshFaces() const override { return true; }
};

// "Polygon": the meshes' edges; alone, only the visible ones (hidden-line removal).
class WireView final : public View {
public:
    using View::View;
    bool seeThrough = false; // hidden edges too
    void draw(const ViewContext& context, Pass pass) override;
    void options(ViewOptions& ui, Scene& scene) override;
    std::string settingsKey() const override { return seeThrough ? "1" : "0"; }
};

// "Slice": the signed distance on the scene's cut plane (Scene::sliceNormal, slicePosition), with
// contours.
class SliceView final : public View {
public:
    using View::View;
    glm::vec2 range{0.0f}; // where its colours saturate inside (x < 0) and outside (y > 0); (0, 0): automatic
    void draw(const ViewContext& context, Pass pass) override;
    void options(ViewOptions& ui, Scene& scene) override;
    std::string settingsKey() const override;
    std::optional<glm::vec2> colourRange() const override { return range; }
    bool drawsSectionOnCut() const override { return true; }

private:
    SliceRenderer slice_;
};

// "Ray-marched": the field's level set at the iso level, sphere traced, with shadows and occlusion.
class RaymarchView final : public View {
public:
    using View::View;
    float iso = 0.0f;    // the level set drawn (0: the surface; > 0: offset outwards)
    bool shadows = true; // soft shadows and ambient occlusion from the field
    void draw(const ViewContext& context, Pass pass) override;
    void options(ViewOptions& ui, Scene& scene) override;
    std::string settingsKey() const override;

private:
    RaymarchRenderer raymarch_;
};

// "Bounding box": the field's box as lines.
class BoxView final : public View {
public:
    using View::View;
    void draw(const ViewContext& context, Pass pass) override;

private:
    LineRenderer lines_;
};

// "Grid": the infinite grid on the plane under the meshes (Scene::gridHeight).
class GridView final : public View {
public:
    using View::View;
    void draw(const ViewContext& context, Pass pass) override;

private:
    GridRenderer grid_;
};

// "SDF volume": the field ray-marched as a coloured volume, stopping at the opaque views' depth.
class VolumeView final : public View {
public:
    using View::View;
    float density = 1.0f;
    glm::vec2 range{0.0f}; // as SliceView::range
    void draw(const ViewContext& context, Pass pass) override;
    void options(ViewOptions& ui, Scene& scene) override;
    std::string settingsKey() const override;
    std::optional<glm::vec2> colourRange() const override { return range; }

private:
    VolumeRenderer volume_;
};

// "Sign errors": a cross at each sample where the field shown and the field it was compared with
// (the viewer's Compare, compareFields) lie on different sides of the surface.
class SignErrorsView final : public View {
public:
    using View::View;
    std::vector<glm::vec3> crosses; // segments, two points each
    void draw(const ViewContext& context, Pass pass) override;
    std::string settingsKey() const override { return std::to_string(crosses.size()); }

private:
    LineRenderer lines_;
};

} // namespace sdfgen::render
