#pragma once
// A narrow-band field: exact signed distances where they lie within a band around the surface,
// stored in bricks of 8³ samples; everywhere else only the side is known (OpenVDB's level sets
// keep the same information, and the .vdb writer turns one into the other).
#include "sdfgen/field.hpp"
#include "sdfgen/grid.hpp"

#include <glm/vec3.hpp>
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace sdfgen {

// Its header (FieldHeader) as a dense field's; its background is the band (band * voxel).
struct SparseField : FieldHeader {
    static constexpr int kBrick = 8;                              // samples per brick edge
    static constexpr int kBrickSamples = kBrick * kBrick * kBrick; // 512

    // The stored bricks, ordered by z, then y, then x: each is the sample box [8b, 8b + 8) (cut at
    // the grid's end); a brick is stored where it holds a sample in the band or where the side
    // changes inside it (near the open boundary of a mesh).
    std::vector<glm::ivec3> bricks;
    // kBrickSamples values per brick, x fastest within it; samples past the grid's end hold +background.
    std::vector<float> values;
    // Boxes of samples [lo, hi) outside every stored brick that are entirely inside the solid
    // (value -background); samples neither in a brick nor in one of these are outside (+background).
    // Each box is a run of whole bricks along x in one row of bricks (lo a multiple of 8 on every
    // axis; hi.y = lo.y + 8 and hi.z = lo.z + 8, cut at the grid's end), ordered by z, y, x.
    std::vector<std::array<int, 6>> insideBoxes; // lo.x lo.y lo.z hi.x hi.y hi.z
    // The inside box of bricks x0 to x1 - 1 of the brick row (y, z) on a grid of `dims` samples.
    static std::array<int, 6> insideBox(const glm::ivec3& dims, int x0, int x1, int y, int z);

    // The value at sample (i, j, k) (0 <= i < dims.x, ...): looked up among the bricks, then the boxes.
    float at(int i, int j, int k) const;
    // Whether |at(i, j, k)| < background: an exact distance.
    bool inBand(int i, int j, int k) const;
    // Trilinear interpolation of the samples at a world position (clamped to the grid).
    float sample(const glm::dvec3& position) const;
    // The samples in the band.
    std::size_t activeCount() const;
    // The dense field (every sample, ±background outside the band) and its `band` parameter kept;
    // throws Error when it does not fit in the memory available.
    Field toDense() const;
    // Throws Error naming `path` when the bricks, values and boxes do not describe a field on the grid
    // (what every reader checks, and every writer before it writes).
    void check(const std::string& path) const;
};

} // namespace sdfgen
