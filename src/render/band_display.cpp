#include "render/band_display.hpp"
#include "core/runtime/memory.hpp"
#include "core/runtime/parallel.hpp"
#include "render/gl.hpp"

#include <glm/common.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>

namespace sdfgen::render {

namespace {
std::string dimsText(glm::ivec3 d) { return std::to_string(d.x) + "x" + std::to_string(d.y) + "x" + std::to_string(d.z); }

bool fits(glm::ivec3 dims, int textureLimit, double memory) {
    const double samples = double(dims.x) * double(dims.y) * double(dims.z);
    return dims.x <= textureLimit && dims.y <= textureLimit && dims.z <= textureLimit && samples <= double(kBandDisplaySamples) &&
           (memory <= 0.0 || samples * sizeof(float) <= memory);
}
} // namespace

BandDisplay bandDisplay(const SparseField& band, int textureLimit, const RunControl& control) {
    BandDisplay shown;
    const double memory = double(availableMemoryBytes());
    const glm::ivec3 dims = band.grid.dims;
    glm::ivec3 coarse = dims;
    while (!fits(coarse, textureLimit, memory)) {
        ++shown.factor;
        coarse = (dims + (shown.factor - 1)) / shown.factor;
    }
    char voxels[32];
    std::snprintf(voxels, sizeof(voxels), "%g", band.background / band.grid.voxel);
    shown.line = "band field " + dimsText(dims) + " (band " + voxels + " voxels): ";
    if (shown.factor == 1) {
        shown.field = band.toDense();
        shown.line += "shown at full resolution";
        return shown;
    }
    Field& field = shown.field;
    field.source = band.source;
    field.method = band.method;
    field.parameters = band.parameters;
    field.background = band.background;
    field.grid.origin = band.grid.origin;
    field.grid.voxel = band.grid.voxel * shown.factor;
    field.grid.dims = coarse;
    field.values.resize(field.grid.sampleCount());
    // One item per row of samples: each row is written by one item alone, whatever the threads.
    parallelFor(std::size_t(coarse.y) * std::size_t(coarse.z), control, [&](std::size_t row) {
        const int j = int(row % std::size_t(coarse.y)), k = int(row / std::size_t(coarse.y));
        float* out = &field.values[field.grid.index(0, j, k)];
        for (int i = 0; i < coarse.x; ++i) {
            // Trilinear weights summing to 1 within rounding: kept within the background.
            out[i] = std::clamp(band.sample(field.grid.position(i, j, k)), -band.background, band.background);
        }
    });
    shown.line += "shown resampled to " + dimsText(coarse);
    return shown;
}

int textureLimit3D() {
    GLint limit = 0;
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &limit);
    return int(limit);
}

} // namespace sdfgen::render
