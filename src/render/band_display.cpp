#include "render/band_display.hpp"
#include "sdfgen/memory.hpp"
#include "core/runtime/parallel.hpp"
#include "render/gl.hpp"

#include <glm/common.hpp>
#include <glm/vec2.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <tuple>
#include <vector>

namespace sdfgen::render {

namespace {
std::string dimsText(glm::ivec3 d) { return std::to_string(d.x) + "x" + std::to_string(d.y) + "x" + std::to_string(d.z); }

// Samples (0..dims.x, j, k) of `band`, as SparseField::at gives them: the background, the inside
// boxes of the row of bricks, then its stored bricks.
void readRow(const SparseField& band, int j, int k, float* out) {
    constexpr int kBrick = SparseField::kBrick;
    const int width = band.grid().dims.x, by = j / kBrick, bz = k / kBrick;
    std::fill(out, out + width, band.background());
    const std::array<int, 6> rowStart{0, by * kBrick, bz * kBrick, 0, 0, 0};
    auto box = std::lower_bound(band.insideBoxes().begin(), band.insideBoxes().end(), rowStart, [](const std::array<int, 6>& a, const std::array<int, 6>& b) {
        return std::tie(a[2], a[1], a[0]) < std::tie(b[2], b[1], b[0]);
    });
    for (; box != band.insideBoxes().end() && (*box)[2] == rowStart[2] && (*box)[1] == rowStart[1]; ++box) {
        std::fill(out + (*box)[0], out + (*box)[3], -band.background());
    }
    auto brick = std::lower_bound(band.bricks().begin(), band.bricks().end(), glm::ivec3(0, by, bz), [](const glm::ivec3& a, const glm::ivec3& b) {
        return std::tie(a.z, a.y, a.x) < std::tie(b.z, b.y, b.x);
    });
    for (; brick != band.bricks().end() && brick->z == bz && brick->y == by; ++brick) {
        const std::size_t b = std::size_t(brick - band.bricks().begin());
        const float* values = &band.values()[b * SparseField::kBrickSamples + std::size_t(((k % kBrick) * kBrick + j % kBrick) * kBrick)];
        const int x0 = brick->x * kBrick;
        std::copy(values, values + std::min(kBrick, width - x0), out + x0);
    }
}

bool fits(glm::ivec3 dims, int textureLimit, double memory) {
    const double samples = double(dims.x) * double(dims.y) * double(dims.z);
    return dims.x <= textureLimit && dims.y <= textureLimit && dims.z <= textureLimit && samples <= double(kBandDisplaySamples) &&
           (memory <= 0.0 || samples * sizeof(float) <= memory);
}
} // namespace

BandDisplay bandDisplay(const SparseField& band, int textureLimit, const RunControl& control) {
    BandDisplay shown;
    const double memory = double(availableMemoryBytes());
    const glm::ivec3 dims = band.grid().dims;
    glm::ivec3 coarse = dims;
    while (!fits(coarse, textureLimit, memory) && coarse != glm::ivec3(1)) {
        ++shown.factor;
        coarse = (dims + (shown.factor - 1)) / shown.factor;
    }
    char voxels[32];
    std::snprintf(voxels, sizeof(voxels), "%g", band.background() / band.grid().voxel);
    shown.line = "band field " + dimsText(dims) + " (band " + voxels + " voxels): ";
    if (shown.factor == 1) {
        shown.field = band.toDense();
        shown.line += "shown at full resolution";
        return shown;
    }
    Field& field = shown.field;
    static_cast<FieldHeader&>(field) = band.header(); // its names, background and grid, made coarser here
    field.grid.voxel = band.grid().voxel * shown.factor;
    field.grid.dims = coarse;
    field.values.resize(field.grid.sampleCount());
    // One item per row of samples: each row is written by one item alone, whatever the threads.
    parallelFor(std::size_t(coarse.y) * std::size_t(coarse.z), control, [&](std::size_t row) {
        const int j = int(row % std::size_t(coarse.y)), k = int(row / std::size_t(coarse.y));
        // SparseField::sample's arithmetic, with the four rows of the band's samples it reads
        // along this row taken out once instead of a lookup per corner.
        const glm::dvec3 g0 = glm::clamp((field.grid.position(0, j, k) - band.grid().origin) / band.grid().voxel - 0.5, glm::dvec3(0.0),
                                         glm::dvec3(dims - 1));
        const glm::ivec3 lo0 = glm::min(glm::ivec3(glm::floor(g0)), glm::max(dims - 2, 0));
        const glm::dvec2 t(g0.y - double(lo0.y), g0.z - double(lo0.z));
        std::vector<float> rows(4 * std::size_t(dims.x));
        for (int r = 0; r < 4; ++r) {
            readRow(band, std::min(lo0.y + (r & 1), dims.y - 1), std::min(lo0.z + (r >> 1), dims.z - 1), &rows[std::size_t(r) * std::size_t(dims.x)]);
        }
        float* out = &field.values[field.grid.index(0, j, k)];
        for (int i = 0; i < coarse.x; ++i) {
            const double gx = std::clamp((field.grid.position(i, j, k).x - band.grid().origin.x) / band.grid().voxel - 0.5, 0.0, double(dims.x - 1));
            const int lox = std::min(int(std::floor(gx)), std::max(dims.x - 2, 0));
            const double tx = gx - double(lox);
            double sum = 0.0;
            for (int c = 0; c < 8; ++c) {
                const int ox = c & 1, oy = c >> 1 & 1, oz = c >> 2 & 1;
                const double w = (ox ? tx : 1.0 - tx) * (oy ? t.x : 1.0 - t.x) * (oz ? t.y : 1.0 - t.y);
                if (w != 0.0) sum += w * double(rows[std::size_t(oz * 2 + oy) * std::size_t(dims.x) + std::size_t(std::min(lox + ox, dims.x - 1))]);
            }
            // Trilinear weights summing to 1 within rounding: kept within the background.
            out[i] = std::clamp(float(sum), -band.background(), band.background());
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
