// Band fields (SparseField) in files: .npz and .vdb keep them sparse and give them back bit for bit;
// .vdb is an OpenVDB level set as OpenVDB itself reads it; the dense formats hold the dense form or
// refuse in one line; dense files read as band fields; hostile sparse files are refused before
// anything is allocated for what they claim; compare and surface take band fields as they are.
#include "sdfgen/surface.hpp"
#include "core/io/formats/format.hpp"
#include "core/io/formats/npy.hpp"
#include "core/accel/topology.hpp"
#include "sdfgen/compare.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/formats.hpp"

#include "support/checks.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>
#if SDFGEN_HAS_OPENVDB
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#endif

#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

namespace sdfgen {
namespace {

using test::errorFrom;

// A solid ball and a hollow one (a shell between radii 0.12 and 0.25) on a grid whose sides are
// not multiples of 8, so that bricks are cut at the grid's end, and whole bricks lie inside.
Field ballsField() {
    Field field;
    field.source = "balls.obj";
    field.method = "exact";
    field.parameters = {{"sign", "winding"}, {"band", "2.5"}};
    field.grid.dims = {75, 57, 45};
    field.grid.origin = {-0.1, -0.2, -0.3};
    field.grid.voxel = 0.02;
    field.values.resize(field.grid.sampleCount());
    for (int k = 0; k < field.grid.dims.z; ++k)
        for (int j = 0; j < field.grid.dims.y; ++j)
            for (int i = 0; i < field.grid.dims.x; ++i) {
                const glm::dvec3 p = field.grid.position(i, j, k);
                const double ball = glm::distance(p, glm::dvec3(0.4, 0.36, 0.18)) - 0.4;
                const double shell = std::fabs(glm::distance(p, glm::dvec3(1.05, 0.45, 0.2)) - 0.185) - 0.065;
                field.values[field.grid.index(i, j, k)] = float(std::min(ball, shell));
            }
    return field;
}

// `field` with its header and storage as `change(header, storage)` leaves them: a new field,
// refused as any is when they no longer describe one (Error naming `where`).
template <class Change>
SparseField changed(const SparseField& field, Change change, const std::string& where = "changed") {
    FieldHeader header = field.header();
    SparseField::Storage storage = field.storage();
    change(header, storage);
    return SparseField(header, std::move(storage), where);
}

void expectSameSparse(const SparseField& a, const SparseField& b) {
    EXPECT_EQ(a.grid().dims, b.grid().dims);
    EXPECT_EQ(a.grid().origin, b.grid().origin);
    EXPECT_EQ(a.grid().voxel, b.grid().voxel);
    EXPECT_EQ(a.background(), b.background());
    EXPECT_EQ(a.source, b.source);
    EXPECT_EQ(a.method, b.method);
    EXPECT_EQ(a.parameters, b.parameters);
    EXPECT_EQ(a.bricks(), b.bricks());
    EXPECT_EQ(a.insideBoxes(), b.insideBoxes());
    ASSERT_EQ(a.values().size(), b.values().size());
    EXPECT_EQ(std::memcmp(a.values().data(), b.values().data(), a.values().size() * sizeof(float)), 0) << "brick values differ";
}

class SparseFormats : public test::ScratchFolderTest {
protected:
    void SetUp() override {
        ScratchFolderTest::SetUp();
    }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    // The band field saved as band.vdb, read back as OpenVDB's grids (for crafting bad files).
    openvdb::GridPtrVecPtr savedBandGrids() const {
        saveSparseField(sparse_, path("band.vdb"));
        openvdb::initialize();
        openvdb::io::File in(path("band.vdb"));
        in.open();
        openvdb::GridPtrVecPtr grids = in.getGrids();
        in.close();
        return grids;
    }
    // The band field saved with `extension` reads back bit for bit (loadField: its dense form,
    // marked as a band field); a dense file of the format is not sparse and reads as the band
    // field through its samples.
    void expectRoundTrip(const std::string& extension) {
        const std::string file = path("band" + extension), denseFile = path("dense" + extension);
        saveSparseField(sparse_, file);
        const AnyField loaded = loadAnyField(file);
        ASSERT_TRUE(loaded.isBand());
        expectSameSparse(loaded.band(), sparse_);
        expectSameSparse(loadSparseField(file), sparse_);
        const Field dense = loadField(file);
        EXPECT_EQ(dense.background, sparse_.background());
        EXPECT_EQ(dense.values, sparse_.toDense().values);
        saveField(dense_, denseFile);
        EXPECT_EQ(loadAnyField(denseFile).dense().values, dense_.values);
        expectSameSparse(loadSparseField(denseFile), sparse_);
    }

    const Field dense_ = ballsField();
    SparseField sparse_ = formats::sparseFromDense(dense_, formats::bandBackground(dense_), "balls");
};

TEST_F(SparseFormats, FromDenseKeepsTheBandAndTheSides) {
    const float background = float(2.5 * dense_.grid.voxel);
    EXPECT_EQ(sparse_.background(), background);
    EXPECT_GT(sparse_.bricks().size(), 0u);
    EXPECT_LT(sparse_.bricks().size(), 10u * 8u * 6u / 2u) << "most bricks are away from the surface";
    EXPECT_GT(sparse_.insideBoxes().size(), 0u) << "whole bricks lie inside the balls";
    std::size_t inBand = 0;
    for (int k = 0; k < dense_.grid.dims.z; ++k)
        for (int j = 0; j < dense_.grid.dims.y; ++j)
            for (int i = 0; i < dense_.grid.dims.x; ++i) {
                const float v = dense_.values[dense_.grid.index(i, j, k)];
                const float expected = std::clamp(v, -background, background);
                ASSERT_EQ(sparse_.at(i, j, k), expected) << i << " " << j << " " << k;
                inBand += std::fabs(v) < background;
            }
    EXPECT_EQ(sparse_.activeCount(), inBand);
}

TEST_F(SparseFormats, NpzRoundTripIsExact) { expectRoundTrip(".npz"); }

TEST_F(SparseFormats, DenseFormatsHoldTheDenseFormAndReadBackAsTheBandField) {
    for (const char* name : {"band.sdf", "band.nrrd", "band.npy"}) {
        SCOPED_TRACE(name);
        saveSparseField(sparse_, path(name));
        EXPECT_FALSE(loadAnyField(path(name)).isBand());
        const Field dense = loadField(path(name));
        EXPECT_EQ(dense.values, sparse_.toDense().values);
        if (std::string(name) != "band.npy") {
            // The method line keeps band=2.5: the field knows it is a band field.
            EXPECT_EQ(dense.background, sparse_.background());
            expectSameSparse(loadSparseField(path(name)), sparse_);
        }
    }
    // A bare .npy names no band, and its voxels are 1: 3 voxels.
    EXPECT_EQ(loadSparseField(path("band.npy")).background(), 3.0f);
}

TEST_F(SparseFormats, DenseFormatsRefuseABandFieldThatDoesNotFitDense) {
    // 16384^3 samples: 16 TiB dense, a few kilobytes sparse.
    const SparseField huge = changed(sparse_, [](FieldHeader& header, SparseField::Storage& storage) {
        header.grid.dims = {16384, 16384, 16384};
        storage.insideBoxes.clear();
    });
    for (const char* name : {"huge.npy", "huge.sdf", "huge.nrrd"}) {
        const std::string message = errorFrom([&] { saveSparseField(huge, path(name)); });
        EXPECT_EQ(message.rfind(path(name), 0), 0u) << message;
        EXPECT_CONTAINS(message, ".vdb or .npz");
        EXPECT_EQ(message.find('\n'), std::string::npos);
        EXPECT_FALSE(std::filesystem::exists(path(name)));
    }
    saveSparseField(huge, path("huge.npz"));
    expectSameSparse(loadSparseField(path("huge.npz")), huge);
    const std::string message = errorFrom([&] { loadField(path("huge.npz")); });
    EXPECT_EQ(message.rfind(path("huge.npz"), 0), 0u) << message;
    EXPECT_CONTAINS(message, "keep it sparse");
}

// An .npz of the sparse layout with one member replaced.
class HostileSparseNpz : public SparseFormats {
protected:
    std::string writeWith(const std::string& name, const formats::NpzMember& replaced) {
        const SparseField& f = sparse_;
        std::vector<std::int32_t> origins;
        for (const glm::ivec3& b : f.bricks()) origins.insert(origins.end(), {8 * b.x, 8 * b.y, 8 * b.z});
        std::string background = formats::npyHeader("<f4", false, {});
        const float backgroundValue = f.background();
        background.append(reinterpret_cast<const char*>(&backgroundValue), 4);
        const std::uint64_t bricks = f.bricks().size();
        std::vector<formats::NpzMember> members = {
            {"brick_origins.npy", formats::npyHeader("<i4", false, {bricks, 3}), origins.data(), origins.size() * 4},
            {"brick_values.npy", formats::npyHeader("<f4", true, {8, 8, 8, bricks}), f.values().data(), f.values().size() * 4},
            {"inside_boxes.npy", formats::npyHeader("<i4", false, {f.insideBoxes().size(), 6}), f.insideBoxes().data(), f.insideBoxes().size() * 24},
            {"background.npy", background},
            {"origin.npy", formats::npyFloat64Array({-0.1, -0.2, -0.3}, false)},
            {"voxel_size.npy", formats::npyFloat64Array({0.02}, true)},
            {"dims.npy", formats::npyInt64Array({75, 57, 45})},
        };
        for (formats::NpzMember& m : members) {
            if (m.name == replaced.name) m = replaced;
        }
        const std::string file = path(name);
        formats::writeNpz(file, members);
        return file;
    }
    void expectRefused(const std::string& file, const std::string& problem) {
        const std::string message = errorFrom([&] { loadSparseField(file); });
        EXPECT_EQ(message.rfind(file, 0), 0u) << message;
        EXPECT_CONTAINS(message, problem);
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        EXPECT_EQ(errorFrom([&] { loadField(file); }), message);
    }
};

TEST_F(HostileSparseNpz, CountsAreCheckedAgainstTheBytes) {
    // A billion bricks claimed, a few held: refused before 2 TB are allocated.
    const std::uint64_t bricks = sparse_.bricks().size();
    expectRefused(writeWith("values.npz", {"brick_values.npy", formats::npyHeader("<f4", true, {8, 8, 8, 1u << 30}), sparse_.values().data(),
                                           sparse_.values().size() * 4}),
                  "shape is not (8, 8, 8, " + std::to_string(bricks) + ")");
    std::vector<std::int32_t> many(3 * 1000, 0);
    expectRefused(writeWith("origins.npz", {"brick_origins.npy", formats::npyHeader("<i4", false, {1u << 30, 3}), many.data(), many.size() * 4}),
                  "bytes of data");
    expectRefused(writeWith("boxes.npz", {"inside_boxes.npy", formats::npyHeader("<i4", false, {4, 5}), many.data(), 80}),
                  "shape is not (n, 6)");
    expectRefused(writeWith("type.npz", {"inside_boxes.npy", formats::npyHeader("<f4", false, {0, 6}), nullptr, 0}), "is not int32 or int64");
}

TEST_F(HostileSparseNpz, DimsWhoseProductPassesTwoToThe64AreRefused) {
    // Each axis below 2^31, their product exactly 2^64 (a size_t product wraps to 0).
    expectRefused(writeWith("wrap.npz", {"dims.npy", formats::npyInt64Array({4194304, 2097152, 2097152})}), "more than 2^58 samples");
    expectRefused(writeWith("past.npz", {"dims.npy", formats::npyInt64Array({2147483647, 2147483647, 2147483647})}), "more than 2^58 samples");
    // The one check every front end meets: the field itself, its dense form, a save.
    // No such band field can be made: there is nothing to save.
    const std::string message = errorFrom([&] {
        changed(
            sparse_,
            [](FieldHeader& header, SparseField::Storage& storage) {
                header.grid.dims = {4194304, 2097152, 2097152};
                storage.insideBoxes.clear();
            },
            "huge");
    });
    EXPECT_EQ(message.rfind("huge: ", 0), 0u) << message;
    EXPECT_CONTAINS(message, "more than 2^58 samples");
    Field dense;
    dense.grid.dims = {4194304, 2097152, 2097152};
    dense.grid.voxel = 1e-6;
    EXPECT_CONTAINS(errorFrom([&] { saveField(dense, path("dense.npy")); }), "more than 2^58 samples");
}

TEST_F(HostileSparseNpz, FieldsThatAreNotBandFieldsAreRefused) {
    std::vector<std::int32_t> origins;
    for (const glm::ivec3& b : sparse_.bricks()) origins.insert(origins.end(), {8 * b.x, 8 * b.y, 8 * b.z});
    const std::string originsHeader = formats::npyHeader("<i4", false, {sparse_.bricks().size(), 3});
    std::vector<std::int32_t> shifted = origins;
    shifted[0] += 1;
    expectRefused(writeWith("shifted.npz", {"brick_origins.npy", originsHeader, shifted.data(), shifted.size() * 4}), "multiple of 8");
    std::vector<std::int32_t> swapped = origins;
    std::swap_ranges(swapped.begin(), swapped.begin() + 3, swapped.end() - 3);
    expectRefused(writeWith("order.npz", {"brick_origins.npy", originsHeader, swapped.data(), swapped.size() * 4}), "not in z, y, x order");
    std::vector<std::int32_t> outside = origins;
    outside.back() = 1 << 20;
    expectRefused(writeWith("outside.npz", {"brick_origins.npy", originsHeader, outside.data(), outside.size() * 4}), "outside the grid");
    std::vector<float> values = sparse_.values();
    values[7] = 1.0f;
    expectRefused(writeWith("value.npz", {"brick_values.npy", formats::npyHeader("<f4", true, {8, 8, 8, sparse_.bricks().size()}), values.data(),
                                          values.size() * 4}),
                  "exceeds the background");
    std::vector<std::array<int, 6>> boxes = sparse_.insideBoxes();
    ASSERT_FALSE(boxes.empty());
    boxes[0][3] -= 1;
    expectRefused(writeWith("box.npz", {"inside_boxes.npy", formats::npyHeader("<i4", false, {boxes.size(), 6}), boxes.data(), boxes.size() * 24}),
                  "whole bricks");
    // Overlapping boxes: at() takes the last box of a row starting at or before a sample,
    // toDense() every box, so the two would disagree.
    boxes = sparse_.insideBoxes();
    const auto wide = std::find_if(boxes.begin(), boxes.end(), [](const std::array<int, 6>& b) { return b[3] - b[0] >= 16; });
    ASSERT_NE(wide, boxes.end()) << "a box of two bricks or more";
    std::array<int, 6> later = *wide;
    later[0] += 8; // from the box's second brick on
    const std::string overlapping = "inside boxes " + std::to_string(wide - boxes.begin()) + " and " + std::to_string(wide - boxes.begin() + 1) + " overlap";
    boxes.insert(wide + 1, later);
    expectRefused(writeWith("overlap.npz", {"inside_boxes.npy", formats::npyHeader("<i4", false, {boxes.size(), 6}), boxes.data(), boxes.size() * 24}),
                  overlapping);
    std::string negative = formats::npyHeader("<f4", false, {});
    const float minusOne = -1.0f;
    negative.append(reinterpret_cast<const char*>(&minusOne), 4);
    expectRefused(writeWith("background.npz", {"background.npy", negative}), "background is not a positive");
}

TEST_F(SparseFormats, CompareTakesABandFieldByValueInItsBandAndBySignOutside) {
    Field band = sparse_.toDense();
    FieldDifference d = compareFields(band, dense_, 0.0);
    EXPECT_EQ(d.compared, sparse_.activeCount());
    EXPECT_EQ(d.compared + d.signOnly, dense_.values.size());
    EXPECT_EQ(d.maxAbs, 0.0);
    EXPECT_EQ(d.signDifferences, 0u);
    // A wrong side far from the surface, and a wrong distance in the band.
    Field wrong = dense_;
    std::size_t far = 0, near = 0;
    for (std::size_t i = 0; i < wrong.values.size(); ++i) {
        if (std::fabs(wrong.values[i]) > 2 * band.background && far == 0) far = i;
        if (std::fabs(wrong.values[i]) < 0.5f * band.background && near == 0) near = i;
    }
    wrong.values[far] = -wrong.values[far];
    wrong.values[near] += 0.25f * float(dense_.grid.voxel);
    d = compareFields(wrong, band, 0.0);
    EXPECT_EQ(d.signDifferences, 1u);
    EXPECT_NEAR(d.maxAbs, 0.25 * dense_.grid.voxel, 1e-7);
}

void expectSameDifference(const FieldDifference& sparse, const FieldDifference& dense, const std::string& what) {
    EXPECT_EQ(sparse.compared, dense.compared) << what;
    EXPECT_EQ(sparse.signOnly, dense.signOnly) << what;
    EXPECT_EQ(sparse.signDifferences, dense.signDifferences) << what;
    EXPECT_EQ(sparse.maxAbs, dense.maxAbs) << what;
    EXPECT_NEAR(sparse.meanAbs, dense.meanAbs, 1e-12) << what;
    EXPECT_NEAR(sparse.rmsAbs, dense.rmsAbs, 1e-12) << what;
    EXPECT_EQ(sparse.voxel, dense.voxel) << what;
}

TEST_F(SparseFormats, BandFieldsCompareSparseAsTheirDenseFormsDo) {
    // Against itself, a narrower band, the balls moved by 3 voxels (bricks and inside boxes of
    // each where the other has none, sides that differ), each with and without --band.
    Field moved = dense_;
    for (int k = 0; k < moved.grid.dims.z; ++k)
        for (int j = 0; j < moved.grid.dims.y; ++j)
            for (int i = 0; i < moved.grid.dims.x; ++i) moved.values[moved.grid.index(i, j, k)] = dense_.at(std::max(i - 3, 0), j, k);
    const std::vector<std::pair<std::string, SparseField>> others = {
        {"itself", sparse_},
        {"narrower", formats::sparseFromDense(dense_, 0.6f * sparse_.background(), "narrower")},
        {"moved", formats::sparseFromDense(moved, sparse_.background(), "moved")}};
    for (const auto& [name, other] : others) {
        ASSERT_FALSE(other.insideBoxes().empty()) << name;
        for (const double band : {0.0, 1.0, 2.0, 100.0}) {
            expectSameDifference(compareSparseFields(sparse_, other, band), compareFields(sparse_.toDense(), other.toDense(), band),
                                 name + ", band " + std::to_string(band));
            expectSameDifference(compareSparseFields(other, sparse_, band), compareFields(other.toDense(), sparse_.toDense(), band),
                                 name + " first, band " + std::to_string(band));
        }
    }
    FieldDifference moved3 = compareSparseFields(sparse_, others[2].second, 0.0);
    EXPECT_GT(moved3.signDifferences, 0u);
    // A grid of 1000^3 samples and no bricks: counted, never made dense.
    FieldHeader header;
    header.grid = sparse_.grid();
    header.grid.dims = {1000, 1000, 1000};
    header.background = 0.1f;
    const SparseField empty(header, {{}, {}, {SparseField::insideBox(header.grid.dims, 0, 125, 0, 0)}}, "empty"); // one row of bricks inside
    const SparseField other(header, {{}, {}, {SparseField::insideBox(header.grid.dims, 100, 125, 0, 0)}}, "other");
    const FieldDifference d = compareSparseFields(empty, other, 0.0);
    EXPECT_EQ(d.signOnly, 1000000000u);
    EXPECT_EQ(d.signDifferences, 100u * 8 * 8 * 8);
    EXPECT_EQ(d.compared, 0u);
    EXPECT_CONTAINS(errorFrom([&] { compareSparseFields(sparse_, empty, 0.0); }), "the fields have different grids: 75x57x45 and 1000x1000x1000");
}

TEST_F(SparseFormats, InsideBoxesOverTheirFieldsBricksAreRefused) {
    const glm::ivec3 brick = sparse_.bricks()[0];
    auto overBrick = [&](FieldHeader& header, SparseField::Storage& storage) {
        storage.insideBoxes = {SparseField::insideBox(header.grid.dims, brick.x, brick.x + 1, brick.y, brick.z)};
    };
    EXPECT_CONTAINS(errorFrom([&] { changed(sparse_, overBrick, "brick.npz"); }), "brick.npz: inside box 0 holds stored brick 0");
}

#if SDFGEN_HAS_OPENVDB

TEST_F(SparseFormats, VdbRoundTripIsExactAndALevelSetToOpenVdb) {
    expectRoundTrip(".vdb");
    const std::string file = path("band.vdb");

    // As OpenVDB reads it: a level set whose active voxels are the band's, whose leaves are the
    // bricks, whose inside is inactive -background tiles, valued as the field at every sample.
    openvdb::initialize();
    openvdb::io::File vdb(file);
    vdb.open();
    const openvdb::FloatGrid::Ptr grid = openvdb::gridPtrCast<openvdb::FloatGrid>(vdb.readGrid("surface"));
    vdb.close();
    ASSERT_TRUE(grid);
    EXPECT_EQ(grid->getGridClass(), openvdb::GRID_LEVEL_SET);
    EXPECT_EQ(grid->background(), sparse_.background());
    EXPECT_EQ(grid->activeVoxelCount(), sparse_.activeCount());
    EXPECT_EQ(grid->tree().leafCount(), sparse_.bricks().size());
    std::size_t insideTiles = 0;
    for (auto tile = grid->tree().cbeginValueOff(); tile; ++tile) insideTiles += !tile.isVoxelValue() && *tile == -sparse_.background();
    EXPECT_GT(insideTiles, 0u);
    const auto accessor = grid->getConstAccessor();
    for (int k = 0; k < sparse_.grid().dims.z; ++k)
        for (int j = 0; j < sparse_.grid().dims.y; ++j)
            for (int i = 0; i < sparse_.grid().dims.x; ++i) ASSERT_EQ(accessor.getValue(openvdb::Coord(i, j, k)), sparse_.at(i, j, k));
    const openvdb::Vec3d world = grid->indexToWorld(openvdb::Vec3d(3, 5, 7));
    const glm::dvec3 expected = sparse_.grid().position(3, 5, 7);
    EXPECT_NEAR(world.x(), expected.x, 1e-12);
    EXPECT_NEAR(world.z(), expected.z, 1e-12);
}

TEST_F(SparseFormats, AFieldGivenUpIsSavedAsTheSameFileAndLeftEmpty) {
    // More bricks than the .vdb writer takes at a time (it hands their memory back chunk by chunk).
    FieldHeader header;
    header.source = "many.obj";
    header.method = "exact";
    header.grid.dims = {8 * 100, 8 * 100, 12};
    header.grid.origin = {-1.0, -2.0, -3.0};
    header.grid.voxel = 0.01;
    header.background = 0.03f;
    SparseField::Storage storage;
    for (int y = 0; y < 100; ++y)
        for (int x = 0; x < 100; x += 2) storage.bricks.emplace_back(x, y, 1); // the brick cut at the grid's end
    storage.values.resize(storage.bricks.size() * SparseField::kBrickSamples);
    for (std::size_t n = 0; n < storage.values.size(); ++n) {
        const bool pastTheEnd = n % SparseField::kBrickSamples >= 4 * 64; // z 12 and on (past the grid's end) hold the background
        storage.values[n] = pastTheEnd ? header.background : header.background * float(std::sin(double(n) * 0.37));
    }
    storage.insideBoxes.push_back({0, 0, 0, 8 * 100, 8, 8});
    const SparseField many(header, std::move(storage), "many");
    for (const char* extension : {".vdb", ".npz"}) {
        const std::string kept = path(std::string("kept") + extension), givenUp = path(std::string("given-up") + extension);
        saveSparseField(many, kept);
        SparseField copy = many;
        saveSparseField(std::move(copy), givenUp);
        EXPECT_TRUE(copy.bricks().empty() && copy.values().empty()) << extension;
        expectSameSparse(loadSparseField(givenUp), loadSparseField(kept));
        expectSameSparse(loadSparseField(givenUp), many);
    }
}

TEST_F(SparseFormats, VdbOfAGridTooLargeToBeDenseStaysSparse) {
    const SparseField huge = changed(sparse_, [](FieldHeader& header, SparseField::Storage& storage) {
        header.grid.dims = {16384, 16384, 16384};
        storage.insideBoxes.clear();
    });
    saveSparseField(huge, path("huge.vdb"));
    expectSameSparse(loadSparseField(path("huge.vdb")), huge);
    const std::string message = errorFrom([&] { loadField(path("huge.vdb")); });
    EXPECT_EQ(message.rfind(path("huge.vdb"), 0), 0u) << message;
    EXPECT_CONTAINS(message, "keep it sparse");
}

TEST_F(SparseFormats, VdbWhoseDimsMultiplyPastTwoToThe64IsRefused) {
    const openvdb::GridPtrVecPtr grids = savedBandGrids();
    (*grids)[0]->removeMeta("sdfgen_dims");
    (*grids)[0]->insertMeta("sdfgen_dims", openvdb::Vec3IMetadata(openvdb::Vec3i(4194304, 2097152, 2097152)));
    openvdb::io::File(path("wrap.vdb")).write(*grids);
    for (const bool sparse : {true, false}) {
        const std::string message = errorFrom([&] { sparse ? (void)loadSparseField(path("wrap.vdb")) : (void)loadField(path("wrap.vdb")); });
        EXPECT_EQ(message.rfind(path("wrap.vdb"), 0), 0u) << message;
        EXPECT_CONTAINS(message, "more than 2^58 samples");
    }
}

TEST_F(SparseFormats, VdbWithActiveTilesIsRefused) {
    const openvdb::GridPtrVecPtr grids = savedBandGrids();
    auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>((*grids)[0]);
    grid->tree().addTile(1, openvdb::Coord(0, 0, 0), -0.01f, /*active=*/true);
    openvdb::io::File(path("tiles.vdb")).write(*grids);
    const std::string message = errorFrom([&] { loadSparseField(path("tiles.vdb")); });
    EXPECT_EQ(message.rfind(path("tiles.vdb"), 0), 0u) << message;
    EXPECT_CONTAINS(message, "active tiles");
}

// The surface of a band field, meshed as a level set: closed and manifold, and the same as the
// dense field's (the band holds every value volumeToMesh reads).
TEST_F(SparseFormats, SurfaceOfABandFieldIsClosedAndEqualsTheDenseOnes) {
    const SurfaceMesh fromSparse = extractSurface(sparse_, 0.0, 0.0);
    const SurfaceMesh fromDense = extractSurface(dense_, 0.0, 0.0);
    EXPECT_EQ(fromSparse.positions, fromDense.positions);
    EXPECT_EQ(fromSparse.triangles, fromDense.triangles);
    const Mesh output = buildMesh("surface", fromSparse.positions, fromSparse.triangles);
    const MeshCheck check = MeshTopology(output).check(output, Bvh(output));
    EXPECT_EQ(check.boundaryEdges, 0u);
    EXPECT_EQ(check.nonManifoldEdges, 0u);
    EXPECT_EQ(check.inconsistentEdges, 0u);
    EXPECT_EQ(check.nonManifoldVertices, 0u);
    EXPECT_CONTAINS(errorFrom([&] { extractSurface(sparse_, 3.0 * dense_.grid.voxel, 0.0); }), "outside the band field's band");
    // An inside box on the grid's boundary cuts the surface open.
    const SparseField cut = changed(sparse_, [](FieldHeader&, SparseField::Storage& storage) {
        storage.insideBoxes.insert(storage.insideBoxes.begin(), {0, 0, 0, 8, 8, 8});
    });
    EXPECT_CONTAINS(errorFrom([&] { extractSurface(cut, 0.0, 0.0); }), "reaches the grid's boundary");
}

#endif

} // namespace
} // namespace sdfgen
