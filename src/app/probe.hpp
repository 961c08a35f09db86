#pragma once
#include "sdfgen/field.hpp"
#include "sdfgen/mesh.hpp"
#include "sdfgen/sparse_field.hpp"

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <optional>

namespace sdfgen {
class Model;
}

namespace sdfgen::app {

// What the probe reports at a point: the field's value and gradient there (trilinear, as the
// views draw it), and the exact distance to the mesh with the nearest surface point.
struct ProbeResult {
    glm::dvec3 point{0.0};
    bool insideField = false;  // the point is within the field's box
    float fieldValue = 0.0f;   // trilinear, clamped to the box as the GL texture is
    glm::vec3 gradient{0.0f};  // of the trilinear field
    bool haveMesh = false;
    double meshDistance = 0.0; // unsigned, to the nearest triangle (world units)
    glm::dvec3 nearest{0.0};   // the nearest surface point
    std::size_t triangle = 0;
};

// The field at p by trilinear interpolation between sample centres (clamped at the box's edge),
// and its gradient.
float trilinear(const Field& field, const glm::dvec3& p, glm::vec3* gradient = nullptr);

// One ray of the ray-marched view (render::Scene::pixelRay) and how the view marches it.
struct MarchedRay {
    glm::dvec3 origin{0.0}, direction{0.0, 0.0, 1.0}; // direction: unit
    float iso = 0.0f;
    glm::vec4 cut{0.0f, 0.0f, 0.0f, 1.0f}; // render::Scene::cutPlane()
    bool capCut = false;                   // a cap where the cut enters the solid (the slice is hidden)
    int maxSteps = 512;                    // render::raymarchSteps
};

// The distance along the ray to the surface the ray-marched view draws there, or none where it
// draws nothing: the march of shaders/raymarch.frag (its box, cut, hit threshold and step rule) on
// `field`, the field its texture holds, then refined by bisection to where the probe's value (the
// band's own with `band`, else trilinear) equals the iso level. The march stops short of the level
// by up to the hit threshold, and the view's depth is drawn a voxel nearer still, so neither is
// the point to read. A cap where the cut enters the solid is returned as drawn.
std::optional<double> marchSurface(const MarchedRay& ray, const Field& field, const SparseField* band = nullptr);

// Probes `field` and `model` (either may be null) at p (world coordinates). With `band` (the band
// field `field` shows, resampled), the value is the band's own (SparseField::sample), not the resampling's.
ProbeResult probe(const glm::dvec3& p, const Field* field, const Model* model, const SparseField* band = nullptr);

} // namespace sdfgen::app
