// OpenVDB: a FloatGrid named "surface" (the name Houdini's VDB from Polygons gives) of class level
// set, with a transform that puts index (i, j, k) at sample (i, j, k): voxel size h, translation
// origin + h/2. Dense by default; with a band of V voxels only samples with |d| < V h stay active
// and the rest are inactive +-V h, as OpenVDB level sets are. The grid's sdfgen_* metadata keep
// the exact grid, method and source. A field's channels (sdfgen::Channels) follow as grids of their
// names with the surface grid's transform and active voxels: "gradient" and "closest" Vec3SGrids,
// "triangle" an Int32Grid. Also the iso-surfaces of `sdfgen surface`.
//
// The library the core opens on first use (core/io/openvdb_plugin.hpp), so that only runs that read
// or write OpenVDB load it.
#include "core/io/atomic_file.hpp"
#include "core/io/formats/format.hpp"
#include "core/io/openvdb_plugin.hpp"
#include "sdfgen/error.hpp"

#include <openvdb/io/DelayedLoadMetadata.h>
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <openvdb/tree/LeafManager.h>

#include <algorithm>
#include <array>
#include <set>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <tuple>
#include <sys/stat.h>

namespace sdfgen::formats {

namespace {

constexpr const char* kGridName = "surface";
constexpr const char* kFloatTreeType = "Tree_float_5_4_3";

using DenseField = openvdb::tools::Dense<float, openvdb::tools::LayoutXYZ>; // x fastest, like Field::values

openvdb::CoordBBox indexBox(const Grid& grid) {
    return openvdb::CoordBBox(openvdb::Coord(0, 0, 0), openvdb::Coord(grid.dims.x - 1, grid.dims.y - 1, grid.dims.z - 1));
}

// A walk through a whole VDB file as OpenVDB will read it (header, metadata, grid descriptors,
// transforms, trees), without keeping anything: OpenVDB allocates what a count or length claims
// before it reads what it describes (strings, metadata values, compressed blocks), so each one is
// checked here against the bytes the file has left and a corrupt one is refused before OpenVDB
// sees the file.
class VdbLayout {
public:
    VdbLayout(std::istream& in, std::uint64_t fileBytes, const std::string& path) : in_(in), size_(fileBytes), path_(path) {}

    void check() {
        if (read<std::int64_t>("the magic number") != std::int64_t(openvdb::OPENVDB_MAGIC)) fail("not an OpenVDB file (no VDB magic number)");
        version_ = read<std::uint32_t>("the format version");
        if (version_ < openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION || version_ > openvdb::OPENVDB_FILE_VERSION) {
            fail("OpenVDB file format version " + std::to_string(version_) + " is not supported (sdfgen reads " +
                 std::to_string(openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION) + " to " + std::to_string(openvdb::OPENVDB_FILE_VERSION) + ")");
        }
        const std::uint32_t libraryMajor = read<std::uint32_t>("the library version");
        const std::uint32_t libraryMinor = read<std::uint32_t>("the library version");
        openvdb::io::setVersion(in_, openvdb::VersionId(libraryMajor, libraryMinor), version_); // for Transform::read
        const bool hasOffsets = read<char>("the grid offsets flag") != 0;
        skip(36, "the file's UUID");
        metaMap("the file's metadata");
        const std::int32_t grids = read<std::int32_t>("the grid count");
        // A descriptor and its grid take at least 48 bytes (six lengths and counts, three offsets).
        if (grids < 1 || std::uint64_t(grids) > (size_ - pos_) / 48) {
            fail("not a readable OpenVDB file: it claims " + std::to_string(grids) + " grids, more than its remaining " + std::to_string(size_ - pos_) + " bytes hold");
        }
        for (std::int32_t g = 0; g < grids; ++g) {
            const std::string what = "grid " + std::to_string(g);
            string(what + "'s name");
            const std::string type = string(what + "'s type");
            const bool instance = !string(what + "'s instance parent").empty();
            // OpenVDB reads every grid of the file; sdfgen checks the layout of the grid types it
            // writes (the distance and its channels).
            const ValueLayout layout = valueLayout(type, what);
            const std::int64_t gridPos = read<std::int64_t>(what + "'s offsets");
            const std::int64_t blockPos = read<std::int64_t>(what + "'s offsets");
            const std::int64_t endPos = read<std::int64_t>(what + "'s offsets");
            if (hasOffsets && !(gridPos == std::int64_t(pos_) && blockPos >= gridPos && endPos >= blockPos && std::uint64_t(endPos) <= size_)) {
                fail(what + "'s offsets (" + std::to_string(gridPos) + ", " + std::to_string(blockPos) + ", " + std::to_string(endPos) +
                     ") do not lie in the file's " + std::to_string(size_) + " bytes");
            }
            const std::uint32_t compression = read<std::uint32_t>(what + "'s compression flags");
            metaMap(what + "'s metadata");
            transform(what + "'s transform");
            if (!instance) tree(compression, layout, what + "'s tree");
            if (hasOffsets && std::uint64_t(endPos) != pos_) fail(what + " ends at byte " + std::to_string(pos_) + ", not at its end offset " + std::to_string(endPos));
        }
        if (pos_ != size_) fail("not a readable OpenVDB file (" + std::to_string(size_ - pos_) + " bytes after the last grid)");
    }

private:
    // How a tree's values are stored: the value type's size (background, tiles, inactive values)
    // and whether the buffers hold them as half floats.
    struct ValueLayout {
        std::uint64_t bytes;
        bool half;
        std::uint64_t stored() const { return half ? bytes / 2 : bytes; }
    };
    ValueLayout valueLayout(const std::string& type, const std::string& what) const {
        const std::string halfSuffix = "_HalfFloat";
        const bool half = type.size() > halfSuffix.size() && type.compare(type.size() - halfSuffix.size(), halfSuffix.size(), halfSuffix) == 0;
        const std::string base = half ? type.substr(0, type.size() - halfSuffix.size()) : type;
        if (base == kFloatTreeType) return {4, half};
        if (base == "Tree_vec3s_5_4_3") return {12, half};
        if (base == "Tree_int32_5_4_3" && !half) return {4, false};
        fail(what + " is of type '" + printable(type) + "' (sdfgen reads files of float grids, " + kFloatTreeType +
             ", beside Vec3s and Int32 grids)");
    }

    [[noreturn]] void fail(const std::string& problem) const { throw Error(path_ + ": " + problem); }

    void need(std::uint64_t bytes, const std::string& what) const {
        if (bytes > size_ - pos_) {
            fail("not a readable OpenVDB file: " + what + " (" + std::to_string(bytes) + " bytes at byte " + std::to_string(pos_) +
                 ") reach past the end of the file's " + std::to_string(size_) + " bytes");
        }
    }
    template <class T>
    T read(const std::string& what) {
        need(sizeof(T), what);
        T value;
        in_.read(reinterpret_cast<char*>(&value), sizeof(T));
        pos_ += sizeof(T);
        return value;
    }
    void skip(std::uint64_t bytes, const std::string& what) {
        need(bytes, what);
        seek(pos_ + bytes);
    }
    void seek(std::uint64_t to) {
        in_.seekg(std::streamoff(to));
        pos_ = to;
    }
    std::string string(const std::string& what) {
        const std::uint32_t length = read<std::uint32_t>(what);
        need(length, what);
        std::string text(length, '\0');
        in_.read(text.data(), length);
        pos_ += length;
        return text;
    }
    // The transform: its type name (checked above), then a fixed-size map that OpenVDB reads.
    void transform(const std::string& what) {
        const std::uint64_t start = pos_;
        string(what);
        in_.seekg(std::streamoff(start));
        openvdb::math::Transform transform;
        transform.read(in_);
        if (!in_) fail("not a readable OpenVDB file: " + what + " reaches past the end of the file");
        pos_ = std::uint64_t(in_.tellg());
    }
    // A tree of the 5-4-3 kind sdfgen writes (root, internal nodes of 32^3 and 16^3, leaves of
    // 8^3): its topology, then each leaf's values, laid out as RootNode, InternalNode and
    // LeafNode read them (file versions 222-224). Every node read stands for bytes in the file,
    // and every compressed block's size is checked against the bytes left.
    void tree(std::uint32_t compression, const ValueLayout& layout, const std::string& what) {
        skip(4, what); // buffer count
        skip(layout.bytes, what); // background
        const std::uint32_t tiles = read<std::uint32_t>(what);
        const std::uint32_t children = read<std::uint32_t>(what);
        if (std::uint64_t(tiles) * (13 + layout.bytes) + std::uint64_t(children) * 12 > size_ - pos_) fail("not a readable OpenVDB file: " + what + " claims more nodes than the file holds");
        // RootNode keeps one node per origin: a repeated origin would replace a node read before.
        std::set<std::array<std::int32_t, 3>> origins;
        auto origin = [&]() {
            std::array<std::int32_t, 3> xyz;
            for (std::int32_t& v : xyz) v = read<std::int32_t>(what);
            if (!origins.insert(xyz).second) fail("not a readable OpenVDB file: " + what + " has two root nodes at one origin");
        };
        for (std::uint32_t t = 0; t < tiles; ++t) {
            origin();
            skip(layout.bytes + 1, what); // value and active flag
        }
        std::uint64_t leaves = 0;
        for (std::uint32_t c = 0; c < children; ++c) {
            origin();
            const std::uint64_t middle = internalNode(5, compression, layout, what);
            for (std::uint64_t m = 0; m < middle; ++m) leaves += internalNode(4, compression, layout, what);
        }
        for (std::uint64_t l = 0; l < leaves; ++l) values(512, mask(512, what), compression, layout, what);
    }
    // An internal node of 2^(3 log2Dim) entries: child and value masks, its tile values; returns
    // its number of children.
    std::uint64_t internalNode(int log2Dim, std::uint32_t compression, const ValueLayout& layout, const std::string& what) {
        const std::uint64_t entries = std::uint64_t(1) << (3 * log2Dim);
        const std::uint64_t childCount = mask(entries, what);
        const std::uint64_t activeCount = mask(entries, what);
        values(entries, activeCount, compression, layout, what);
        if (log2Dim == 4) {
            for (std::uint64_t c = 0; c < childCount; ++c) skip(64, what); // the leaves' value masks
        }
        return childCount;
    }
    // A bit mask of `bits` bits; returns how many are set.
    std::uint64_t mask(std::uint64_t bits, const std::string& what) {
        need(bits / 8, what);
        std::vector<std::uint64_t> words(bits / 64);
        in_.read(reinterpret_cast<char*>(words.data()), std::streamsize(bits / 8));
        pos_ += bits / 8;
        std::uint64_t count = 0;
        for (const std::uint64_t w : words) count += std::uint64_t(__builtin_popcountll(w));
        return count;
    }
    // io::readCompressedValues: a flag saying what is implied by the mask, one or two inactive
    // values, a selection mask, then the values (all, or only the active ones), raw or as a
    // zip or Blosc block with its byte count before it.
    void values(std::uint64_t count, std::uint64_t active, std::uint32_t compression, const ValueLayout& layout, const std::string& what) {
        const std::int8_t flag = read<std::int8_t>(what);
        if (flag == openvdb::io::NO_MASK_AND_ONE_INACTIVE_VAL || flag == openvdb::io::MASK_AND_ONE_INACTIVE_VAL ||
            flag == openvdb::io::MASK_AND_TWO_INACTIVE_VALS) {
            skip(flag == openvdb::io::MASK_AND_TWO_INACTIVE_VALS ? 2 * layout.bytes : layout.bytes, what);
        }
        if (flag == openvdb::io::MASK_AND_NO_INACTIVE_VALS || flag == openvdb::io::MASK_AND_ONE_INACTIVE_VAL ||
            flag == openvdb::io::MASK_AND_TWO_INACTIVE_VALS) {
            skip(count / 8, what);
        }
        if ((compression & openvdb::io::COMPRESS_ACTIVE_MASK) && flag != openvdb::io::NO_MASK_AND_ALL_VALS) count = active;
        if (layout.half && count == 0) return; // io::HalfReader reads nothing for no values
        const std::uint64_t bytes = count * layout.stored();
        if (compression & (openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ZIP)) {
            const std::int64_t stored = read<std::int64_t>(what);
            if (stored <= 0 && std::uint64_t(-(stored + 1)) + 1 != bytes) { // -stored, without overflow
                fail("not a readable OpenVDB file: " + what + " has a raw block of " + std::to_string(stored) + " bytes for " + std::to_string(bytes));
            }
            skip(stored <= 0 ? bytes : std::uint64_t(stored), what);
        } else {
            skip(bytes, what);
        }
    }


    // A MetaMap: a count, then per entry a name, a type name and the value's size and bytes.
    void metaMap(const std::string& what) {
        const std::int32_t count = read<std::int32_t>(what);
        // Each entry takes at least 12 bytes (three lengths).
        if (count < 0 || std::uint64_t(count) > (size_ - pos_) / 12) {
            fail("not a readable OpenVDB file: " + what + " claims " + std::to_string(count) + " entries, more than its remaining " +
                 std::to_string(size_ - pos_) + " bytes hold");
        }
        for (std::int32_t i = 0; i < count; ++i) {
            string(what);
            const std::uint32_t typeLength = read<std::uint32_t>(what);
            need(typeLength, what);
            std::string type(typeLength, '\0');
            in_.read(type.data(), typeLength);
            pos_ += typeLength;
            const std::uint32_t bytes = read<std::uint32_t>(what);
            need(bytes, what);
            const std::uint64_t end = pos_ + bytes;
            // OpenVDB reads a value of a fixed-size type by its type, not by the size given
            // with it, and the delayed-load table by the counts inside it: a size that
            // disagrees would start the next read in the wrong place.
            if (type == openvdb::io::DelayedLoadMetadata::staticTypeName()) {
                delayedLoadTable(bytes, what);
            } else if (type != openvdb::StringMetadata::staticTypeName() && openvdb::Metadata::isRegisteredType(type) &&
                       bytes != openvdb::Metadata::createMetadata(type)->size()) {
                fail("not a readable OpenVDB file: a " + printable(type) + " value in " + what + " claims " + std::to_string(bytes) + " bytes");
            }
            seek(end);
        }
    }
    // io::DelayedLoadMetadata: a count, a mask of `count` bytes and optionally `count` 8-byte
    // sizes, each stored raw or Blosc-compressed (with a byte count before it).
    void delayedLoadTable(std::uint32_t bytes, const std::string& what) {
        if (bytes == 0) return;
        const std::uint64_t end = pos_ + bytes;
        const std::string problem = "not a readable OpenVDB file: the delayed-load table in " + what + " is malformed";
        if (bytes < 12) fail(problem);
        const std::uint64_t count = read<std::uint32_t>(what);
        for (const std::uint64_t itemBytes : {1, 8}) {
            if (end - pos_ < 4) fail(problem);
            const std::uint32_t stored = read<std::uint32_t>(what);
            if (itemBytes == 8 && stored == std::numeric_limits<std::uint32_t>::max()) break; // no sizes stored
            if (stored == 0) {
                if (count * itemBytes > end - pos_) fail(problem);
                seek(pos_ + count * itemBytes);
                continue;
            }
            // Blosc's 16-byte header: the sizes it will decompress to and read from.
            if (stored < 16 || stored > end - pos_) fail(problem);
            std::uint32_t header[4];
            in_.read(reinterpret_cast<char*>(header), sizeof header);
            // OpenVDB pads what it compresses to at least 128 bytes.
            if (header[1] < count * itemBytes || header[1] > std::max<std::uint64_t>(count * itemBytes, 128) || header[3] > stored) fail(problem);
            seek(pos_ + stored);
        }
        if (pos_ > end) fail(problem);
        // Each entry stands for a leaf buffer in the file, so the file has more bytes than entries.
        if (count > size_) fail(problem);
    }

    std::istream& in_;
    std::uint64_t size_;
    const std::string& path_;
    std::uint64_t pos_ = 0;
    std::uint32_t version_ = 0;
};

// The grid's index-to-world map as voxel size and translation; Error unless it is axis-aligned
// with cubic voxels, which is what a Field can hold.
void linearMap(const openvdb::math::Transform& transform, double& h, openvdb::Vec3d& translation, const std::string& path) {
    if (!transform.isLinear()) throw Error(path + ": the grid's transform is not linear (sdfgen reads axis-aligned grids)");
    const openvdb::Mat4d m = transform.baseMap()->getAffineMap()->getMat4();
    for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 4; ++c) {
            if (!std::isfinite(m(r, c))) throw Error(path + ": the grid's transform is not finite");
        }
    }
    h = m(0, 0);
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
            const double expected = r == c ? h : 0.0;
            if (std::fabs(m(r, c) - expected) > 1e-9 * std::fabs(h)) {
                throw Error(path + ": the grid's transform is rotated or its voxels are not cubes (sdfgen reads axis-aligned grids of cubic voxels)");
            }
        }
    }
    if (!(h > 0) || !std::isfinite(h)) throw Error(path + ": the grid's voxel size is not positive");
    translation = m.getTranslation();
}

// OpenVDB's linear transforms refuse a voxel whose volume is below three times its double tolerance
// (openvdb/math/Maps.h: "Non-zero scale values required").
const double kSmallestVoxelVolume = 3.0 * openvdb::math::Tolerance<double>::value();
bool representableVoxel(double h) { return h * h * h >= kSmallestVoxelVolume; }

// A level-set FloatGrid named "surface" whose index (i, j, k) is at sample (i, j, k) (voxel size
// h, translation origin + h/2). band 0: every sample active; band >= 1: only samples with
// |d| < band * h, the rest inactive +-band * h. Initializes OpenVDB.
openvdb::FloatGrid::Ptr fieldToGrid(const Field& field, double band) {
    openvdb::initialize();
    const Grid& g = field.grid;
    const double h = g.voxel;
    const openvdb::CoordBBox box = indexBox(g);
    openvdb::FloatGrid::Ptr grid;
    if (band == 0) {
        // Every sample active: the background is just beyond the largest distance, so that no
        // sample equals it (copyFromDense makes samples equal to the background inactive).
        float largest = 0.0f;
        for (const float v : field.values) largest = std::max(largest, std::fabs(v));
        grid = openvdb::FloatGrid::create(std::nextafter(largest, std::numeric_limits<float>::infinity()));
        // copyFromDense only reads the dense array; Dense has no const view.
        const DenseField dense(box, const_cast<float*>(field.values.data()));
        openvdb::tools::copyFromDense(dense, *grid, 0.0f);
    } else {
        const float width = float(band * h);
        std::vector<float> clamped(field.values.size());
        std::transform(field.values.begin(), field.values.end(), clamped.begin(),
                       [width](float v) { return std::clamp(v, -width, width); });
        // Samples at +width become inactive background here, those at -width just below, then
        // whole inactive nodes become +-width tiles: the layout of an OpenVDB narrow-band level set.
        grid = openvdb::FloatGrid::create(width);
        const DenseField dense(box, clamped.data());
        openvdb::tools::copyFromDense(dense, *grid, 0.0f);
        for (auto it = grid->beginValueOn(); it; ++it) {
            if (*it <= -width) it.setValueOff();
        }
        openvdb::tools::pruneLevelSet(grid->tree());
    }
    grid->setName(kGridName);
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    openvdb::math::Transform::Ptr transform = openvdb::math::Transform::createLinearTransform(h);
    transform->postTranslate(openvdb::Vec3d(double(g.origin.x) + 0.5 * h, double(g.origin.y) + 0.5 * h, double(g.origin.z) + 0.5 * h));
    grid->setTransform(transform);
    return grid;
}

// A channel as a grid named `name` whose active voxels are the surface grid's (every sample when
// dense, the band's otherwise; the rest hold the background), valued at each voxel (i, j, k) by
// value(grid.index(i, j, k)).
template <class ChannelGrid, class Value>
typename ChannelGrid::Ptr channelGrid(const Field& field, const openvdb::FloatGrid& surface, const char* name,
                                      const typename ChannelGrid::ValueType& background, const Value& value) {
    const typename ChannelGrid::Ptr grid = ChannelGrid::create(background);
    grid->tree().topologyUnion(surface.tree());
    grid->tree().voxelizeActiveTiles();
    openvdb::tree::LeafManager<typename ChannelGrid::TreeType> leaves(grid->tree());
    leaves.foreach([&](typename ChannelGrid::TreeType::LeafNodeType& leaf, std::size_t) {
        for (auto voxel = leaf.beginValueOn(); voxel; ++voxel) {
            const openvdb::Coord c = voxel.getCoord();
            voxel.setValue(value(field.grid.index(c.x(), c.y(), c.z())));
        }
    });
    grid->setName(name);
    grid->setTransform(surface.transform().copy());
    return grid;
}

// The field's channels (sdfgen::Channels) beside the surface grid: "gradient" and "closest" as
// Vec3SGrids, "triangle" as an Int32Grid (background -1: no triangle).
openvdb::GridCPtrVec channelGrids(const Field& field, const openvdb::FloatGrid& surface) {
    openvdb::GridCPtrVec grids;
    const std::size_t n = field.grid.sampleCount();
    for (const auto& [name, planes, type] : {std::tuple{"gradient", &field.gradient, openvdb::VEC_COVARIANT_NORMALIZE},
                                             {"closest", &field.closest, openvdb::VEC_CONTRAVARIANT_ABSOLUTE}}) {
        if (planes->empty()) continue;
        const float* v = planes->data();
        const openvdb::Vec3SGrid::Ptr grid = channelGrid<openvdb::Vec3SGrid>(
            field, surface, name, openvdb::Vec3s(0.0f), [v, n](std::size_t i) { return openvdb::Vec3s(v[i], v[n + i], v[2 * n + i]); });
        grid->setVectorType(type);
        grids.push_back(grid);
    }
    if (!field.triangle.empty()) {
        const std::int32_t* t = field.triangle.data();
        grids.push_back(channelGrid<openvdb::Int32Grid>(field, surface, "triangle", -1, [t](std::size_t i) { return t[i]; }));
    }
    return grids;
}

void saveVdbFile(const Field& field, const std::string& path, const SaveOptions& options) {
    checkField(field, path);
    if (!(options.band == 0 || options.band >= 1) || !std::isfinite(options.band)) {
        throw Error(path + ": band must be 0 (dense) or at least 1 voxel (got " + std::to_string(options.band) + ")");
    }
    const Grid& g = field.grid;
    const double h = g.voxel;
    if (!representableVoxel(h)) {
        throw Error(path + ": voxel size " + std::to_string(h) + " is below what an OpenVDB transform can hold (OpenVDB refuses voxels of volume under " +
                    std::to_string(kSmallestVoxelVolume) + ", sizes under about 1.45e-5)");
    }
    openvdb::FloatGrid::Ptr grid;
    try {
        grid = fieldToGrid(field, options.band);
    } catch (const openvdb::Exception& e) {
        throw Error(path + ": OpenVDB cannot hold this grid (" + e.what() + ")");
    }
    grid->insertMeta("sdfgen_dims", openvdb::Vec3IMetadata(openvdb::Vec3i(g.dims.x, g.dims.y, g.dims.z)));
    grid->insertMeta("sdfgen_origin", openvdb::Vec3DMetadata(openvdb::Vec3d(double(g.origin.x), double(g.origin.y), double(g.origin.z))));
    grid->insertMeta("sdfgen_voxel", openvdb::DoubleMetadata(h));
    grid->insertMeta("sdfgen_band", openvdb::DoubleMetadata(options.band));
    grid->insertMeta("sdfgen_method", openvdb::StringMetadata(methodLine(field)));
    grid->insertMeta("sdfgen_source", openvdb::StringMetadata(field.source));

    openvdb::GridCPtrVec grids{grid};
    for (const openvdb::GridBase::ConstPtr& channel : channelGrids(field, *grid)) grids.push_back(channel);
    writeFileAtomically(path, [&](std::ostream& out) {
        try {
            openvdb::io::Stream stream(out);
            // Blosc pays off on a narrow band's few leaves; a dense grid of distances hardly
            // compresses (about 20%) and saves three times faster without it.
            stream.setCompression(openvdb::io::COMPRESS_ACTIVE_MASK | (options.band > 0 ? openvdb::io::COMPRESS_BLOSC : 0));
            stream.write(grids);
        } catch (const openvdb::Exception& e) {
            throw Error(path + ": " + e.what());
        }
    });
}

// The grid's sdfgen_* metadata, all or none of dims, origin and voxel (a partial or mistyped
// set is not sdfgen's and is refused rather than read past).
struct SdfgenMetadata {
    bool present = false;
    openvdb::Vec3i dims;
    openvdb::Vec3d origin;
    double voxel = 0, band = 0;
    std::string method, source;
    bool hasMethod = false, hasSource = false;
};

SdfgenMetadata sdfgenMetadata(const openvdb::GridBase& grid, const std::string& path) {
    SdfgenMetadata meta;
    int found = 0, required = 0;
    for (auto it = grid.beginMeta(); it != grid.endMeta(); ++it) {
        const std::string& name = it->first;
        if (name.compare(0, 7, "sdfgen_") != 0) continue;
        const openvdb::Metadata& value = *it->second;
        auto wrongType = [&](const char* expected) {
            throw Error(path + ": metadata '" + printable(name) + "' is of type " + printable(value.typeName()) + ", not " + expected);
        };
        if (name == "sdfgen_dims") {
            const auto* v = dynamic_cast<const openvdb::Vec3IMetadata*>(&value);
            if (!v) wrongType("vec3i");
            meta.dims = v->value();
            ++required;
        } else if (name == "sdfgen_origin") {
            const auto* v = dynamic_cast<const openvdb::Vec3DMetadata*>(&value);
            if (!v) wrongType("vec3d");
            meta.origin = v->value();
            ++required;
        } else if (name == "sdfgen_voxel") {
            const auto* v = dynamic_cast<const openvdb::DoubleMetadata*>(&value);
            if (!v) wrongType("double");
            meta.voxel = v->value();
            ++required;
        } else if (name == "sdfgen_band") {
            const auto* v = dynamic_cast<const openvdb::DoubleMetadata*>(&value);
            if (!v) wrongType("double");
            meta.band = v->value();
        } else if (name == "sdfgen_method" || name == "sdfgen_source") {
            const auto* v = dynamic_cast<const openvdb::StringMetadata*>(&value);
            if (!v) wrongType("string");
            (name == "sdfgen_method" ? meta.method : meta.source) = v->value();
            (name == "sdfgen_method" ? meta.hasMethod : meta.hasSource) = true;
        } else {
            throw Error(path + ": unknown sdfgen metadata '" + printable(name) + "'");
        }
        ++found;
    }
    if (required != 0 && required != 3) throw Error(path + ": the grid has only some of sdfgen_dims, sdfgen_origin and sdfgen_voxel");
    if (required == 0 && found != 0) throw Error(path + ": the grid has sdfgen metadata without sdfgen_dims, sdfgen_origin and sdfgen_voxel");
    meta.present = required == 3;
    if (!(meta.band == 0 || meta.band >= 1) || !std::isfinite(meta.band)) {
        throw Error(path + ": sdfgen_band " + std::to_string(meta.band) + " is not 0 (dense) or at least 1");
    }
    return meta;
}

// What the rest of the reading needs from the file, read by OpenVDB.
openvdb::FloatGrid::Ptr readFloatGrid(const std::string& path, std::uint64_t fileBytes) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open file (" + std::strerror(errno) + ")");
    VdbLayout(in, fileBytes, path).check();
    in.seekg(0);
    // OpenVDB does not look at the stream's state while it reads a tree: a read past the end must
    // throw at once, or a truncated file's counts make it allocate node after empty node.
    in.exceptions(std::ios::failbit | std::ios::badbit);
    // Read as a stream, not memory-mapped: a truncated file must fail, not fault, and it must end
    // exactly where the last grid does.
    openvdb::io::Stream stream(in, /*delayLoad=*/false);
    const openvdb::GridPtrVecPtr grids = stream.getGrids();
    if (in.tellg() != std::streampos(fileBytes)) throw Error(path + ": not a readable OpenVDB file (data after the last grid)");
    // The grid named "surface", else the first float grid.
    for (const bool byName : {true, false}) {
        for (const openvdb::GridBase::Ptr& candidate : *grids) {
            if (candidate->isType<openvdb::FloatGrid>() && (!byName || candidate->getName() == kGridName)) {
                return openvdb::gridPtrCast<openvdb::FloatGrid>(candidate);
            }
        }
    }
    throw Error(path + ": the file holds no float grid");
}

Field loadGrid(const openvdb::FloatGrid& grid, const std::string& path) {
    if (grid.getGridClass() == openvdb::GRID_FOG_VOLUME) {
        throw Error(path + ": grid '" + printable(grid.getName()) + "' is a fog volume, not a signed distance field");
    }
    double h = 0;
    openvdb::Vec3d translation;
    linearMap(grid.transform(), h, translation, path);
    // What the writer could not write back (a transform OpenVDB itself refuses to make).
    if (!representableVoxel(h)) throw Error(path + ": the grid's voxel size " + std::to_string(h) + " is below what an OpenVDB transform can hold");
    const SdfgenMetadata meta = sdfgenMetadata(grid, path);

    Field field;
    field.method = "unknown";
    openvdb::CoordBBox box;
    openvdb::CoordBBox active;
    grid.tree().evalActiveVoxelBoundingBox(active);
    if (meta.present) {
        // Written by sdfgen: the exact grid, which must agree with the transform and the tree.
        for (int a = 0; a < 3; ++a) {
            field.grid.dims[a] = meta.dims[a];
            field.grid.origin[a] = meta.origin[a];
            if (!(std::fabs(meta.origin[a] + 0.5 * h - translation[a]) <= 1e-6 * h)) {
                throw Error(path + ": the grid's transform does not match its sdfgen_origin metadata");
            }
        }
        if (!(std::fabs(meta.voxel - h) <= 1e-9 * h)) throw Error(path + ": the grid's voxel size does not match its sdfgen_voxel metadata");
        field.grid.voxel = meta.voxel;
        checkGrid(field.grid, path);
        box = indexBox(field.grid);
        const std::string dimsText = std::to_string(meta.dims[0]) + "x" + std::to_string(meta.dims[1]) + "x" + std::to_string(meta.dims[2]);
        if (!active.empty() && !box.isInside(active)) {
            throw Error(path + ": the grid's active voxels reach outside its sdfgen_dims " + dimsText);
        }
        // A dense grid (band 0) has every sample active, and nothing else.
        if (meta.band == 0 && grid.tree().activeVoxelCount() != box.volume()) {
            throw Error(path + ": sdfgen_dims " + dimsText + " says " + std::to_string(box.volume()) + " samples, the dense grid holds " +
                        std::to_string(grid.tree().activeVoxelCount()));
        }
        const std::uint64_t extent[3] = {std::uint64_t(meta.dims[0]), std::uint64_t(meta.dims[1]), std::uint64_t(meta.dims[2])};
        checkDimsFit(extent, path);
        if (meta.hasMethod) parseMethodLine(meta.method, field, path);
        if (meta.hasSource) field.source = meta.source;
    } else {
        // Another program's grid: the box of its active voxels.
        box = active;
        if (box.empty()) throw Error(path + ": grid '" + printable(grid.getName()) + "' has no active voxels");
        const std::uint64_t extent[3] = {std::uint64_t(box.dim()[0]), std::uint64_t(box.dim()[1]), std::uint64_t(box.dim()[2])};
        checkDimsFit(extent, path);
        for (int a = 0; a < 3; ++a) {
            field.grid.dims[a] = box.dim()[a];
            field.grid.origin[a] = translation[a] + h * (double(box.min()[a]) - 0.5);
        }
        field.grid.voxel = h;
        checkGrid(field.grid, path);
    }
    field.values.resize(field.grid.sampleCount());
    DenseField dense(box, field.values.data());
    openvdb::tools::copyToDense(grid, dense);
    checkField(field, path);
    return field;
}

Field loadVdbFile(const std::string& path) {
    struct stat info;
    if (stat(path.c_str(), &info) != 0) throw Error(path + ": cannot open file (" + std::strerror(errno) + ")");
    if (!S_ISREG(info.st_mode)) throw Error(path + ": not a regular file");
    openvdb::initialize();
    try {
        return loadGrid(*readFloatGrid(path, std::uint64_t(info.st_size)), path);
    } catch (const openvdb::Exception& e) {
        throw Error(path + ": not a readable OpenVDB file (" + printable(e.what(), 200) + ")");
    } catch (const std::bad_alloc&) {
        throw Error(path + ": not a readable OpenVDB file (it declares more data than fits in memory)");
    } catch (const std::ios_base::failure&) {
        throw Error(path + ": not a readable OpenVDB file (truncated or unreadable: its data ends before its grid does)");
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        throw Error(path + ": not a readable OpenVDB file (" + printable(e.what(), 200) + ")");
    }
}

void surfacePolygons(const Field& field, double iso, double adaptivity, std::vector<glm::vec3>& points,
                     std::vector<glm::uvec3>& triangles, std::vector<glm::uvec4>& quads) {
    // A voxel too small for OpenVDB's transforms: the field is meshed 2^exponent times larger
    // (grid, distances and iso value; powers of two scale exactly) and the points scaled back.
    int exponent = 0;
    while (!representableVoxel(std::ldexp(field.grid.voxel, exponent))) exponent += 8;
    openvdb::FloatGrid::Ptr grid;
    if (exponent == 0) {
        grid = fieldToGrid(field, 0.0);
    } else {
        Field scaled = field;
        scaled.grid.voxel = std::ldexp(field.grid.voxel, exponent);
        for (int a = 0; a < 3; ++a) scaled.grid.origin[a] = std::ldexp(field.grid.origin[a], exponent);
        for (float& v : scaled.values) v = std::ldexp(v, exponent);
        grid = fieldToGrid(scaled, 0.0);
        iso = std::ldexp(iso, exponent);
    }
    std::vector<openvdb::Vec3s> vdbPoints;
    std::vector<openvdb::Vec3I> vdbTriangles;
    std::vector<openvdb::Vec4I> vdbQuads;
    openvdb::tools::volumeToMesh(*grid, vdbPoints, vdbTriangles, vdbQuads, iso, adaptivity);
    points.resize(vdbPoints.size());
    for (std::size_t i = 0; i < vdbPoints.size(); ++i) {
        points[i] = {std::ldexp(vdbPoints[i].x(), -exponent), std::ldexp(vdbPoints[i].y(), -exponent), std::ldexp(vdbPoints[i].z(), -exponent)};
    }
    triangles.resize(vdbTriangles.size());
    for (std::size_t i = 0; i < vdbTriangles.size(); ++i) triangles[i] = {vdbTriangles[i][0], vdbTriangles[i][1], vdbTriangles[i][2]};
    quads.resize(vdbQuads.size());
    for (std::size_t i = 0; i < vdbQuads.size(); ++i) quads[i] = {vdbQuads[i][0], vdbQuads[i][1], vdbQuads[i][2], vdbQuads[i][3]};
}

} // namespace

} // namespace sdfgen::formats

extern "C" __attribute__((visibility("default"))) const sdfgen::OpenVdbPlugin* sdfgen_openvdb_plugin() {
    static const sdfgen::OpenVdbPlugin plugin{sdfgen::formats::saveVdbFile, sdfgen::formats::loadVdbFile, sdfgen::formats::surfacePolygons};
    return &plugin;
}
