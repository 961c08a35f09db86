#include "app/probe.hpp"
#include "render/renderers.hpp"
#include "sdfgen/model.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace sdfgen::app {

float trilinear(const Field& field, const glm::dvec3& p, glm::vec3* gradient) {
    const Grid& g = field.grid;
    // Sample (i, j, k) sits at origin + (i + 1/2) * voxel.
    const glm::dvec3 u = (p - glm::dvec3(g.origin)) / double(g.voxel) - 0.5;
    int i0[3], i1[3];
    double f[3];
    for (int a = 0; a < 3; ++a) {
        const double c = std::clamp(u[a], 0.0, double(g.dims[a] - 1));
        i0[a] = std::min(int(std::floor(c)), g.dims[a] - 1);
        i1[a] = std::min(i0[a] + 1, g.dims[a] - 1);
        f[a] = c - double(i0[a]);
    }
    double v[2][2][2];
    for (int dz = 0; dz < 2; ++dz)
        for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx)
                v[dz][dy][dx] = double(field.at(dx ? i1[0] : i0[0], dy ? i1[1] : i0[1], dz ? i1[2] : i0[2]));
    auto lerp = [](double a, double b, double t) { return a + (b - a) * t; };
    const double x00 = lerp(v[0][0][0], v[0][0][1], f[0]), x10 = lerp(v[0][1][0], v[0][1][1], f[0]);
    const double x01 = lerp(v[1][0][0], v[1][0][1], f[0]), x11 = lerp(v[1][1][0], v[1][1][1], f[0]);
    const double y0 = lerp(x00, x10, f[1]), y1 = lerp(x01, x11, f[1]);
    if (gradient) {
        // Derivatives of the trilinear interpolant (per unit length); zero across a clamped axis.
        const double dx = lerp(lerp(v[0][0][1] - v[0][0][0], v[0][1][1] - v[0][1][0], f[1]),
                               lerp(v[1][0][1] - v[1][0][0], v[1][1][1] - v[1][1][0], f[1]), f[2]);
        const double dy = lerp(x10 - x00, x11 - x01, f[2]);
        const double dz = y1 - y0;
        *gradient = glm::vec3(glm::dvec3(dx, dy, dz) / double(g.voxel));
    }
    return float(lerp(y0, y1, f[2]));
}

std::optional<double> marchSurface(const MarchedRay& ray, const Field& field, const SparseField* band) {
    const Grid& g = field.grid;
    const double voxel = g.voxel;
    const glm::dvec3 &o = ray.origin, &dir = ray.direction;
    // The ray's span in the box, then on the kept side of the cut.
    const glm::dvec3 boxMin(g.origin), boxMax = boxMin + glm::dvec3(g.dims) * voxel;
    double enter = -INFINITY, leave = INFINITY;
    for (int a = 0; a < 3; ++a) {
        if (dir[a] == 0.0) {
            if (o[a] < boxMin[a] || o[a] > boxMax[a]) return std::nullopt;
            continue;
        }
        const double t0 = (boxMin[a] - o[a]) / dir[a], t1 = (boxMax[a] - o[a]) / dir[a];
        enter = std::max(enter, std::min(t0, t1));
        leave = std::min(leave, std::max(t0, t1));
    }
    if (enter >= leave || leave <= 0.0) return std::nullopt;
    const glm::dvec3 normal(ray.cut);
    const double towards = glm::dot(normal, dir), side = double(ray.cut.w) - glm::dot(normal, o);
    bool enteredAtCut = false;
    if (towards > 0.0) {
        leave = std::min(leave, side / towards);
    } else if (towards < 0.0 && side / towards > enter) {
        enter = side / towards;
        enteredAtCut = true;
    } else if (towards == 0.0 && side < 0.0) {
        return std::nullopt;
    }
    if (enter >= leave || leave <= 0.0) return std::nullopt;

    auto marched = [&](double t) { return double(trilinear(field, o + t * dir)) - double(ray.iso); };
    const double hit = double(render::kRaymarchHit) * voxel, minStep = double(render::kRaymarchMinStep) * voxel;
    double t = std::max(enter, 0.0), outside = t;
    int step = 0;
    for (; step < ray.maxSteps && t < leave; ++step) {
        const double d = marched(t);
        if (d < hit) break;
        outside = t;
        t += std::max(d, minStep);
    }
    if (step == ray.maxSteps || t >= leave) return std::nullopt;
    // Inside from the start: the solid where the cut enters it (a cap, or nothing where the slice
    // shows that section), or the box's face.
    if (step == 0) return enteredAtCut && !ray.capCut ? std::nullopt : std::optional<double>(t);

    // The level lies between the last step outside and the hit, or a little past the hit (it stops
    // short of the level); a band's own samples may put it a little off the resampling marched.
    auto level = [&](double s) {
        const glm::dvec3 p = o + s * dir;
        return (band ? double(band->sample(p)) : double(trilinear(field, p))) - double(ray.iso);
    };
    double inside = t;
    for (int n = 0; n < 40 && level(inside) > 0.0; ++n) inside += minStep;
    for (int n = 0; n < 40 && level(outside) <= 0.0; ++n) outside -= minStep;
    if (level(inside) > 0.0 || level(outside) <= 0.0) return t; // grazing: no crossing near the hit
    for (int n = 0; n < 64; ++n) {
        const double middle = 0.5 * (outside + inside);
        (level(middle) > 0.0 ? outside : inside) = middle;
    }
    return inside;
}

ProbeResult probe(const glm::dvec3& p, const Field* field, const Model* model, const SparseField* band) {
    ProbeResult result;
    result.point = p;
    if (field && !field->values.empty()) {
        const glm::dvec3 lo(field->grid.origin);
        const glm::dvec3 hi = lo + glm::dvec3(field->grid.dims) * double(field->grid.voxel);
        result.insideField = glm::all(glm::greaterThanEqual(p, lo)) && glm::all(glm::lessThanEqual(p, hi));
        result.fieldValue = trilinear(*field, p, &result.gradient);
        if (band) result.fieldValue = band->sample(p);
    }
    if (model) {
        // The library's point query: the same search and tie rule as a bake, in world coordinates.
        std::int64_t triangle = 0;
        PointQueryOutputs outputs;
        outputs.closestPoint = &result.nearest.x;
        outputs.triangle = &triangle;
        model->query(&p.x, 1, outputs);
        result.haveMesh = true;
        result.meshDistance = glm::length(p - result.nearest);
        result.triangle = std::size_t(triangle);
    }
    return result;
}

} // namespace sdfgen::app
