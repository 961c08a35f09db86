#pragma once
// A narrow-band field (SparseField) as the views show it: a dense field that fits the GPU.
#include "sdfgen/field.hpp"
#include "sdfgen/run_control.hpp"
#include "sdfgen/sparse_field.hpp"

#include <cstddef>
#include <string>

namespace sdfgen::render {

// The most samples a field shown from a band field gets (512³ floats: 512 MiB on the GPU).
constexpr std::size_t kBandDisplaySamples = std::size_t(512) * 512 * 512;

struct BandDisplay {
    Field field; // the band's dense form, or a coarser grid over the same box; background kept
    int factor = 1; // the shown voxel in the band's voxels (1: every sample as it is)
    // For the panel and the CLI, e.g. "band field 2048x2031x1688 (band 3 voxels): shown resampled to 512x508x422".
    std::string line;
};

// The band's full grid when its dense form fits the memory available, the 3D texture limit
// `textureLimit` and kBandDisplaySamples; otherwise the grid `factor` times coarser (the smallest
// whole factor that fits), each sample the value SparseField::sample gives at its centre (clamped
// to the background), in parallel on control.threads (progress and cancel through control).
BandDisplay bandDisplay(const SparseField& band, int textureLimit, const RunControl& control = {});

// GL_MAX_3D_TEXTURE_SIZE of the current context.
int textureLimit3D();

} // namespace sdfgen::render
