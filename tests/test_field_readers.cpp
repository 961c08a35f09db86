// Hostile field files: every size a file claims is checked against what its bytes can hold before
// anything is allocated for it; grids that are not a field's (non-finite, degenerate, beyond
// float32) are refused by every format; errors are one line naming the file, with the file's own
// text escaped.
#include "core/io/formats/format.hpp"
#include "core/io/formats/npy.hpp"
#include "sdfgen/surface.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/formats.hpp"
#include "sdfgen/memory.hpp"
#include "sdfgen/run_control.hpp"

#include "support/checks.hpp"

#include <gtest/gtest.h>
#if SDFGEN_HAS_OPENVDB
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetSphere.h>
#endif
#include <zip.h>

#include <cmath>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <sys/stat.h>
#include <thread>
#include <unistd.h>
#include <vector>

namespace sdfgen {
namespace {

using test::errorFrom;

Field smallField() {
    Field field;
    field.source = "tet.obj";
    field.method = "exact";
    field.grid.dims = {6, 5, 4};
    field.grid.origin = {-0.25, 0.5, 1.0};
    field.grid.voxel = 0.125;
    field.values.resize(field.grid.sampleCount());
    for (std::size_t i = 0; i < field.values.size(); ++i) field.values[i] = float(i % 7) * 0.01f - 0.03f;
    return field;
}

// A sphere of radius 0.3 in a unit cube sampled at `voxel`-scaled coordinates.
Field sphereField(double voxel) {
    Field field;
    field.method = "analytic";
    field.grid.dims = {16, 16, 16};
    field.grid.origin = {0.0, 0.0, 0.0};
    field.grid.voxel = voxel;
    field.values.resize(field.grid.sampleCount());
    for (int k = 0; k < 16; ++k) {
        for (int j = 0; j < 16; ++j) {
            for (int i = 0; i < 16; ++i) {
                const glm::dvec3 p = field.grid.position(i, j, k) - glm::dvec3(8.0 * voxel);
                field.values[field.grid.index(i, j, k)] = float(std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z) - 5.0 * voxel);
            }
        }
    }
    return field;
}

std::string readBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

template <class T>
void put(std::string& bytes, std::size_t at, T value) {
    ASSERT_LE(at + sizeof(T), bytes.size());
    std::memcpy(&bytes[at], &value, sizeof(T));
}

// An .npz whose sdf.npy member holds `member` deflated (numpy.savez_compressed's layout), plus the
// metadata members; built with libzip, which records the member's true sizes.
std::string deflatedNpz(const std::string& member) {
    zip_error_t error;
    zip_error_init(&error);
    zip_source_t* buffer = zip_source_buffer_create(nullptr, 0, 0, &error);
    zip_t* archive = zip_open_from_source(buffer, ZIP_CREATE | ZIP_TRUNCATE, &error);
    zip_source_keep(buffer);
    const std::vector<std::pair<std::string, std::string>> members = {
        {"sdf.npy", member},
        {"origin.npy", formats::npyFloat64Array({0.0, 0.0, 0.0}, false)},
        {"voxel_size.npy", formats::npyFloat64Array({0.5}, true)},
    };
    for (const auto& [name, bytes] : members) {
        zip_source_t* source = zip_source_buffer(archive, bytes.data(), bytes.size(), 0);
        const zip_int64_t index = zip_file_add(archive, name.c_str(), source, 0);
        zip_set_file_compression(archive, zip_uint64_t(index), ZIP_CM_DEFLATE, 9);
    }
    EXPECT_EQ(zip_close(archive), 0);
    zip_stat_t stat;
    zip_source_stat(buffer, &stat);
    zip_source_open(buffer);
    std::string out(stat.size, '\0');
    zip_source_read(buffer, out.data(), stat.size);
    zip_source_close(buffer);
    zip_source_free(buffer);
    return out;
}

// Overwrites the uncompressed size sdf.npy (the first member) claims, in its local header and its
// central directory entry.
void claimSize(std::string& zip, std::uint32_t size) {
    ASSERT_EQ(zip.compare(0, 4, "PK\x03\x04"), 0);
    put<std::uint32_t>(zip, 22, size);
    const std::size_t central = zip.find("PK\x01\x02");
    ASSERT_NE(central, std::string::npos);
    put<std::uint32_t>(zip, central + 24, size);
}

std::string randomFloats(std::size_t count) {
    std::mt19937 random(5);
    std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
    std::string data(count * 4, '\0');
    for (std::size_t i = 0; i < count; ++i) {
        const float v = uniform(random);
        std::memcpy(&data[4 * i], &v, 4);
    }
    return data;
}

class FieldReaders : public test::ScratchFolderTest {
protected:
    std::string path(const std::string& name) const { return (dir_ / name).string(); }

    // Loading `file` fails with one line that starts with its name and contains `word`.
    void expectLoadError(const std::string& file, const std::string& word) {
        const std::string message = errorFrom([&] { loadField(file); });
        EXPECT_EQ(message.rfind(file, 0), 0u) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        EXPECT_CONTAINS(message, word);
    }

    static std::string replaced(std::string text, const std::string& from, const std::string& to) {
        const std::size_t at = text.find(from);
        EXPECT_NE(at, std::string::npos) << from;
        return at == std::string::npos ? text : text.replace(at, from.size(), to);
    }
};

// ---- .npz --------------------------------------------------------------------------------------

TEST_F(FieldReaders, DeflatedNpzLoads) {
    const std::string member = formats::npyHeader("<f4", true, {4, 4, 4}) + randomFloats(64);
    const Field field = loadField(write("ok.npz", deflatedNpz(member)));
    EXPECT_EQ(field.grid.dims, glm::ivec3(4, 4, 4));
    EXPECT_EQ(field.grid.voxel, 0.5);
}

TEST_F(FieldReaders, NpzMemberClaimingMoreThanDeflateCanHoldIsRefused) {
    // A small archive whose member claims 4 GB: refused from the sizes, before any allocation.
    std::string zip = deflatedNpz(formats::npyHeader("<f4", true, {1000, 1000, 1000}) + randomFloats(64));
    ASSERT_LT(zip.size(), 2000u);
    claimSize(zip, 4000000128u);
    expectLoadError(write("claims.npz", zip), "more than deflate can expand to");
}

TEST_F(FieldReaders, StoredNpzMemberClaimingOtherThanItHoldsIsRefused) {
    saveField(smallField(), path("stored.npz"));
    std::string zip = readBytes(path("stored.npz"));
    claimSize(zip, 4000000128u);
    const std::string file = write("stored-claims.npz", zip);
    const std::string message = errorFrom([&] { loadField(file); });
    EXPECT_EQ(message.rfind(file, 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST_F(FieldReaders, NpzMemberEndingBeforeItsClaimFailsWithoutReadingTheClaim) {
    // 64 KiB of real data in a member that claims (and whose header declares) 256 KiB: within
    // deflate's ratio, so the reading starts, and fails where the data ends.
    std::string zip = deflatedNpz(formats::npyHeader("<f4", true, {64, 32, 32}) + randomFloats(16384));
    const std::uint32_t header = std::uint32_t(formats::npyHeader("<f4", true, {64, 32, 32}).size());
    claimSize(zip, header + 64 * 32 * 32 * 4);
    expectLoadError(write("short.npz", zip), "data ends before the 262144 bytes its header declares");
}

TEST_F(FieldReaders, NpzVoxelSizesAreChecked) {
    for (const double voxel : {1e-320, 1e300, std::numeric_limits<double>::infinity()}) {
        SCOPED_TRACE(voxel);
        const Field field = smallField();
        const std::string file = path("voxel.npz");
        formats::writeNpz(file, {{"sdf.npy", formats::npyFieldHeader(field), field.values.data(), field.values.size() * 4},
                                 {"origin.npy", formats::npyFloat64Array({0.0, 0.0, 0.0}, false)},
                                 {"voxel_size.npy", formats::npyFloat64Array({voxel}, true)}});
        expectLoadError(file, voxel > 1 ? (std::isfinite(voxel) ? "float32" : "not finite") : "voxel size");
    }
}

// ---- .npy --------------------------------------------------------------------------------------

TEST_F(FieldReaders, NpyByteCountOverflowIsReportedAsSuch) {
    // (2^62, 3) float64: the element count fits in 64 bits, the byte count does not.
    const std::string header = formats::npyHeader("<f8", false, {std::uint64_t(1) << 62, 3});
    std::size_t pos = 0;
    const formats::ReadBytes read = [&](void* data, std::size_t size) {
        const std::size_t n = std::min(size, header.size() - pos);
        std::memcpy(data, header.data() + pos, n);
        pos += n;
        return n;
    };
    const formats::NpyHeader parsed = formats::readNpyHeader(read, "points.npy");
    const std::string message = errorFrom([&] { parsed.dataBytes("points.npy"); });
    EXPECT_CONTAINS(message, "points.npy: shape (4611686018427387904, 3) of 8-byte items is more than 2^64 bytes");
}

TEST_F(FieldReaders, NpyHeaderTextIsEscapedInErrors) {
    const std::string dict = "{'descr': '<f\n4\x01', 'fortran_order': True, 'shape': (2, 2, 2), }";
    std::string bytes = "\x93NUMPY\x01";
    bytes += '\0';
    bytes += char(dict.size());
    bytes += '\0';
    expectLoadError(write("escaped.npy", bytes + dict + std::string(32, '\0')), "dtype '<f\\n4\\x01'");
}

// ---- .nrrd -------------------------------------------------------------------------------------

TEST_F(FieldReaders, NrrdDuplicatesAndNonScalarKindsAreRefused) {
    saveField(smallField(), path("f.nrrd"));
    const std::string nrrd = readBytes(path("f.nrrd"));
    expectLoadError(write("twice.nrrd", replaced(nrrd, "type: float\n", "type: float\ntype: float\n")), "field 'type' appears twice");
    expectLoadError(write("alias.nrrd", replaced(nrrd, "encoding: raw\n", "encoding: raw\ncenters: cell cell cell\ncenterings: node node node\n")),
                    "field 'centers' appears twice");
    expectLoadError(write("key.nrrd", replaced(nrrd, "sdfgen_voxel:=", "sdfgen_voxel:=0.5\nsdfgen_voxel:=")), "key 'sdfgen_voxel' appears twice");
    expectLoadError(write("rgb.nrrd", replaced(nrrd, "kinds: domain domain domain", "kinds: RGB-color domain domain")), "kind 'RGB-color' on axis 0");
    expectLoadError(write("list.nrrd", replaced(nrrd, "kinds: domain domain domain", "kinds: domain domain vector")), "kind 'vector' on axis 2");
    expectLoadError(write("kinds2.nrrd", replaced(nrrd, "kinds: domain domain domain", "kinds: domain domain")), "2 entries for 3 axes");
    expectLoadError(write("unknown.nrrd", replaced(nrrd, "endian: little\n", "endian: little\nfavourite colour: blue\n")),
                    "'favourite colour' is not an NRRD field");
    expectLoadError(write("both.nrrd", replaced(nrrd, "space dimension: 3", "space: RAS\nspace dimension: 3")), "both 'space' and 'space dimension'");
    expectLoadError(write("space.nrrd", replaced(nrrd, "space dimension: 3", "space: right-anterior-superior-time")), "not a 3D space");
    expectLoadError(write("spacings.nrrd", replaced(nrrd, "endian: little\n", "endian: little\nspacings: 1 1 1\n")), "'spacings'");
    // What the specification allows reads: its kinds and spaces, informational fields, comments.
    const Field spaced = loadField(write("ras.nrrd", replaced(replaced(nrrd, "space dimension: 3", "space: RAS"), "kinds: domain domain domain",
                                                               "kinds: space domain ???\ncontent: a field\ncenters: cell cell cell\n# note")));
    EXPECT_EQ(spaced.values, smallField().values);
}

TEST_F(FieldReaders, BigEndianNrrdReadsTheSameValues) {
    const Field field = smallField();
    saveField(field, path("f.nrrd"));
    std::string nrrd = replaced(readBytes(path("f.nrrd")), "endian: little", "endian: big");
    const std::size_t data = nrrd.size() - field.values.size() * 4;
    for (std::size_t i = data; i < nrrd.size(); i += 4) std::swap(nrrd[i], nrrd[i + 3]), std::swap(nrrd[i + 1], nrrd[i + 2]);
    EXPECT_EQ(loadField(write("big.nrrd", nrrd)).values, field.values);
}

TEST_F(FieldReaders, NrrdHeaderTextIsEscapedInErrors) {
    saveField(smallField(), path("f.nrrd"));
    const std::string nrrd = readBytes(path("f.nrrd"));
    expectLoadError(write("ctl.nrrd", replaced(nrrd, "type: float", std::string("type: flo\0\x1b", 11))), "'flo\\x00\\x1b'");
    expectLoadError(write("magic.nrrd", "NRRD\r\r\r\x7f\nrest\n\n"), "'NRRD\\r\\r\\r\\x7f'");
    expectLoadError(write("long.nrrd", replaced(nrrd, "type: float", "type: " + std::string(5000, 'f'))), "fff...'");
    expectLoadError(write("utf8.nrrd", replaced(nrrd, "type: float", "type: fl\xc3\xb6\xff")), "'fl\xc3\xb6\\xff'");
}

// ---- Every format: the grid ----------------------------------------------------------------------

TEST_F(FieldReaders, DegenerateGridsAreRefusedByEveryFormat) {
    struct Case {
        glm::dvec3 origin;
        double voxel;
        const char* problem;
    };
    const Case cases[] = {
        {{0, 0, 0}, 1e-320, "voxel size 1e-320 is not a positive normal float32 (1.1754943508222875e-38 to 3.4028234663852886e+38)"},
        {{0, 0, 0}, 1e-39, "is not a positive normal float32"},
        {{0, 0, 0}, 1e300, "is not a positive normal float32"},
        {{1.7e308, 0, 0}, 0.5, "reaches beyond float32's range"},
        {{3.4e38, 0, 0}, 1e37, "reaches beyond float32's range"},
        {{1e20, 0, 0}, 1e-10, "too small for coordinates as large as"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.problem);
        // The writers refuse it (every format, the same rule)...
        Field field = smallField();
        field.grid.origin = c.origin;
        field.grid.voxel = c.voxel;
        for (const char* extension : {".sdf", ".npz", ".vdb", ".nrrd"}) {
            if (!SDFGEN_HAS_OPENVDB && std::string(extension) == ".vdb") continue;
            const std::string file = path(std::string("degenerate") + extension);
            const std::string message = errorFrom([&] { saveField(field, file); });
            EXPECT_CONTAINS(message, file);
            EXPECT_CONTAINS(message, c.problem);
        }
        // ... and the readers, given such a file by someone else.
        char voxel[40], origin[40];
        std::snprintf(voxel, sizeof voxel, "%.17g", c.voxel);
        std::snprintf(origin, sizeof origin, "%.17g", c.origin.x);
        std::string text = "sdfgen-text 1\nsource s\ndims 2 1 1\norigin " + std::string(origin) + " 0 0\nvoxel " + voxel + "\nmethod m\nvalues\n0\n0\n";
        expectLoadError(write("degenerate.sdf", text), c.problem);
        saveField(smallField(), path("ok.nrrd"));
        const std::string nrrd = readBytes(path("ok.nrrd"));
        const std::size_t from = nrrd.find("space directions:"), to = nrrd.find("kinds:");
        std::string header = nrrd.substr(0, from) + "space directions: (" + voxel + ",0,0) (0," + voxel + ",0) (0,0," + voxel +
                             ")\nspace origin: (" + origin + ",0,0)\n" + nrrd.substr(to, nrrd.find("sdfgen_origin") - to) + "\n";
        expectLoadError(write("degenerate.nrrd", header + nrrd.substr(nrrd.size() - field.values.size() * 4)), c.problem);
    }
}

TEST_F(FieldReaders, TinyVoxelsMeshAsTheSameSurfaceScaled) {
    if (!SDFGEN_HAS_OPENVDB) GTEST_SKIP() << "built without OpenVDB (SDFGEN_OPENVDB=OFF)";
    // OpenVDB's transforms refuse voxels under about 1.45e-5; the surface is meshed at a larger
    // power-of-two scale and scaled back, so it is the unit-voxel surface scaled exactly.
    const SurfaceMesh unit = extractSurface(sphereField(1.0), 0.0, 0.0);
    const double tiny = std::ldexp(1.0, -30); // about 9.3e-10
    const SurfaceMesh small = extractSurface(sphereField(tiny), 0.0, 0.0);
    ASSERT_EQ(small.positions.size(), unit.positions.size());
    ASSERT_GT(unit.positions.size(), 100u);
    EXPECT_EQ(small.triangles, unit.triangles);
    for (std::size_t i = 0; i < unit.positions.size(); ++i) {
        for (int a = 0; a < 3; ++a) EXPECT_NEAR(small.positions[i][a] / tiny, unit.positions[i][a], 1e-5) << i;
    }
    const std::string message = errorFrom([&] { saveField(sphereField(tiny), path("tiny.vdb")); });
    EXPECT_CONTAINS(message, "below what an OpenVDB transform can hold");
}

// ---- .vdb (in builds with OpenVDB) -----------------------------------------------------------

#if SDFGEN_HAS_OPENVDB

class VdbReader : public FieldReaders {
protected:
    void SetUp() override {
        FieldReaders::SetUp();
        saveField(smallField(), path("f.vdb"));
        vdb_ = readBytes(path("f.vdb"));
    }
    // Where the value of metadata `name` (after its type name and size) starts.
    std::size_t valueOf(const std::string& name, const std::string& type) const {
        const std::size_t at = vdb_.find(name);
        EXPECT_NE(at, std::string::npos) << name;
        EXPECT_EQ(vdb_.compare(at + name.size() + 4, type.size(), type), 0) << name;
        return at + name.size() + 4 + type.size() + 4;
    }
    std::string vdb_;
};

TEST_F(VdbReader, EveryTruncationIsAOneLineError) {
    for (std::size_t keep = 0; keep < vdb_.size(); keep += keep < 400 ? 7 : 401) {
        SCOPED_TRACE(keep);
        expectLoadError(write("cut.vdb", vdb_.substr(0, keep)), "OpenVDB file");
    }
}

TEST_F(VdbReader, MetadataSizesDisagreeingWithTheirTypesAreRefused) {
    std::string bytes = vdb_;
    put<std::uint32_t>(bytes, valueOf("sdfgen_origin", "vec3d") - 4, 25);
    expectLoadError(write("size.vdb", bytes), "a vec3d value in grid 0's metadata claims 25 bytes");
    bytes = vdb_;
    put<std::uint32_t>(bytes, valueOf("sdfgen_method", "string") - 4, 0x7fffffff);
    expectLoadError(write("string.vdb", bytes), "reach past the end of the file's");
}

TEST_F(VdbReader, SdfgenDimsMustMatchTheGrid) {
    std::string bytes = vdb_;
    const std::size_t dims = valueOf("sdfgen_dims", "vec3i");
    for (int a = 0; a < 3; ++a) put<std::int32_t>(bytes, dims + 4 * std::size_t(a), 1000);
    expectLoadError(write("dims.vdb", bytes), "sdfgen_dims 1000x1000x1000 says 1000000000 samples, the dense grid holds 120");
    bytes = vdb_;
    put<std::int32_t>(bytes, dims, 3);
    expectLoadError(write("smaller.vdb", bytes), "active voxels reach outside its sdfgen_dims 3x5x4");
    bytes = vdb_;
    bytes.replace(bytes.find("sdfgen_band"), 11, "sdfgen_bend");
    expectLoadError(write("unknown.vdb", bytes), "unknown sdfgen metadata 'sdfgen_bend'");
}

TEST_F(VdbReader, NonFiniteTransformsAreRefused) {
    // The transform follows the metadata: its type name, then the map's doubles.
    const std::string type = "UniformScaleTranslateMap";
    const std::size_t map = vdb_.find(type);
    ASSERT_NE(map, std::string::npos);
    for (std::size_t at = map + type.size(); at < map + type.size() + 48; at += 8) {
        std::string bytes = vdb_;
        put<double>(bytes, at, std::nan(""));
        const std::string file = write("nan.vdb", bytes);
        const std::string message = errorFrom([&] { loadField(file); });
        EXPECT_EQ(message.rfind(file, 0), 0u) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
}

TEST_F(VdbReader, FilesOfSeveralGridsWithOffsetsLoadAndOtherGridTypesAreRefused) {
    // io::File writes grid offsets, Blosc blocks and (when asked) half floats; the layout of every
    // grid of a type sdfgen writes (float, and its channels' Vec3s and Int32) is walked, the one
    // named "surface" is read.
    openvdb::initialize();
    auto sphere = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(1.0f, openvdb::Vec3f(0.0f), 0.25f, 3.0f);
    sphere->setName("surface");
    auto halves = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(0.5f, openvdb::Vec3f(0.0f), 0.25f, 3.0f);
    halves->setName("halves");
    halves->setSaveFloatAsHalf(true);
    openvdb::io::File(path("several.vdb")).write({halves, sphere});
    const Field field = loadField(path("several.vdb"));
    const openvdb::CoordBBox active = sphere->evalActiveVoxelBoundingBox();
    for (int a = 0; a < 3; ++a) EXPECT_EQ(field.grid.dims[a], active.max()[a] + 1 - int(std::floor(active.min()[a] / 8.0)) * 8) << "from the leaf below";
    auto vectors = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    vectors->tree().setValue(openvdb::Coord(1, 2, 3), openvdb::Vec3s(1.0f));
    vectors->tree().setValue(openvdb::Coord(40, 2, 3), openvdb::Vec3s(2.0f));
    auto halfVectors = vectors->deepCopy();
    halfVectors->setName("half vectors");
    halfVectors->setSaveFloatAsHalf(true);
    auto indices = openvdb::Int32Grid::create(-1);
    indices->tree().setValue(openvdb::Coord(1, 2, 3), 7);
    openvdb::io::File(path("channels.vdb")).write({vectors, sphere, halfVectors, indices});
    EXPECT_EQ(loadField(path("channels.vdb")).values, field.values);
    auto flags = openvdb::BoolGrid::create(false);
    flags->tree().setValue(openvdb::Coord(1, 2, 3), true);
    openvdb::io::File(path("flags.vdb")).write({sphere, flags});
    expectLoadError(path("flags.vdb"),
                    "grid 1 is of type 'Tree_bool_5_4_3' (sdfgen reads files of float grids, Tree_float_5_4_3, beside Vec3s and Int32 grids)");
}

// A level set's file as io::File writes it (as Houdini does): each leaf's values a compressed
// block (Blosc by default) after its byte count. `flat`: every active value 0.5 and no class, as
// io::File zips no level set and keeps only the zip blocks that shrink.
std::string levelSetFile(const std::string& file, std::uint32_t compression = openvdb::io::COMPRESS_ACTIVE_MASK | openvdb::io::COMPRESS_BLOSC,
                         bool flat = false) {
    openvdb::initialize();
    auto sphere = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(1.0f, openvdb::Vec3f(0.0f), 0.125f, 2.0f);
    sphere->setName("surface");
    if (flat) {
        for (auto value = sphere->beginValueOn(); value; ++value) value.setValue(0.5f);
        sphere->setGridClass(openvdb::GRID_UNKNOWN);
    }
    openvdb::io::File out(file);
    out.setCompression(compression);
    out.write({sphere});
    return readBytes(file);
}

// Where the byte count of the file's last block is: the last leaf's block is the last thing in
// the file, so try each position from the end (a count is followed by exactly that many bytes).
std::size_t lastBlockCount(const std::string& bytes) {
    for (std::size_t at = bytes.size() - 16; at > bytes.size() - 4096; --at) {
        std::int64_t stored;
        std::memcpy(&stored, &bytes[at], 8);
        if (stored > 0 && std::size_t(stored) == bytes.size() - at - 8) return at;
    }
    return 0;
}

TEST_F(VdbReader, CompressedBlockSizesAreCheckedAgainstTheFile) {
    std::string bytes = levelSetFile(path("band.vdb"));
    const std::size_t count = lastBlockCount(bytes);
    ASSERT_NE(count, 0u);
    put<std::int64_t>(bytes, count, std::int64_t(1) << 40);
    expectLoadError(write("block.vdb", bytes), "reach past the end of the file's");
}

TEST_F(VdbReader, BloscHeadersMustClaimTheirBlockAndTheValues) {
    // libblosc reads as many bytes as a block's header claims: the fuzzer's file claims
    // 1717859086 bytes of a 526-byte block.
    const std::string found = std::string(SDFGEN_SOURCE_DIR) + "/tests/fuzz/corpus/vdb/blosc-header-past-block.vdb";
    expectLoadError(found, "has a corrupt Blosc block (526 bytes for 1092, its header claims 1717859086 for 1092)");
    // The header's nbytes, blocksize and cbytes after 4 version bytes.
    const std::string valid = levelSetFile(path("band.vdb"));
    const std::size_t count = lastBlockCount(valid);
    ASSERT_NE(count, 0u);
    const std::size_t header = count + 8;
    std::uint32_t sizes[3];
    std::memcpy(sizes, &valid[header + 4], sizeof sizes);
    EXPECT_NO_THROW(loadField(write("valid.vdb", valid)));
    struct Lie { std::size_t field; std::uint32_t value; };
    for (const Lie lie : {Lie{2, sizes[2] + 1}, Lie{2, 1u << 30}, Lie{2, sizes[2] - 1}, Lie{0, sizes[0] + 4}, Lie{0, sizes[0] - 4}}) {
        std::string bytes = valid;
        put<std::uint32_t>(bytes, header + 4 + 4 * lie.field, lie.value);
        expectLoadError(write("lie.vdb", bytes), "has a corrupt Blosc block");
    }
}

TEST_F(VdbReader, CorruptZipBlocksAreRefusedInOneLine) {
    // zlib's uncompress is bounded by the block and the values: a corrupt block is OpenVDB's error.
    const std::string valid = levelSetFile(path("zip.vdb"), openvdb::io::COMPRESS_ZIP, true);
    const std::size_t count = lastBlockCount(valid);
    ASSERT_NE(count, 0u);
    EXPECT_NO_THROW(loadField(write("valid.vdb", valid)));
    std::size_t refused = 0;
    for (std::size_t at = count + 8; at < valid.size(); at += 3) {
        std::string bytes = valid;
        bytes[at] = char(~bytes[at]);
        const std::string file = write("zip-mutant.vdb", bytes);
        try {
            loadField(file);
        } catch (const Error& e) {
            ++refused;
            EXPECT_EQ(std::string(e.what()).rfind(file, 0), 0u) << e.what();
            EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
        }
    }
    EXPECT_GT(refused, 0u);
}

TEST_F(VdbReader, OneByteMutantsAreLoadedOrRefusedInOneLine) {
    std::mt19937 random(11);
    for (int attempt = 0; attempt < 300; ++attempt) {
        std::string bytes = vdb_;
        const std::size_t at = random() % bytes.size();
        bytes[at] = char(random());
        const std::string file = write("mutant.vdb", bytes);
        try {
            const Field field = loadField(file);
            EXPECT_EQ(field.values.size(), field.grid.sampleCount());
        } catch (const Error& e) {
            EXPECT_EQ(std::string(e.what()).rfind(file, 0), 0u) << e.what();
            EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
        }
    }
}

// The bytes checked are the bytes OpenVDB reads: the file is read once, whole.
TEST_F(VdbReader, IsReadOnceAndOpenVdbReadsTheBytesChecked) {
    // A FIFO yields its bytes once.
    struct sigaction ignore {}, before {};
    ignore.sa_handler = SIG_IGN;
    sigaction(SIGPIPE, &ignore, &before); // a reader that gives up must fail the test, not end it
    const std::string fifo = path("pipe.vdb");
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    std::thread writer([&] { std::ofstream(fifo, std::ios::binary) << vdb_; });
    std::string problem;
    try {
        // As the front ends read it: dense or band is told from the bytes, read once.
        EXPECT_EQ(loadAnyField(fifo).dense().values, smallField().values);
    } catch (const Error& e) {
        problem = e.what();
    }
    const int unblock = open(fifo.c_str(), O_RDONLY | O_NONBLOCK); // for a writer still waiting for a reader
    writer.join();
    close(unblock);
    sigaction(SIGPIPE, &before, nullptr);
    EXPECT_EQ(problem, "");

    // A file rewritten in place after the check, while OpenVDB reads it (from its first progress
    // report past the half that reading the file takes): the field is the one checked. Noise, so
    // that the file stays megabytes.
    Field noisy = smallField();
    noisy.grid.dims = {100, 100, 100};
    noisy.values.resize(noisy.grid.sampleCount());
    std::mt19937 random(5);
    std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
    for (float& v : noisy.values) v = uniform(random);
    const std::string file = path("rewritten.vdb");
    saveField(noisy, file);
    const std::size_t size = readBytes(file).size();
    ASSERT_GT(size, std::size_t(2) << 20);
    bool rewritten = false;
    RunControl control;
    control.progress = [&](double fraction) {
        if (rewritten || fraction <= 0.5) return;
        rewritten = true;
        std::fstream(file, std::ios::in | std::ios::out | std::ios::binary).seekp(1 << 20).write(std::string(size - (1 << 20), '\0').data(),
                                                                                               std::streamsize(size - (1 << 20)));
    };
    const Field read = loadField(file, control);
    EXPECT_TRUE(rewritten);
    EXPECT_EQ(read.values, noisy.values);
    EXPECT_EQ(readBytes(file).substr(size - 10), std::string(10, '\0'));
}

// A .vdb is read whole into memory: one larger than a quarter of the memory available is refused
// before a byte is read (a sparse file here, taking no disk), by every loader.
TEST_F(VdbReader, FilesLargerThanAQuarterOfTheMemoryAvailableAreRefused) {
    const std::uint64_t available = availableMemoryBytes();
    if (available == 0) GTEST_SKIP() << "the memory available is not known here";
    const std::string file = path("huge.vdb");
    std::ofstream(file, std::ios::binary) << vdb_;
    std::error_code error;
    std::filesystem::resize_file(file, available / 4 + (1 << 20), error);
    if (error) GTEST_SKIP() << "no sparse file here: " << error.message();
    expectLoadError(file, "are more than a quarter of the memory available");
    EXPECT_CONTAINS(errorFrom([&] { loadSparseField(file); }), "are more than a quarter of the memory available");
    EXPECT_CONTAINS(errorFrom([&] { loadAnyField(file); }), "are more than a quarter of the memory available");
}

#endif

} // namespace
} // namespace sdfgen
