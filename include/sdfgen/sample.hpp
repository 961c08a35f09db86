#pragma once
// DeepSDF-style training samples: points, most of them near the surface, with their signed distances.
#include "sdfgen/bake.hpp"
#include "sdfgen/model.hpp"
#include "sdfgen/run_control.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace sdfgen {

// How samples are drawn. The defaults are DeepSDF's (Park et al. 2019, section 5 and its
// PreprocessMesh.cpp): 47/50 of the points near the surface, half of those with each noise scale,
// the rest uniform in a box. Noise is added to area-weighted random surface points, independently
// on each axis, with variance `nearVariance` or `farVariance` in DeepSDF's normalized units: the
// mesh centred on its bounding box's centre and scaled so its farthest vertex lies at 1/1.03
// (DeepSDF's 3% buffer). In world units the standard deviations are sqrt(variance) * radius, where
// radius = 1.03 * the farthest vertex's distance from the box centre.
struct SampleSettings {
    std::uint64_t seed = 0;
    double surfaceFraction = 47.0 / 50.0; // share of samples near the surface (rounded to a count)
    // The two scales: "near" is the first (the wider, DeepSDF's `variance`), "far" the second (the
    // narrower, its `second_variance`); the command line and Python call them wide and narrow.
    double nearVariance = 0.0025;         // DeepSDF paper: 0.0025 (std 0.05 of the radius)
    double farVariance = 0.00025;         // and 0.00025 (std 0.0158)
    // The uniform samples fill the mesh's bounding box padded on every side by padding x its longest
    // side, the box bake's grid covers (DeepSDF uses the cube [-1, 1]^3 of its normalized units).
    double padding = 0.1;
    SignMethod sign = SignMethod::Auto; // for the distances, as Model::query
    Channels channels;                  // per-sample outputs besides the distance (sdfgen/channels.hpp)
};

// DeepSDF's normalization of a mesh: normalized = (world - centre) / radius, with `centre` the
// centre of the bounding box of the vertices that triangles use and `radius` 1.03 x the farthest
// such vertex's distance from it, so that the mesh lies in the unit sphere with a 3% buffer. The
// unit of SampleSettings' variances.
struct NormalizedFrame {
    glm::dvec3 centre{0.0};
    double radius = 1.0;
};
NormalizedFrame normalizedFrame(const Mesh& mesh);

// n points (x y z interleaved, world coordinates, float32) and their signed distances.
// Order: the near-surface points of the first scale, then of the second, then the uniform ones.
struct Samples {
    std::vector<float> points; // 3 * n
    std::vector<float> sdf;    // n; sdf[i] == Model::query's signed distance at points[i] (as double)
    // The channels settings.channels asks for, in the registry's order, from the same query as the
    // distances (as a bake computes them at its samples); none otherwise. Interleaved: width values
    // per sample (a vector's x y z).
    std::vector<ChannelValues> channels;
    const ChannelValues* channel(const std::string& name) const { return findChannel(channels, name); }
    std::size_t size() const { return sdf.size(); }
};

// Exactly n samples of `model`, identical for the same seed, settings and mesh whatever the
// thread count: sample i draws from its own counter-based random stream (seed, i). Throws Error for
// bad settings, for n samples that do not fit in the available memory (checked before anything is
// allocated: about 52 bytes each at the peak) or in one call (2^32 - 1), and for samples beyond
// float range; Cancelled when control.cancel is raised.
Samples sampleSdf(const Model& model, std::size_t n, const SampleSettings& settings, const RunControl& control = {});

// The share of each kind for n samples: near (first scale), far (second scale), uniform.
struct SampleCounts {
    std::size_t nearSurface = 0, farSurface = 0, uniform = 0;
};
SampleCounts sampleCounts(std::size_t n, const SampleSettings& settings);

// Writes `points` as (n, 3) float32 and `sdf` as (n,) float32 into an .npz, atomically, and each
// channel present under its name: (n, width) of its type, (n,) for width 1. Throws Error naming
// `path`, also when `path` does not end in .npz (checkSamplesPath).
void saveSamples(const Samples& samples, const std::string& path);
// Throws saveSamples' Error for a path whose extension is not .npz (any case), before any work.
void checkSamplesPath(const std::string& path);

} // namespace sdfgen
