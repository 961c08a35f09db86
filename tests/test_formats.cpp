// Field formats by extension (.sdf, .npy, .npz, .vdb, .nrrd): bit-exact round trips of values,
// grid, method and source; one-line errors naming the file for truncated, corrupt, wrongly typed
// and oversized files, checked before anything large is allocated; atomic saves.
#include "core/io/formats/format.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/formats.hpp"

#include "support/checks.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#if SDFGEN_HAS_OPENVDB
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Composite.h>
#include <openvdb/tools/LevelSetSphere.h>
#endif

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

namespace sdfgen {
namespace {

using test::errorFrom;
namespace fs = std::filesystem;

// .vdb in builds with OpenVDB (SDFGEN_OPENVDB) only.
const std::vector<std::string> kBinaryExtensions =
    SDFGEN_HAS_OPENVDB ? std::vector<std::string>{".npy", ".npz", ".vdb", ".nrrd"} : std::vector<std::string>{".npy", ".npz", ".nrrd"};

// A 5x3x4 field (no two dimensions equal, so a transposed layout shows) with values of every sign
// and magnitude, an origin and voxel that are not round in binary, and a method with parameters.
Field sampleField() {
    Field field;
    field.source = "meshes/bunny model, v2 \xC3\xA9t\xC3\xA9.obj";
    field.method = "exact";
    field.parameters = {{"sign", "auto/winding"}, {"res", "5"}, {"padding", "0.1"}};
    field.grid.dims = {5, 3, 4};
    field.grid.origin = {-0.1104f, 0.0174f, -0.0774f};
    field.grid.voxel = 0.00292f;
    std::mt19937 random(7);
    std::uniform_real_distribution<float> uniform(-0.05f, 0.05f);
    field.values.resize(field.grid.sampleCount());
    for (float& v : field.values) v = uniform(random);
    field.values[0] = 0.0f;
    field.values[1] = -0.0f;
    field.values[2] = 1e-40f; // subnormal
    field.values[3] = 3.0e38f;
    return field;
}

std::vector<std::uint32_t> bitsOf(const std::vector<float>& values) {
    std::vector<std::uint32_t> bits(values.size());
    std::memcpy(bits.data(), values.data(), values.size() * sizeof(float));
    return bits;
}

void expectSameGrid(const Grid& a, const Grid& b) {
    EXPECT_EQ(a.dims, b.dims);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(double(a.origin[k]), double(b.origin[k])) << "origin " << k;
    EXPECT_EQ(double(a.voxel), double(b.voxel));
}

void expectIdentical(const Field& a, const Field& b) {
    EXPECT_EQ(a.source, b.source);
    EXPECT_EQ(a.method, b.method);
    EXPECT_EQ(a.parameters, b.parameters);
    expectSameGrid(a.grid, b.grid);
    EXPECT_EQ(bitsOf(a.values), bitsOf(b.values));
}

std::string readBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

class Formats : public test::ScratchFolderTest {
protected:
    std::string path(const std::string& name) const { return (dir_ / name).string(); }

    // Loading `path` fails with one line that names it.
    void expectLoadError(const std::string& file, const std::string& word = "") {
        const std::string message = errorFrom([&] { loadField(file); });
        EXPECT_EQ(message.rfind(file, 0), 0u) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        if (!word.empty()) {
            EXPECT_CONTAINS(message, word);
        }
    }

    std::vector<std::string> folderContents() const {
        std::vector<std::string> names;
        for (const auto& entry : fs::directory_iterator(dir_)) names.push_back(entry.path().filename().string());
        std::sort(names.begin(), names.end());
        return names;
    }
};

// ---- Round trips -------------------------------------------------------------------------------

// The built-in formats first, in the help texts' order; a format added to the registry comes after
// them and is taken up by the tests that walk the registry (EveryFormatKeepsTheValuesBitExact).
TEST_F(Formats, ExtensionsAreListedOnceInLowerCase) {
    const std::vector<std::string> extensions = fieldFormatExtensions();
    const std::vector<std::string> builtIn = {".sdf", ".npy", ".npz", ".vdb", ".nrrd"};
    ASSERT_GE(extensions.size(), builtIn.size());
    EXPECT_TRUE(std::equal(builtIn.begin(), builtIn.end(), extensions.begin()));
    for (const std::string& extension : extensions) {
        EXPECT_EQ(std::count(extensions.begin(), extensions.end(), extension), 1) << extension;
        EXPECT_TRUE(extension.size() > 1 && extension[0] == '.') << extension;
        EXPECT_TRUE(std::none_of(extension.begin(), extension.end(), [](char c) { return std::isupper(static_cast<unsigned char>(c)); }))
            << extension;
    }
}

TEST_F(Formats, EveryFormatKeepsTheValuesBitExact) {
    const Field field = sampleField();
    for (const std::string& extension : fieldFormatExtensions()) {
        SCOPED_TRACE(extension);
        if (extension == ".vdb" && !SDFGEN_HAS_OPENVDB) continue;
        const std::string file = path("field" + extension);
        saveField(field, file);
        const Field loaded = loadField(file);
        EXPECT_EQ(loaded.grid.dims, field.grid.dims);
        EXPECT_EQ(bitsOf(loaded.values), bitsOf(field.values));
    }
}

TEST_F(Formats, EveryFormatWithGridKeepsEverythingBitExact) {
    const Field field = sampleField();
    for (const std::string extension : {".sdf", ".npz", ".vdb", ".nrrd"}) {
        SCOPED_TRACE(extension);
        if (extension == ".vdb" && !SDFGEN_HAS_OPENVDB) continue;
        const std::string file = path("field" + std::string(extension));
        saveField(field, file);
        expectIdentical(loadField(file), field);
    }
}

TEST_F(Formats, UpperCaseExtensionsWork) {
    const std::string file = path("FIELD.NPZ");
    saveField(sampleField(), file);
    expectIdentical(loadField(file), sampleField());
}

TEST_F(Formats, NpyKeepsValuesAndShapeOnly) {
    const Field field = sampleField();
    const std::string file = path("field.npy");
    saveField(field, file);
    const Field loaded = loadField(file);
    EXPECT_EQ(loaded.grid.dims, field.grid.dims);
    EXPECT_EQ(bitsOf(loaded.values), bitsOf(field.values));
    EXPECT_EQ(loaded.method, "unknown");
    EXPECT_EQ(double(loaded.grid.voxel), 1.0);
}

TEST_F(Formats, PointArraysRoundTripAndWrongOnesAreRefused) {
    const std::vector<double> points = {0.5, -1.0, 2.25, 1e-300, 3.0, -0.0};
    const std::string file = path("points.npy");
    saveNpy(file, points, {2, 3});
    EXPECT_EQ(loadPointsNpy(file), points);
    // float32 points come back as the doubles of their floats
    const std::vector<float> single = {0.1f, 0.2f, 0.3f};
    saveNpy(path("single.npy"), single, {1, 3});
    EXPECT_EQ(loadPointsNpy(path("single.npy")), (std::vector<double>{double(0.1f), double(0.2f), double(0.3f)}));
    // not (N, 3), not float, a shape that does not hold the values: one line naming the file
    saveNpy(path("flat.npy"), points, {6});
    EXPECT_CONTAINS(errorFrom([&] { loadPointsNpy(path("flat.npy")); }), path("flat.npy") + ": points must be an (N, 3) array");
    saveNpy(path("ints.npy"), std::vector<std::int64_t>{1, 2, 3}, {1, 3});
    EXPECT_CONTAINS(errorFrom([&] { loadPointsNpy(path("ints.npy")); }), "points must be float32 or float64");
    EXPECT_CONTAINS(errorFrom([&] { saveNpy(path("short.npy"), points, {3, 3}); }), path("short.npy") + ": 6 values do not fill an array of 9");
    EXPECT_FALSE(fs::exists(path("short.npy")));
    // a file cut short is refused, not read as fewer points
    const std::string bytes = readBytes(file);
    std::ofstream(path("cut.npy"), std::ios::binary) << bytes.substr(0, bytes.size() - 8);
    EXPECT_CONTAINS(errorFrom([&] { loadPointsNpy(path("cut.npy")); }), "bytes of data, not the 48 its header declares");
}

TEST_F(Formats, NpyIsTheFieldBufferInFortranOrder) {
    const Field field = sampleField();
    const std::string file = path("field.npy");
    saveField(field, file);
    const std::string bytes = readBytes(file);
    const std::size_t dataBytes = field.values.size() * sizeof(float);
    ASSERT_GT(bytes.size(), dataBytes);
    const std::size_t headerBytes = bytes.size() - dataBytes;
    EXPECT_EQ(headerBytes % 64, 0u) << "numpy aligns the data to 64 bytes";
    const std::string header = bytes.substr(0, headerBytes);
    EXPECT_EQ(header.rfind("\x93NUMPY\x01\x00", 0), 0u);
    EXPECT_CONTAINS(header, "'descr': '<f4'");
    EXPECT_CONTAINS(header, "'fortran_order': True");
    EXPECT_CONTAINS(header, "'shape': (5, 3, 4)");
    EXPECT_EQ(std::memcmp(bytes.data() + headerBytes, field.values.data(), dataBytes), 0);
}

std::string npyWithHeader(const std::string& dictionary, std::size_t dataBytes) {
    std::string bytes = "\x93NUMPY\x01";
    bytes += '\0';
    std::string dict = dictionary;
    dict.append((64 - (10 + dict.size() + 1) % 64) % 64, ' ');
    dict += '\n';
    bytes += char(dict.size() & 0xFF);
    bytes += char(dict.size() >> 8);
    return bytes + dict + std::string(dataBytes, '\0');
}

TEST_F(Formats, NpyInCOrderIsTransposed) {
    // numpy.save of a C-ordered (2, 1, 3) array a with a[i, 0, k] = 10 i + k.
    std::string bytes = npyWithHeader("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 1, 3), }", 0);
    for (int i = 0; i < 2; ++i) {
        for (int k = 0; k < 3; ++k) {
            const float v = float(10 * i + k);
            bytes.append(reinterpret_cast<const char*>(&v), 4);
        }
    }
    const Field field = loadField(write("c.npy", bytes));
    ASSERT_EQ(field.grid.dims, glm::ivec3(2, 1, 3));
    for (int i = 0; i < 2; ++i) {
        for (int k = 0; k < 3; ++k) EXPECT_EQ(field.at(i, 0, k), float(10 * i + k));
    }
}

TEST_F(Formats, NpzKeepsSourceNamesThatAreNotUtf8) {
    Field field = sampleField();
    field.source = "odd\xFF\xC3name\xE2\x82.obj";
    const std::string file = path("field.npz");
    saveField(field, file);
    EXPECT_EQ(loadField(file).source, field.source);
    field.source = "";
    saveField(field, file);
    EXPECT_EQ(loadField(file).source, "");
}

TEST_F(Formats, NrrdPlacesTheFirstSampleAtSpaceOrigin) {
    const Field field = sampleField();
    const std::string file = path("field.nrrd");
    saveField(field, file);
    const std::string bytes = readBytes(file);
    EXPECT_EQ(bytes.rfind("NRRD0004\n", 0), 0u);
    EXPECT_CONTAINS(bytes, "type: float\n");
    EXPECT_CONTAINS(bytes, "sizes: 5 3 4\n");
    EXPECT_CONTAINS(bytes, "encoding: raw\n");
    EXPECT_CONTAINS(bytes, "endian: little\n");
    const std::size_t at = bytes.find("space origin: (");
    ASSERT_NE(at, std::string::npos);
    const double x = std::strtod(bytes.c_str() + at + 15, nullptr);
    EXPECT_NEAR(x, double(field.grid.origin.x) + 0.5 * double(field.grid.voxel), 1e-12);
    EXPECT_EQ(std::memcmp(bytes.data() + bytes.size() - field.values.size() * 4, field.values.data(), field.values.size() * 4), 0);
}

// ---- OpenVDB -----------------------------------------------------------------------------------

#if SDFGEN_HAS_OPENVDB

openvdb::FloatGrid::Ptr readSurfaceGrid(const std::string& file) {
    openvdb::initialize();
    openvdb::io::File vdb(file);
    vdb.open(false);
    auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(vdb.readGrid("surface"));
    vdb.close();
    return grid;
}

TEST_F(Formats, VdbIsALevelSetWithSamplesAtIndexCoordinates) {
    const Field field = sampleField();
    const std::string file = path("field.vdb");
    saveField(field, file);
    const auto grid = readSurfaceGrid(file);
    ASSERT_TRUE(grid);
    EXPECT_EQ(grid->getGridClass(), openvdb::GRID_LEVEL_SET);
    EXPECT_EQ(grid->activeVoxelCount(), openvdb::Index64(field.values.size())) << "dense by default";
    const double h = field.grid.voxel;
    for (int k = 0; k < 4; ++k) {
        for (int j = 0; j < 3; ++j) {
            for (int i = 0; i < 5; ++i) {
                const openvdb::Vec3d world = grid->indexToWorld(openvdb::Coord(i, j, k));
                EXPECT_NEAR(world.x(), double(field.grid.origin.x) + (i + 0.5) * h, 1e-12);
                EXPECT_NEAR(world.y(), double(field.grid.origin.y) + (j + 0.5) * h, 1e-12);
                EXPECT_NEAR(world.z(), double(field.grid.origin.z) + (k + 0.5) * h, 1e-12);
                EXPECT_EQ(grid->tree().getValue(openvdb::Coord(i, j, k)), field.at(i, j, k));
            }
        }
    }
}

TEST_F(Formats, VdbBandKeepsOnlyVoxelsNearTheSurface) {
    Field field = sampleField();
    const double band = 3;
    const float width = float(band * field.grid.voxel);
    field.values[3] = 1.0f; // far outside
    field.values[4] = -1.0f; // far inside
    const std::string file = path("band.vdb");
    SaveOptions options;
    options.band = band;
    saveField(field, file, options);
    const auto grid = readSurfaceGrid(file);
    ASSERT_TRUE(grid);
    EXPECT_EQ(grid->background(), width);
    std::size_t near = 0;
    for (const float v : field.values) near += std::fabs(v) < width;
    EXPECT_LT(near, field.values.size());
    EXPECT_EQ(grid->activeVoxelCount(), openvdb::Index64(near));

    const Field loaded = loadField(file);
    expectSameGrid(loaded.grid, field.grid);
    EXPECT_EQ(loaded.method, field.method);
    for (std::size_t i = 0; i < field.values.size(); ++i) {
        const float v = field.values[i];
        const float expected = std::fabs(v) < width ? v : std::copysign(width, v);
        EXPECT_EQ(loaded.values[i], expected) << "sample " << i << " value " << v;
    }
}

TEST_F(Formats, VdbBandBelowOneVoxelIsRefused) {
    SaveOptions options;
    options.band = 0.5;
    const std::string file = path("band.vdb");
    EXPECT_CONTAINS(errorFrom([&] { saveField(sampleField(), file, options); }), "band");
    EXPECT_FALSE(fs::exists(file));
}

// The box of a grid's active voxels, its low corner moved down onto the leaves' 8-voxel grid:
// another program's grid as sdfgen reads it.
openvdb::CoordBBox leafAlignedActiveBox(const openvdb::FloatGrid& grid) {
    const openvdb::CoordBBox active = grid.evalActiveVoxelBoundingBox();
    openvdb::Coord low = active.min();
    for (int a = 0; a < 3; ++a) low[a] = int(std::floor(low[a] / 8.0)) * 8;
    return openvdb::CoordBBox(low, active.max());
}

TEST_F(Formats, ForeignVdbLoadsItsActiveBox) {
    openvdb::initialize();
    const float h = 0.125f;
    auto sphere = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(1.0f, openvdb::Vec3f(0.5f, 0.0f, -0.25f), h, 3.0f);
    sphere->setName("ls_sphere");
    const std::string file = path("sphere.vdb");
    openvdb::io::File(file).write({sphere});

    const Field field = loadField(file);
    const openvdb::CoordBBox box = leafAlignedActiveBox(*sphere);
    EXPECT_NE(box.min(), sphere->evalActiveVoxelBoundingBox().min()) << "the test should move the corner";
    EXPECT_EQ(field.grid.dims, glm::ivec3(box.dim().x(), box.dim().y(), box.dim().z()));
    EXPECT_EQ(double(field.grid.voxel), double(h));
    // A level set reads sparse too, into the same samples.
    ASSERT_TRUE(loadAnyField(file).isBand());
    const SparseField sparse = loadSparseField(file);
    EXPECT_EQ(sparse.grid().dims, field.grid.dims);
    EXPECT_EQ(sparse.grid().origin, field.grid.origin);
    EXPECT_EQ(sparse.toDense().values, field.values);
    for (const openvdb::Coord c : {box.min(), box.max(), openvdb::Coord(4, 0, -2), openvdb::Coord(0, 0, 0)}) {
        const int i = c.x() - box.min().x(), j = c.y() - box.min().y(), k = c.z() - box.min().z();
        EXPECT_EQ(field.at(i, j, k), sphere->tree().getValue(c));
        EXPECT_EQ(sparse.at(i, j, k), sphere->tree().getValue(c));
        const openvdb::Vec3d world = sphere->indexToWorld(c);
        EXPECT_NEAR(double(field.grid.origin.x) + (i + 0.5) * h, world.x(), 1e-6);
        EXPECT_NEAR(double(field.grid.origin.y) + (j + 0.5) * h, world.y(), 1e-6);
        EXPECT_NEAR(double(field.grid.origin.z) + (k + 0.5) * h, world.z(), 1e-6);
    }
    EXPECT_LT(field.at(4 - box.min().x(), -box.min().y(), -2 - box.min().z()), 0.0f) << "the centre is inside";
}

// Two small spheres 10^6 voxels apart as another program's level set: their active box has
// 10^6 x 32 x 32 samples (4 GB dense).
openvdb::FloatGrid::Ptr farApartSpheres() {
    openvdb::initialize();
    auto spheres = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(10.0f, openvdb::Vec3f(0.0f), 1.0f, 3.0f);
    auto far = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(10.0f, openvdb::Vec3f(1e6f, 0.0f, 0.0f), 1.0f, 3.0f);
    openvdb::tools::csgUnion(*spheres, *far);
    spheres->setName("spheres");
    return spheres;
}

TEST_F(Formats, ForeignLevelSetWithoutItsClassIsReadSparse) {
    // Other programs write level sets without a class, or of class "unknown": read as level sets
    // all the same (a positive background, values within it, active voxels in a band), never dense
    // over their box.
    const auto spheres = farApartSpheres();
    const std::string named = path("named.vdb");
    openvdb::io::File(named).write({spheres});
    const SparseField expected = loadSparseField(named);
    for (const bool unknown : {false, true}) {
        SCOPED_TRACE(unknown ? "class unknown" : "no class");
        const auto unclassed = spheres->deepCopy();
        if (unknown) unclassed->setGridClass(openvdb::GRID_UNKNOWN);
        else unclassed->removeMeta(openvdb::GridBase::META_GRID_CLASS);
        const std::string file = path("unclassed.vdb");
        openvdb::io::File(file).write({unclassed});
        ASSERT_TRUE(loadAnyField(file).isBand());
        const SparseField field = loadSparseField(file);
        EXPECT_EQ(field.grid().dims, expected.grid().dims);
        EXPECT_LT(field.bricks().size(), 2000u);
        EXPECT_EQ(field.bricks(), expected.bricks());
        EXPECT_EQ(field.values(), expected.values());
        EXPECT_EQ(field.insideBoxes(), expected.insideBoxes());
    }
}

TEST_F(Formats, ForeignGridWithoutAClassIsDenseUnlessALevelSet) {
    openvdb::initialize();
    // Every voxel of its box active, values beyond the background: a dense grid, read as it is.
    auto dense = openvdb::FloatGrid::create(0.5f);
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 4; ++i) dense->tree().setValue(openvdb::Coord(8 + i, j, k), float(i + 10 * j + 100 * k) - 50.0f);
    dense->setName("surface");
    const std::string file = path("dense.vdb");
    openvdb::io::File(file).write({dense});
    EXPECT_FALSE(loadAnyField(file).isBand());
    const Field field = loadField(file);
    EXPECT_EQ(field.grid.dims, glm::ivec3(4, 2, 3));
    EXPECT_EQ(field.at(3, 1, 2), 3.0f + 10.0f + 200.0f - 50.0f);

    // Two far voxels whose values lie beyond the background: no level set, and its dense box of
    // 2^60 samples is refused in one line before anything is allocated.
    auto spread = openvdb::FloatGrid::create(0.5f);
    spread->tree().setValue(openvdb::Coord(0, 0, 0), 7.0f);
    spread->tree().setValue(openvdb::Coord(1 << 20, 1 << 20, 1 << 20), -7.0f);
    spread->setName("surface");
    const std::string huge = path("huge.vdb");
    openvdb::io::File(huge).write({spread});
    for (const int loader : {0, 1, 2}) {
        try {
            loader == 0 ? (void)loadAnyField(huge) : loader == 1 ? (void)loadSparseField(huge) : (void)loadField(huge);
            ADD_FAILURE() << "a dense box of 2^60 samples was read";
        } catch (const Error& e) {
            EXPECT_EQ(std::string(e.what()).rfind(huge + ": ", 0), 0u) << e.what();
            EXPECT_CONTAINS(e.what(), "1048577x1048577x1048577");
            EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
        }
    }
}

// The process's resident bytes (VmRSS). Unused under ASan, whose quarantine keeps freed memory.
[[maybe_unused]] double residentBytes() {
    std::ifstream status("/proc/self/status");
    for (std::string line; std::getline(status, line);) {
        if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) * 1024.0;
    }
    return 0.0;
}

TEST_F(Formats, CorruptVdbTopologyLeavesNothingBehind) {
    // A grid written zip-compressed (OpenVDB zips grids of no class only), its first compressed
    // block (the values of the first node under the root) garbled after the zlib header, its size
    // kept: the layout walk passes it, OpenVDB's decompression throws while that node's subtree is
    // being read. OpenVDB 10's own RootNode::readTopology leaked the subtree (270 KB) on every such read.
    openvdb::initialize();
    auto sphere = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(1.0f, openvdb::Vec3f(0.0f), 0.125f, 3.0f);
    sphere->setName("surface");
    sphere->setGridClass(openvdb::GRID_UNKNOWN);
    const std::string file = path("garbled.vdb");
    openvdb::io::File out(file);
    out.setCompression(openvdb::io::COMPRESS_ZIP);
    out.write({sphere});
    std::string bytes;
    {
        std::ifstream in(file, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    const std::size_t zlib = bytes.find("\x78\x9c", bytes.find("Tree_float_5_4_3"));
    ASSERT_NE(zlib, std::string::npos);
    ASSERT_LT(zlib + 40, bytes.size());
    for (std::size_t b = zlib + 2; b < zlib + 40; ++b) bytes[b] = char(0xff);
    std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;

    auto readOnce = [&] {
        try {
            loadSparseField(file);
            ADD_FAILURE() << "the garbled file was read";
        } catch (const Error& e) {
            EXPECT_EQ(std::string(e.what()).rfind(file + ": ", 0), 0u) << e.what();
        }
    };
    for (int n = 0; n < 20; ++n) readOnce(); // the allocator's own pools settle
#ifdef SDFGEN_TEST_ASAN // ASan keeps freed memory in quarantine; there LeakSanitizer checks that nothing leaks
    for (int n = 0; n < 300; ++n) readOnce();
#else
    const double before = residentBytes();
    for (int n = 0; n < 300; ++n) readOnce();
    EXPECT_LT(residentBytes() - before, 20e6) << "300 reads of a bad file kept memory (a leak would keep 80 MB)";
#endif
}

TEST_F(Formats, ForeignLevelSetIsReadSparseHoweverFarApartItsParts) {
    // Read sparse, a few hundred bricks.
    const auto spheres = farApartSpheres();
    const std::string file = path("far.vdb");
    openvdb::io::File(file).write({spheres});
    ASSERT_TRUE(loadAnyField(file).isBand());
    const SparseField field = loadSparseField(file);
    EXPECT_GT(field.grid().dims.x, 1000000);
    EXPECT_LT(field.bricks().size(), 2000u);
    const openvdb::CoordBBox box = leafAlignedActiveBox(*spheres);
    EXPECT_LT(field.at(-box.min().x(), -box.min().y(), -box.min().z()), 0.0f) << "the first centre is inside";
    EXPECT_LT(field.at(1000000 - box.min().x(), -box.min().y(), -box.min().z()), 0.0f) << "the second centre is inside";
    EXPECT_GT(field.at(500000 - box.min().x(), -box.min().y(), -box.min().z()), 0.0f) << "between them is outside";
}
#else
TEST_F(Formats, VdbWithoutOpenVdbIsAnErrorNamingTheFile) {
    const std::string file = path("field.vdb");
    for (const std::string& message : {errorFrom([&] { saveField(sampleField(), file); }), errorFrom([&] { loadField(file); })}) {
        EXPECT_EQ(message.rfind(file + ": ", 0), 0u) << message;
        EXPECT_CONTAINS(message, "built without OpenVDB");
    }
    EXPECT_TRUE(folderContents().empty());
}
#endif

// ---- Bad files ---------------------------------------------------------------------------------

TEST_F(Formats, UnknownExtensionIsAnErrorListingTheKnownOnes) {
    for (const std::string name : {"field.xyz", "field", "field.npy.bak"}) {
        const std::string file = path(name);
        const std::string message = errorFrom([&] { saveField(sampleField(), file); });
        EXPECT_CONTAINS(message, file);
        EXPECT_CONTAINS(message, ".sdf, .npy, .npz, .vdb, .nrrd");
        EXPECT_FALSE(fs::exists(file)) << "nothing may be written";
    }
    write("field.xyz", "anything");
    expectLoadError(path("field.xyz"), "unknown field format");
}

TEST_F(Formats, TruncatedFilesAreOneLineErrors) {
    const Field field = sampleField();
    for (const std::string& extension : kBinaryExtensions) {
        SCOPED_TRACE(extension);
        const std::string whole = path("whole" + extension);
        saveField(field, whole);
        const std::string bytes = readBytes(whole);
        for (const std::size_t keep : {std::size_t(0), std::size_t(5), std::size_t(40), bytes.size() / 2, bytes.size() - 4, bytes.size() - 1}) {
            SCOPED_TRACE(keep);
            expectLoadError(write("cut" + extension, bytes.substr(0, keep)));
        }
        expectLoadError(write("longer" + extension, bytes + "xxxx"));
    }
}

TEST_F(Formats, GarbageFilesAreOneLineErrors) {
    std::mt19937 random(3);
    for (const std::string& extension : kBinaryExtensions) {
        SCOPED_TRACE(extension);
        for (int attempt = 0; attempt < 5; ++attempt) {
            std::string bytes(std::size_t(64 << attempt), '\0');
            for (char& c : bytes) c = char(random());
            expectLoadError(write("garbage" + extension, bytes));
        }
        expectLoadError(write("empty" + extension, ""));
        expectLoadError(path("missing" + extension), "cannot open");
    }
}

TEST_F(Formats, CorruptedBytesNeverLoadSilentlyWrongGrids) {
    // Flip one byte at a time in the metadata-bearing parts: loading either fails with a one-line
    // error or (for a byte of sample data) gives a field on the same grid.
    const Field field = sampleField();
    for (const std::string extension : {".npy", ".npz", ".nrrd"}) {
        SCOPED_TRACE(extension);
        const std::string whole = path("whole" + std::string(extension));
        saveField(field, whole);
        const std::string bytes = readBytes(whole);
        for (std::size_t at = 0; at < std::min<std::size_t>(bytes.size(), 200); at += 3) {
            std::string changed = bytes;
            changed[at] = char(changed[at] ^ 0x5A);
            const std::string file = write("flipped" + std::string(extension), changed);
            try {
                const Field loaded = loadField(file);
                EXPECT_EQ(loaded.values.size(), loaded.grid.sampleCount());
            } catch (const Error& e) {
                EXPECT_EQ(std::string(e.what()).rfind(file, 0), 0u) << e.what();
            }
        }
    }
}

TEST_F(Formats, NpyHeaderIsValidated) {
    const std::string ok = "{'descr': '<f4', 'fortran_order': True, 'shape': (2, 2, 2), }";
    ASSERT_NO_THROW(loadField(write("ok.npy", npyWithHeader(ok, 32))));
    expectLoadError(write("f8.npy", npyWithHeader("{'descr': '<f8', 'fortran_order': True, 'shape': (2, 2, 2), }", 64)), "'<f8'");
    expectLoadError(write("big.npy", npyWithHeader("{'descr': '>f4', 'fortran_order': True, 'shape': (2, 2, 2), }", 32)), "'>f4'");
    expectLoadError(write("2d.npy", npyWithHeader("{'descr': '<f4', 'fortran_order': True, 'shape': (4, 2), }", 32)), "3-dimensional");
    expectLoadError(write("zero.npy", npyWithHeader("{'descr': '<f4', 'fortran_order': True, 'shape': (0, 2, 2), }", 0)), "at least 1");
    expectLoadError(write("short.npy", npyWithHeader(ok, 31)), "truncated");
    expectLoadError(write("long.npy", npyWithHeader(ok, 36)), "unexpected bytes");
    expectLoadError(write("key.npy", npyWithHeader("{'descr': '<f4', 'fortran_order': True, 'shape': (2, 2, 2), 'x': 1}", 32)), "key");
    expectLoadError(write("nokey.npy", npyWithHeader("{'descr': '<f4', 'shape': (2, 2, 2), }", 32)), "fortran_order");
    expectLoadError(write("syntax.npy", npyWithHeader("{'descr': '<f4', 'fortran_order': Maybe, 'shape': (2, 2, 2), }", 32)));
    expectLoadError(write("ver.npy", "\x93NUMPY\x09" + std::string(100, ' ')), "version");
}

TEST_F(Formats, HugeDeclaredShapesAreRefusedBeforeAllocating) {
    // A few bytes claiming terabytes: refused from the header, never allocated.
    expectLoadError(write("huge.npy", npyWithHeader("{'descr': '<f4', 'fortran_order': True, 'shape': (100000, 100000, 100000), }", 16)), "too large");
    expectLoadError(write("wrap.npy", npyWithHeader("{'descr': '<f4', 'fortran_order': True, 'shape': (4294967296, 4294967296, 4294967296), }", 16)));
    expectLoadError(write("digits.npy", npyWithHeader("{'descr': '<f4', 'fortran_order': True, 'shape': (99999999999999999999999, 1, 1), }", 16)));

    const Field field = sampleField();
    saveField(field, path("f.nrrd"));
    std::string nrrd = readBytes(path("f.nrrd"));
    const std::string sizes = "sizes: 5 3 4";
    nrrd.replace(nrrd.find(sizes), sizes.size(), "sizes: 100000 100000 100000");
    expectLoadError(write("huge.nrrd", nrrd), "too large");
}

TEST_F(Formats, NonFiniteValuesAreRefused) {
    Field field = sampleField();
    for (const std::string extension : {".npy", ".npz", ".nrrd"}) { // .vdb compresses its values
        const std::string file = path("nan" + extension);
        saveField(field, file);
        std::string bytes = readBytes(file);
        const float nan = std::nanf("");
        // The last sample sits at the end of the raw data in .npy, .nrrd and the stored .npz member.
        const std::size_t last = extension == ".npz" ? bytes.find(std::string(reinterpret_cast<const char*>(&field.values.back()), 4))
                                                     : bytes.size() - 4;
        ASSERT_NE(last, std::string::npos);
        bytes.replace(last, 4, std::string(reinterpret_cast<const char*>(&nan), 4));
        expectLoadError(write("nan" + extension, bytes), extension == ".npz" ? "" : "not finite");
    }
    field.values[7] = std::numeric_limits<float>::infinity();
    for (const std::string& extension : kBinaryExtensions) {
        const std::string file = path("inf" + extension);
        EXPECT_CONTAINS(errorFrom([&] { saveField(field, file); }), "not finite");
        EXPECT_FALSE(fs::exists(file));
    }
}

TEST_F(Formats, NpzMembersAreValidated) {
    const std::string file = path("f.npz");
    saveField(sampleField(), file);
    // Not a zip at all, and a zip of something else.
    expectLoadError(write("text.npz", "PK\x03\x04 but not really a zip archive"), "not a valid .npz");
    saveField(sampleField(), path("plain.npy"));
    const std::string npy = readBytes(path("plain.npy"));
    expectLoadError(write("npy-renamed.npz", npy), "not a valid .npz");
}

TEST_F(Formats, NrrdHeaderIsValidated) {
    saveField(sampleField(), path("f.nrrd"));
    const std::string nrrd = readBytes(path("f.nrrd"));
    auto replaced = [&](const std::string& from, const std::string& to) {
        std::string copy = nrrd;
        const std::size_t at = copy.find(from);
        EXPECT_NE(at, std::string::npos) << from;
        return copy.replace(at, from.size(), to);
    };
    expectLoadError(write("double.nrrd", replaced("type: float", "type: double")), "type");
    expectLoadError(write("gzip.nrrd", replaced("encoding: raw", "encoding: gzip")), "encoding");
    expectLoadError(write("2d.nrrd", replaced("dimension: 3\n", "dimension: 2\n")), "dimension");
    expectLoadError(write("noorigin.nrrd", replaced("space origin:", "space orrigin:")), "'space orrigin' is not an NRRD field");
    expectLoadError(write("noorigin2.nrrd", replaced("space origin: ", "content: ")), "no 'space origin'");
    expectLoadError(write("skew.nrrd", replaced("space directions: (", "space directions: (1,")), "space directions");
    expectLoadError(write("magic.nrrd", replaced("NRRD0004", "NRRD0009")), "not an NRRD file");
    expectLoadError(write("line.nrrd", replaced("kinds: domain domain domain", "this is not a header line")), "header line");
}

// ---- Atomic saves ------------------------------------------------------------------------------

TEST_F(Formats, FailedSaveLeavesTheOldFileAndNoTemporaries) {
    Field bad = sampleField();
    bad.values.pop_back();
    for (const std::string& extension : kBinaryExtensions) {
        SCOPED_TRACE(extension);
        const std::string file = write("keep" + extension, "previous contents");
        EXPECT_CONTAINS(errorFrom([&] { saveField(bad, file); }), file);
        EXPECT_EQ(readBytes(file), "previous contents");
        saveField(sampleField(), file);
        saveField(sampleField(), file);
    }
    for (const std::string& name : folderContents()) EXPECT_EQ(name.find(".tmp-"), std::string::npos) << name;
    std::vector<std::string> kept;
    for (const std::string& extension : kBinaryExtensions) kept.push_back("keep" + extension);
    std::sort(kept.begin(), kept.end());
    EXPECT_EQ(folderContents(), kept);
}

// ---- Progress and Cancel -----------------------------------------------------------------------

// A sphere's distances on a grid large enough for many blocks of every reader (13 MB of values).
Field sphereField(int n) {
    Field field;
    field.source = "sphere";
    field.method = "exact";
    field.grid.dims = {n, n - 7, n - 13};
    field.grid.origin = {-1.0, -1.0, -1.0};
    field.grid.voxel = 2.0 / n;
    field.values.resize(field.grid.sampleCount());
    for (int k = 0; k < field.grid.dims.z; ++k)
        for (int j = 0; j < field.grid.dims.y; ++j)
            for (int i = 0; i < field.grid.dims.x; ++i) {
                const glm::dvec3 p = glm::dvec3(field.grid.origin) + double(field.grid.voxel) * (glm::dvec3(i, j, k) + 0.5);
                field.values[(std::size_t(k) * field.grid.dims.y + j) * field.grid.dims.x + i] = float(glm::length(p) - 0.6);
            }
    return field;
}

// Reads `file` with a control: the progress reported rises to 1 and the field is the one read
// without; then a Cancel raised at the first report stops the read with Cancelled.
template <class Load>
void expectProgressAndCancel(const std::string& file, const Load& load) {
    std::vector<double> reports;
    RunControl control;
    control.progress = [&](double fraction) { reports.push_back(fraction); };
    load(control);
    ASSERT_GE(reports.size(), 3u);
    EXPECT_TRUE(std::is_sorted(reports.begin(), reports.end()));
    EXPECT_EQ(reports.back(), 1.0);

    std::atomic<bool> cancel{false};
    int reportsAfterCancel = 0;
    control.cancel = &cancel;
    control.progress = [&](double) { reportsAfterCancel += cancel.exchange(true); };
    EXPECT_THROW(load(control), Cancelled) << file;
    EXPECT_EQ(reportsAfterCancel, 0) << "the read went on after the Cancel";
}

TEST_F(Formats, EveryReaderReportsProgressAndStopsWhenCancelled) {
    const Field big = sphereField(160);
    for (const std::string& extension : fieldFormatExtensions()) {
        SCOPED_TRACE(extension);
        if (extension == ".vdb" && !SDFGEN_HAS_OPENVDB) continue;
        // The text format is slow to write: a smaller field still spans many checks.
        const Field field = extension == ".sdf" ? sphereField(90) : big;
        const std::string file = path("big" + extension);
        saveField(field, file);
        const Field plain = loadField(file);
        expectProgressAndCancel(file, [&](const RunControl& control) { EXPECT_EQ(bitsOf(loadField(file, control).values), bitsOf(plain.values)); });
    }
    // Band fields, read as bricks.
    const SparseField band = formats::sparseFromDense(big, float(12.0 * big.grid.voxel), "big");
    for (const std::string extension : {".npz", ".vdb"}) {
        SCOPED_TRACE(extension);
        if (extension == ".vdb" && !SDFGEN_HAS_OPENVDB) continue;
        const std::string file = path("band" + extension);
        saveSparseField(band, file);
        expectProgressAndCancel(file, [&](const RunControl& control) { EXPECT_EQ(loadSparseField(file, control).values(), band.values()); });
    }
}

TEST_F(Formats, SaveIntoAMissingFolderFails) {
    for (const std::string& extension : kBinaryExtensions) {
        const std::string file = path("no-such-folder/f" + extension);
        EXPECT_CONTAINS(errorFrom([&] { saveField(sampleField(), file); }), file);
    }
    EXPECT_TRUE(folderContents().empty());
}

} // namespace
} // namespace sdfgen
