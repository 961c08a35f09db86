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

// Valid by construction: the constructor checks the bricks, values and inside boxes against the
// grid and the background and refuses what does not describe a field on the grid, so that no
// reader, bake or writer checks them again (writers check only what a file holds of the grid and
// names). All that may change afterwards is its names (source, method, parameters): its grid,
// background and samples are read-only.
class SparseField : protected FieldHeader {
public:
    static constexpr int kBrick = 8;                              // samples per brick edge
    static constexpr int kBrickSamples = kBrick * kBrick * kBrick; // 512
    // Samples [lo, hi) entirely inside the solid: lo.x lo.y lo.z hi.x hi.y hi.z.
    using InsideBox = std::array<int, 6>;

    // What a band field stores, as the constructor takes it and release() gives it back:
    // - bricks: ordered by z, then y, then x; each is the sample box [8b, 8b + 8) (cut at the
    //   grid's end); a brick is stored where it holds a sample in the band or where the side
    //   changes inside it (near the open boundary of a mesh);
    // - values: kBrickSamples per brick, x fastest within it, each finite and within
    //   ±background; samples past the grid's end hold +background;
    // - insideBoxes: boxes of samples outside every stored brick that are entirely inside the
    //   solid (value -background); samples neither in a brick nor in one of these are outside
    //   (+background). Each box is a run of whole bricks along x in one row of bricks (lo a
    //   multiple of 8 on every axis; hi.y = lo.y + 8 and hi.z = lo.z + 8, cut at the grid's end),
    //   ordered by z, y, x, none overlapping another.
    struct Storage {
        std::vector<glm::ivec3> bricks;
        std::vector<float> values;
        std::vector<InsideBox> insideBoxes;
    };

    // The field of `header` (its grid, background and names) and `storage`, taken over as it is
    // (never copied). Throws Error "where: problem" when they do not describe a field on the grid
    // (`where` names what they came from: the file read, the mesh baked).
    SparseField(const FieldHeader& header, Storage storage, const std::string& where);

    using FieldHeader::method;
    using FieldHeader::parameter;
    using FieldHeader::parameters;
    using FieldHeader::source;
    const FieldHeader& header() const { return *this; }
    const Grid& grid() const { return FieldHeader::grid; }
    float background() const { return FieldHeader::background; } // band * voxel, > 0
    const Storage& storage() const { return storage_; }
    const std::vector<glm::ivec3>& bricks() const { return storage_.bricks; }
    const std::vector<float>& values() const { return storage_.values; }
    const std::vector<InsideBox>& insideBoxes() const { return storage_.insideBoxes; }
    // The storage taken out, for a writer given the field that hands its memory back as it goes;
    // the field is left with no bricks and no boxes (everywhere outside: still a field on its grid).
    Storage release();

    // The inside box of bricks x0 to x1 - 1 of the brick row (y, z) on a grid of `dims` samples.
    static InsideBox insideBox(const glm::ivec3& dims, int x0, int x1, int y, int z);

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

private:
    void check(const std::string& where) const;

    Storage storage_;
};

} // namespace sdfgen
