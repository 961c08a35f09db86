#include "sdfgen/sample.hpp"
#include "core/runtime/memory.hpp"
#include "core/runtime/parallel.hpp"
#include "sdfgen/error.hpp"

#include <glm/geometric.hpp>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace sdfgen {

namespace {

// A counter-based random stream: value k of stream (seed, index) is a hash of the three, so every
// sample's numbers are fixed by its index alone, whatever thread computes it and in what order.
class Stream {
public:
    Stream(std::uint64_t seed, std::uint64_t index) : key_(mix(mix(seed ^ 0x5DEECE66DULL) + index)) {}

    // Uniform in [0, 1) with 53 random bits.
    double uniform() { return double(mix(key_ + 0x9E3779B97F4A7C15ULL * ++counter_) >> 11) * 0x1.0p-53; }
    // Two independent standard normals (Box-Muller).
    void normals(double& a, double& b) {
        const double radius = std::sqrt(-2.0 * std::log(1.0 - uniform())); // 1 - u in (0, 1]: no log(0)
        const double angle = 2.0 * M_PI * uniform();
        a = radius * std::cos(angle);
        b = radius * std::sin(angle);
    }

private:
    // SplitMix64's finaliser: a bijective mix in which every input bit affects every output bit.
    static std::uint64_t mix(std::uint64_t z) {
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
        return z ^ (z >> 31);
    }
    std::uint64_t key_;
    std::uint64_t counter_ = 0;
};

void checkSettings(const SampleSettings& s) {
    if (!(s.surfaceFraction >= 0.0 && s.surfaceFraction <= 1.0)) {
        throw Error("the surface fraction must be between 0 and 1 (got " + std::to_string(s.surfaceFraction) + ")");
    }
    if (!(s.nearVariance >= 0.0) || !std::isfinite(s.nearVariance) || !(s.farVariance >= 0.0) || !std::isfinite(s.farVariance)) {
        throw Error("noise variances must be finite numbers >= 0 (got " + std::to_string(s.nearVariance) + " and " +
                    std::to_string(s.farVariance) + ")");
    }
    if (!(s.padding >= 0.0) || !std::isfinite(s.padding)) {
        throw Error("padding must be a finite number >= 0 (got " + std::to_string(s.padding) + ")");
    }
}

} // namespace

SampleCounts sampleCounts(std::size_t n, const SampleSettings& settings) {
    SampleCounts counts;
    const std::size_t surface = std::min(n, std::size_t(std::llround(double(n) * settings.surfaceFraction)));
    counts.nearSurface = (surface + 1) / 2;
    counts.farSurface = surface / 2;
    counts.uniform = n - surface;
    return counts;
}

NormalizedFrame normalizedFrame(const Mesh& mesh) {
    const WorldBounds box = mesh.worldBounds();
    NormalizedFrame frame;
    frame.centre = (box.min + box.max) * 0.5;
    double farthest = 0.0;
    for (const glm::uvec3& tri : mesh.triangles) {
        for (int c = 0; c < 3; ++c) farthest = std::max(farthest, glm::length(mesh.toWorld(glm::dvec3(mesh.positions[tri[c]])) - frame.centre));
    }
    frame.radius = 1.03 * farthest; // DeepSDF's normalization: the unit sphere with a 3% buffer
    return frame;
}

Samples sampleSdf(const Model& model, std::size_t n, const SampleSettings& settings, const RunControl& control) {
    checkSettings(settings);
    const Mesh& mesh = model.mesh();
    // Checked before anything is allocated. Per sample at the peak: the float points and distances
    // kept (12 + 4 bytes), the double points queried (24) and the query's Morton keys and order (8 + 4).
    constexpr double kBytesPerSample = 12 + 4 + 24 + 8 + 4;
    const double needed = double(n) * kBytesPerSample;
    if (const std::uint64_t available = availableMemoryBytes(); available > 0 && needed > double(available)) {
        throw Error(mesh.source + ": " + std::to_string(n) + " samples need about " + std::to_string(std::llround(needed / (1 << 20))) +
                    " MiB but only " + std::to_string(available >> 20) + " MiB of memory is available");
    }
    if (n > std::numeric_limits<std::uint32_t>::max()) {
        throw Error(mesh.source + ": " + std::to_string(n) + " samples in one call; at most 4294967295");
    }
    const SampleCounts counts = sampleCounts(n, settings);

    // Triangles in world coordinates and their cumulative areas, for area-weighted picks.
    std::vector<double> cumulativeArea(mesh.triangleCount());
    double total = 0.0;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const glm::dvec3 a = mesh.toWorld(glm::dvec3(mesh.vertex(t, 0)));
        const glm::dvec3 b = mesh.toWorld(glm::dvec3(mesh.vertex(t, 1)));
        const glm::dvec3 c = mesh.toWorld(glm::dvec3(mesh.vertex(t, 2)));
        total += 0.5 * glm::length(glm::cross(b - a, c - a));
        cumulativeArea[t] = total;
    }
    const WorldBounds box = mesh.worldBounds();
    const double radius = normalizedFrame(mesh).radius;
    const double sigma[2] = {std::sqrt(settings.nearVariance) * radius, std::sqrt(settings.farVariance) * radius};
    const glm::dvec3 extent = box.extent();
    const double pad = settings.padding * std::max({extent.x, extent.y, extent.z});
    const glm::dvec3 uniformMin = box.min - glm::dvec3(pad), uniformSize = extent + glm::dvec3(2.0 * pad);

    Samples samples;
    samples.points.resize(3 * n);
    std::vector<double> points(3 * n);
    const std::size_t surfaceCount = counts.nearSurface + counts.farSurface;
    constexpr std::size_t chunk = 4096;
    parallelFor((n + chunk - 1) / chunk, control.phase(0.0, 0.2), [&](std::size_t block) {
        for (std::size_t i = block * chunk; i < std::min(n, (block + 1) * chunk); ++i) {
            Stream random(settings.seed, i);
            glm::dvec3 p;
            if (i < surfaceCount) {
                const double pick = random.uniform() * total;
                const std::size_t t = std::min<std::size_t>(
                    std::size_t(std::upper_bound(cumulativeArea.begin(), cumulativeArea.end(), pick) - cumulativeArea.begin()),
                    cumulativeArea.size() - 1);
                const glm::dvec3 a = mesh.toWorld(glm::dvec3(mesh.vertex(t, 0)));
                const glm::dvec3 b = mesh.toWorld(glm::dvec3(mesh.vertex(t, 1)));
                const glm::dvec3 c = mesh.toWorld(glm::dvec3(mesh.vertex(t, 2)));
                // Uniform on the triangle: the square root keeps the density even across it.
                const double r = std::sqrt(random.uniform()), s = random.uniform();
                p = a * (1.0 - r) + b * (r * (1.0 - s)) + c * (r * s);
                glm::dvec3 noise;
                double spare;
                random.normals(noise.x, noise.y);
                random.normals(noise.z, spare);
                p += noise * sigma[i < counts.nearSurface ? 0 : 1];
            } else {
                p = uniformMin + glm::dvec3(random.uniform(), random.uniform(), random.uniform()) * uniformSize;
            }
            for (int a = 0; a < 3; ++a) {
                samples.points[3 * i + a] = float(p[a]);
                points[3 * i + a] = double(samples.points[3 * i + a]); // the distance is of the stored float point
            }
        }
    });
    // Never a file of infinities: a mesh far beyond single precision has no float samples.
    const auto finite = [](float v) { return std::isfinite(v); };
    if (!std::all_of(samples.points.begin(), samples.points.end(), finite)) {
        throw Error(mesh.source + ": the samples' coordinates are beyond single precision at this mesh's scale and position; "
                                  "scale or move the mesh nearer to unit size at the origin");
    }
    samples.sdf.resize(n);
    PointQueryOutputs outputs;
    outputs.signedDistance = samples.sdf.data();
    outputs.channels = settings.channels;
    outputs.channelValues = &samples.channels;
    model.query(points.data(), n, outputs, settings.sign, control.phase(0.2, 1.0));
    if (!std::all_of(samples.sdf.begin(), samples.sdf.end(), finite)) {
        throw Error(mesh.source + ": the samples' distances are beyond single precision at this mesh's scale; scale the mesh "
                                  "nearer to unit size");
    }
    return samples;
}

} // namespace sdfgen
