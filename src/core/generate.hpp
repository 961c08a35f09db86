#pragma once
#include "core/field.hpp"
#include "core/kdtree.hpp"
#include "core/mesh.hpp"

#include <atomic>
#include <functional>

namespace sdfgen {

// How long-running work is run and watched: thread count, progress reports and cancellation.
struct RunControl {
    int threads = 0; // 0 = all hardware threads
    // Called with the fraction done (0..1), from worker threads but never concurrently.
    std::function<void(double)> progress;
    // When set and raised, the work stops soon and throws Cancelled.
    const std::atomic<bool>* cancel = nullptr;
};

// What to bake: the grid (see makeGrid) and the sampling method's parameters.
struct BakeSettings {
    int res = 64;
    float padding = 0.1f;
    int rays = 64;
};

// The ray-sampling generator. For each sample, `rays` rays leave in the directions of
// sphereDirections(rays); the distance is the nearest hit of any ray (an upper bound of the true
// distance), and the sample is inside (negative) when more than half of the rays that hit anything
// first hit a back face. A sample whose rays all miss lies outside, and gets the distance to the
// farthest corner of the mesh's bounding box: finite, positive and still an upper bound.
// The result does not depend on the thread count.
Field generateRayField(const Mesh& mesh, const KdTree& tree, const Grid& grid, int rays, const RunControl& control);

// Grid + generator + the field's recorded method line, in one call. Throws Error for bad settings.
Field bake(const Mesh& mesh, const KdTree& tree, const BakeSettings& settings, const RunControl& control);

} // namespace sdfgen
