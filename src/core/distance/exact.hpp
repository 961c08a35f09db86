#pragma once
#include "sdfgen/field.hpp"
#include "sdfgen/grid.hpp"
#include "sdfgen/sparse_field.hpp"
#include "core/runtime/parallel.hpp"
#include "core/accel/bvh.hpp"
#include "core/accel/wide_bvh.hpp"
#include "core/method/channels.hpp"
#include "core/method/methods.hpp"

#include <cstdint>
#include <vector>

namespace sdfgen {

// The exact unsigned distance from every sample to the mesh, and the triangle that attains it.
struct NearestField {
    std::vector<float> distance;
    std::vector<std::uint32_t> triangle;
};

class MeshTopology;

// Samples are visited in bricks of 8x8x8: one tree search from the brick's centre bounds the
// distance of every sample in it (the field is 1-Lipschitz), and the leaf packets within that
// bound of the brick (far from the surface, within the lens around its centre's closest point)
// are collected once; each 4x4x4 quarter finds its centre's nearest triangle among them and
// narrows the list the same way from there, and each row of four samples
// scans only its quarter's list, together, each sample seeded by the packet that held its
// neighbour's answer. The answer is the nearest triangle by WideBvh's float distance, ties to the
// lower index (as WideBvh::nearest, so point queries agree bit for bit); its distance is
// re-measured in double (four samples of a row at once, bit for bit closestPointOnTriangle's).
// Independent of thread count.
NearestField computeNearest(const Mesh& mesh, const WideBvh& tree, const Grid& grid, const RunControl& control);
NearestField computeNearest(const Mesh& mesh, const Bvh& tree, const Grid& grid, const RunControl& control);

// The same search writing each sample's exact distance (world units) straight into
// values[grid.index(i, j, k)] (grid.sampleCount() floats): negated where the closest feature's
// angle-weighted pseudonormal points away from the sample when `pseudonormal` is given (the other
// way round when `flipped`), unsigned otherwise. No per-sample side arrays; `channels` (may be null)
// receives each sample's channels from the closest point its distance is measured with, at
// grid.index(i, j, k) of a planar writer, unsigned (signChannels signs them once the field is);
// the distances are the same with or without.
void computeExactField(const Mesh& mesh, const WideBvh& tree, const Grid& grid, const MeshTopology* pseudonormal, bool flipped,
                       float* values, const RunControl& control, const ChannelWriter* channels = nullptr);

// computeExactField for the samples of `count` bricks of 8³ (SparseField's): brick b's samples go to
// values[512 b + ((k - 8 z) * 8 + (j - 8 y)) * 8 + (i - 8 x)], (x, y, z) = bricks[b]; samples past
// the grid's end are not written. Each sample gets the value computeExactField gives it, bit for bit,
// except those farther than `skipBeyond` (local units) from the surface, which may be left
// unwritten (a band bake keeps only their side).
void computeExactBricks(const Mesh& mesh, const WideBvh& tree, const Grid& grid, const glm::ivec3* bricks, std::size_t count,
                        double skipBeyond, const MeshTopology* pseudonormal, bool flipped, float* values, const RunControl& control);

// The distance (world units) from p (local) to triangle t, measured in double, negated where the
// pseudonormal of its closest feature points away from p (the other way round when flipped), when
// `pseudonormal` is given: what computeExactField writes for a sample whose nearest triangle is t.
float sampleValue(const Mesh& mesh, const MeshTopology* pseudonormal, bool flipped, const glm::dvec3& p, std::uint32_t t);

// What computeExactField writes for the sample at local position p (nearestTriangle's answer,
// `hint` as there), signed by the pseudonormal: for samples a compute device leaves undecided.
float exactSignedSample(const Mesh& mesh, const WideBvh& tree, const MeshTopology& topology, bool flipped, const glm::dvec3& p,
                        std::uint32_t& hint);

// Every sample's nearest triangle by the same search, row by row (BakeContext::nearestRows).
void forEachNearestRow(const Mesh& mesh, const WideBvh& tree, const Grid& grid, const NearestRowStore& store, const RunControl& control);

// The nearest triangle to one point (local coordinates) by the same float distance and tie rule
// as the grid's samples; `hint` (in/out, WideBvh::kEmpty at first) is the packet that held the
// previous answer, a seed for the next nearby point.
std::uint32_t nearestTriangle(const WideBvh& tree, const glm::vec3& p, std::uint32_t& hint);

// The reference: for every sample, the distance to every triangle and the winding number summed
// over every triangle, all in double (inside where its magnitude exceeds 1/2, as the winding sign
// has it). O(samples x triangles).
Field computeBruteForce(const Mesh& mesh, const Grid& grid, const RunControl& control);

} // namespace sdfgen
