#include "app/probe.hpp"
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
