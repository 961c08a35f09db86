#pragma once
// The nearest-point terms behind sdfgen.torch's values and gradients. The nearest triangle comes
// from the model's tree; its closest point is then measured again in double from the caller's own
// vertex coordinates, so that the values (and finite differences of them) carry no rounding of the
// mesh's float copy.
#include "sdfgen/model.hpp"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

namespace sdfgen::python {

// Per point, each output optional (nullptr = not wanted).
struct NearestTerms {
    double* distance = nullptr;       // signed by the sign method when one is given, else unsigned
    double* gradient = nullptr;       // (3) the distance's gradient at the point: sign * (p - c) / |p - c|; on the surface
                                      // the face normal, oriented as Model::query's gradient (the face normal unsigned)
    double* closest = nullptr;        // (3) the closest surface point c, world coordinates
    std::int64_t* corners = nullptr;  // (3) vertex indices of the nearest triangle, those spanning c's feature first
    double* weights = nullptr;        // (3) barycentric weights of c on those corners
    std::int8_t* featureSize = nullptr; // corners spanning c's feature: 3 face, 2 edge, 1 vertex
    std::int64_t* triangle = nullptr; // the nearest triangle, an index into the mesh's triangles
    double* barycentric = nullptr;    // (3) c's weights on that triangle's corners, in its own order
};

// `points` are count world positions (xyz). `vertices` (world xyz, one per mesh vertex, nullptr for
// the mesh's own) are the coordinates the closest points are measured from: the vertices the
// model's mesh was built from, at full precision. Without them the mesh's own positions are used,
// in its local frame, so distances round to float exactly as Model::query's do. `sign` as for
// Model::query; none gives unsigned distances. Throws Error as Model::query does.
void measureNearest(const Model& model, const double* points, std::size_t count, const double* vertices,
                    std::optional<SignMethod> sign, const NearestTerms& out, const RunControl& control);

// The gradient of sum_i upstream[i] * distance_i with respect to the vertices, into the zeroed
// (vertexCount, 3) `vertexGradient`: each point's -w * gradient on the corners of its nearest
// triangle (`corners`, `weights` and `gradient` as NearestTerms gives them), summed per vertex in
// point order and corner order, as torch's scatter_add_ sums them (so bit for bit its result).
// Throws Error for a corner index out of range.
void scatterVertexGradient(const std::int64_t* corners, const double* weights, const double* gradient, const double* upstream,
                           std::size_t count, double* vertexGradient, std::size_t vertexCount);

// Runs work(i, part) for every i in [0, count) in one pass over control's thread pool: the items
// not alone(i) side by side, each on one thread (part.threads 1), then the others one after
// another on all of control's threads. Each part reports no progress; warnings are collected per
// item and reach control.warn in item order, from the calling thread.
void runSideBySide(std::size_t count, const std::function<bool(std::size_t)>& alone,
                   const std::function<void(std::size_t, const RunControl&)>& work, const RunControl& control);

// One mesh's share of a batch: its model, points, coordinates and outputs, as measureNearest takes them.
struct NearestJob {
    const Model* model = nullptr;
    const double* points = nullptr;
    std::size_t count = 0;
    const double* vertices = nullptr;
    NearestTerms out;
};

// measureNearest for every job, in one pass over the thread pool: the jobs of few points (where a
// call of their own costs more in waking the pool than in work) run side by side on one thread
// each; a job of many points runs alone on all of control's threads, its points searched in one
// Morton order. Each job's results are those of its own measureNearest, bit for bit, as a query's
// never depend on the thread count. Warnings reach control.warn in job order.
void measureNearestBatch(const std::vector<NearestJob>& jobs, std::optional<SignMethod> sign, const RunControl& control);

} // namespace sdfgen::python
