// OpenVDB: a FloatGrid named "surface" (the name Houdini's VDB from Polygons gives) of class level
// set, with a transform that puts index (i, j, k) at sample (i, j, k): voxel size h, translation
// origin + h/2. Dense by default; with a band of V voxels only samples with |d| < V h stay active
// and the rest are inactive +-V h, as OpenVDB level sets are: a band field (SparseField) is written
// straight from its bricks (each a leaf, the inside boxes -V h tiles) and read back as bricks. The grid's sdfgen_* metadata keep
// the exact grid, method and source. A field's channels (sdfgen::Channels) follow as grids of their
// names with the surface grid's transform and active voxels: "gradient" and "closest" Vec3SGrids,
// "triangle" an Int32Grid. Also the iso-surfaces of `sdfgen surface`.
//
// The library the core opens on first use (core/io/openvdb_plugin.hpp), so that only runs that read
// or write OpenVDB load it.
#include "core/io/atomic_file.hpp"
#include "core/io/formats/format.hpp"
#include "core/io/openvdb_plugin.hpp"
#include "core/mesh/input_file.hpp"
#include "core/runtime/memory.hpp"
#include "core/runtime/parallel.hpp"
#include "sdfgen/error.hpp"

#include <glm/common.hpp>
#include <openvdb/io/DelayedLoadMetadata.h>
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <openvdb/tree/LeafManager.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <set>
#include <sstream>
#include <cmath>
#include <istream>
#include <streambuf>
#include <limits>
#include <memory>
#include <mutex>
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
            // io::readData decompresses with Blosc when both flags are set. zlib's uncompress is
            // bounded by the block's byte count and the values' size, so a zip block needs no more.
            if (stored > 0 && (compression & openvdb::io::COMPRESS_BLOSC)) bloscBlock(std::uint64_t(stored), bytes, what);
            else skip(stored <= 0 ? bytes : std::uint64_t(stored), what);
        } else {
            skip(bytes, what);
        }
    }

    // A Blosc block of `stored` bytes that OpenVDB decompresses into `bytes`: libblosc reads as
    // many bytes as its 16-byte header claims (cbytes), whatever OpenVDB read from the file, so
    // the header must claim the block's own size (blosc_cbuffer_validate's rule, checked here
    // without linking libblosc; libblosc checks the rest of the block against that size) and the
    // values' size, as OpenVDB's writer makes them.
    void bloscBlock(std::uint64_t stored, std::uint64_t bytes, const std::string& what) {
        need(stored, what);
        std::uint32_t header[4] = {}; // 4 version bytes, then nbytes, blocksize, cbytes (little endian)
        if (stored >= sizeof header) in_.read(reinterpret_cast<char*>(header), sizeof header);
        if (stored < sizeof header || header[3] != stored || header[1] != bytes) {
            fail("not a readable OpenVDB file: " + what + " has a corrupt Blosc block (" + std::to_string(stored) + " bytes for " +
                 std::to_string(bytes) + ", its header claims " + std::to_string(header[3]) + " for " + std::to_string(header[1]) + ")");
        }
        seek(pos_ + stored);
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
            string(what); // the name
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

// OpenVDB 10's RootNode::readTopology news each root child and reads its subtree before the tree
// owns it, so a read that throws there (a corrupt compressed block the layout walk cannot judge
// without decompressing it) leaks the child's whole subtree, 270 KB and up per bad file: a process
// that reads many bad files grows without bound. Nor could the tree simply own it: a node whose
// read threw has a child mask naming children it never made. So the grid types sdfgen reads are
// registered with OwningReadGrid, whose topology read is OpenVDB's (file versions 222 and later,
// the only ones VdbLayout lets through) but gives each node to its parent before reading it and,
// when a read throws, drops from each node's child mask the children it had not made yet: the
// same tree from a valid file, and everything freed after an invalid one.

// An InternalNode's protected masks and table (a derived class may name them).
template <class Node>
struct InternalNodeParts : Node {
    static typename Node::NodeMaskType& childMask(Node& node) { return node.*(&InternalNodeParts::mChildMask); }
    static typename Node::NodeMaskType& valueMask(Node& node) { return node.*(&InternalNodeParts::mValueMask); }
    static typename Node::UnionType* table(Node& node) { return node.*(&InternalNodeParts::mNodes); }
};

template <class Node>
void readInternalTopology(Node& node, std::istream& is, bool fromHalf, const typename Node::ValueType& background) {
    using Parts = InternalNodeParts<Node>;
    using Child = typename Node::ChildNodeType;
    typename Node::NodeMaskType& children = Parts::childMask(node);
    typename Node::UnionType* table = Parts::table(node);
    try {
        children.load(is);
        Parts::valueMask(node).load(is);
        std::unique_ptr<typename Node::ValueType[]> values(new typename Node::ValueType[Node::NUM_VALUES]);
        openvdb::io::readCompressedValues(is, values.get(), Node::NUM_VALUES, Parts::valueMask(node), fromHalf);
        for (auto value = node.beginValueAll(); value; ++value) table[value.pos()].setValue(values[value.pos()]);
    } catch (...) {
        children.setOff(); // none made yet
        throw;
    }
    for (auto on = children.beginOn(); on; ++on) {
        const openvdb::Index i = on.pos();
        auto* child = new Child(openvdb::PartialCreate(), node.offsetToGlobalCoord(i), background);
        table[i].setChild(child);
        try {
            if constexpr (Child::LEVEL > 0) readInternalTopology(*child, is, fromHalf, background);
            else child->readTopology(is, fromHalf);
        } catch (...) {
            for (openvdb::Index later = i + 1; later < Node::NUM_VALUES; ++later) children.setOff(later); // not made
            throw;
        }
    }
}

template <class GridT>
class OwningReadGrid final : public GridT {
public:
    static openvdb::GridBase::Ptr factory() { return std::make_shared<OwningReadGrid>(); }
    // In place of GridT in OpenVDB's registry (GridBase's registration is for its subclasses).
    static void registerInPlaceOfBase() {
        openvdb::GridBase::unregisterGrid(GridT::gridType());
        openvdb::GridBase::registerGrid(GridT::gridType(), factory);
    }
    // Tree::readTopology, then RootNode::readTopology.
    void readTopology(std::istream& is) override {
        using Tree = typename GridT::TreeType;
        using Root = typename Tree::RootNodeType;
        using Value = typename Root::ValueType;
        std::int32_t bufferCount = 0; // always 1 since file version 220 (read and ignored, as TreeBase does)
        is.read(reinterpret_cast<char*>(&bufferCount), sizeof bufferCount);
        Value background;
        is.read(reinterpret_cast<char*>(&background), sizeof(Value));
        const typename Tree::Ptr tree = std::make_shared<Tree>(background);
        this->setTree(tree);
        Root& root = tree->root();
        openvdb::io::setGridBackgroundValuePtr(is, &root.background());
        openvdb::Index tiles = 0, children = 0;
        is.read(reinterpret_cast<char*>(&tiles), sizeof tiles);
        is.read(reinterpret_cast<char*>(&children), sizeof children);
        std::int32_t xyz[3];
        for (openvdb::Index n = 0; n < tiles; ++n) {
            Value value;
            char active = 0;
            is.read(reinterpret_cast<char*>(xyz), sizeof xyz);
            is.read(reinterpret_cast<char*>(&value), sizeof(Value));
            is.read(&active, 1);
            root.addTile(openvdb::Coord(xyz), value, active != 0);
        }
        for (openvdb::Index n = 0; n < children; ++n) {
            is.read(reinterpret_cast<char*>(xyz), sizeof xyz);
            auto* child = new typename Root::ChildNodeType(openvdb::PartialCreate(), openvdb::Coord(xyz), root.background());
            root.addChild(child); // the tree owns it (and frees one it replaces)
            readInternalTopology(*child, is, this->saveFloatAsHalf(), root.background());
        }
    }
};

// openvdb::initialize(), with the grid types sdfgen reads (the surface and the channels) made as
// OwningReadGrids. Once per process: the registry is OpenVDB's, shared with any other user of the
// library in the process (a pyopenvdb beside the Python module gets the same grids from it).
void initializeOpenVdb() {
    static std::once_flag once;
    std::call_once(once, [] {
        openvdb::initialize();
        OwningReadGrid<openvdb::FloatGrid>::registerInPlaceOfBase();
        OwningReadGrid<openvdb::Vec3SGrid>::registerInPlaceOfBase();
        OwningReadGrid<openvdb::Int32Grid>::registerInPlaceOfBase();
    });
}

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

// Names `grid` "surface", of class level set, and gives it the transform that puts index (i, j, k)
// at sample (i, j, k) of `g`.
void nameLevelSet(openvdb::FloatGrid& grid, const Grid& g) {
    const double h = g.voxel;
    grid.setName(kGridName);
    grid.setGridClass(openvdb::GRID_LEVEL_SET);
    openvdb::math::Transform::Ptr transform = openvdb::math::Transform::createLinearTransform(h);
    transform->postTranslate(openvdb::Vec3d(double(g.origin.x) + 0.5 * h, double(g.origin.y) + 0.5 * h, double(g.origin.z) + 0.5 * h));
    grid.setTransform(transform);
}

// A FloatGrid whose leaf buffers are written in parallel: OpenVDB's own LeafNode::writeBuffers,
// run a chunk of leaves at a time on every thread into memory (a stream with the file stream's
// settings: compression, background), then written in the tree's leaf order, as
// Tree::writeBuffers writes them one by one on one thread: the same bytes. The surface grids of
// dense and band fields alike are made as these.
class ParallelBuffersGrid final : public openvdb::FloatGrid {
public:
    using openvdb::FloatGrid::Grid;
    void writeBuffers(std::ostream& os) const override {
        if (hasMultiPassIO()) return openvdb::FloatGrid::writeBuffers(os);
        using Leaf = openvdb::FloatTree::LeafNodeType;
        std::vector<const Leaf*> leaves;
        leaves.reserve(tree().leafCount());
        tree().getNodes(leaves); // depth first, children in order: the order of Tree::writeBuffers
        constexpr std::size_t kChunk = 512, kBatch = 32; // leaves per chunk (1 MB); chunks held at once
        const bool half = saveFloatAsHalf();
        std::vector<std::string> chunks(kBatch);
        for (std::size_t first = 0; first < leaves.size(); first += kChunk * kBatch) {
            const std::size_t count = std::min(kBatch, (leaves.size() - first + kChunk - 1) / kChunk);
            tbb::parallel_for(std::size_t(0), count, [&](std::size_t c) {
                std::ostringstream chunk;
                chunk.copyfmt(os); // OpenVDB's settings live in the stream's iword/pword slots
                const std::size_t begin = first + c * kChunk, end = std::min(leaves.size(), begin + kChunk);
                for (std::size_t n = begin; n < end; ++n) leaves[n]->writeBuffers(chunk, half);
                chunks[c] = std::move(chunk).str();
            });
            for (std::size_t c = 0; c < count; ++c) {
                os.write(chunks[c].data(), std::streamsize(chunks[c].size()));
                chunks[c] = std::string();
            }
        }
    }
};

// A level-set FloatGrid named "surface" whose index (i, j, k) is at sample (i, j, k) (voxel size
// h, translation origin + h/2), every sample an active voxel. Initializes OpenVDB.
openvdb::FloatGrid::Ptr fieldToGrid(const Field& field) {
    initializeOpenVdb();
    // The background is just beyond the largest distance, so that no sample equals it
    // (copyFromDense makes samples equal to the background inactive).
    float largest = 0.0f;
    for (const float v : field.values) largest = std::max(largest, std::fabs(v));
    const openvdb::FloatGrid::Ptr grid = std::make_shared<ParallelBuffersGrid>(std::nextafter(largest, std::numeric_limits<float>::infinity()));
    // copyFromDense only reads the dense array; Dense has no const view.
    const DenseField dense(indexBox(field.grid), const_cast<float*>(field.values.data()));
    openvdb::tools::copyFromDense(dense, *grid, 0.0f);
    nameLevelSet(*grid, field.grid);
    return grid;
}

// A band field as a level-set FloatGrid named "surface" (the transform of fieldToGrid): each
// brick a leaf, its samples in the band active; each inside box inactive -background tiles; the
// rest the +background of the tree. Distances and grid scaled by 2^exponent. Initializes OpenVDB.
// `storage` is the field's, or was taken out of it (SparseField::release) when its owner gave it
// up: then `givenUp` is &storage, the memory of its values goes back to the system as they become
// leaves, and it is emptied.
openvdb::FloatGrid::Ptr sparseToGrid(const SparseField& field, const SparseField::Storage& storage, int exponent,
                                     SparseField::Storage* givenUp = nullptr) {
    constexpr int B = SparseField::kBrick;
    initializeOpenVdb();
    const float background = std::ldexp(field.background(), exponent);
    const openvdb::FloatGrid::Ptr grid = std::make_shared<ParallelBuffersGrid>(background);
    openvdb::FloatTree& tree = grid->tree();
    const glm::ivec3 dims = field.grid().dims;
    // Whole bricks (a box cut at the grid's end reaches on to its brick's end), so that fill makes
    // tiles and no leaves; prune then merges the tiles of nodes wholly inside.
    auto brickEnd = [](int v) { return (v + B - 1) / B * B - 1; };
    for (const auto& box : storage.insideBoxes) {
        tree.fill(openvdb::CoordBBox(openvdb::Coord(box[0], box[1], box[2]), openvdb::Coord(brickEnd(box[3]), brickEnd(box[4]), brickEnd(box[5]))),
                  -background, /*active=*/false);
    }
    openvdb::tools::prune(tree);
    // The leaves are made in parallel (a brick's samples run x fastest, a leaf's z fastest) and
    // then linked into the tree in order, a chunk at a time; the bricks are never in an inside
    // box's tiles.
    using Leaf = openvdb::FloatTree::LeafNodeType;
    auto makeLeaf = [&](std::size_t b) {
        const glm::ivec3 lo = storage.bricks[b] * B;
        const glm::ivec3 inGrid = glm::min(dims - lo, glm::ivec3(B)); // samples of the brick within the grid, per axis
        auto leaf = std::make_unique<Leaf>(openvdb::PartialCreate(), openvdb::Coord(lo.x, lo.y, lo.z), background);
        leaf->allocate(); // not filled: every value is written below
        float* out = leaf->buffer().data();
        openvdb::util::NodeMask<3> active;
        const float* values = &storage.values[b * SparseField::kBrickSamples];
        // A leaf's offset is 64 x + 8 y + z: word x of its mask holds bit 8 y + z.
        static_assert(B == 8 && Leaf::DIM == 8, "a brick is a leaf");
        for (int x = 0; x < B; ++x) {
            std::uint64_t word = 0;
            for (int y = 0; y < B; ++y)
                for (int z = 0; z < B; ++z) {
                    const float v = exponent == 0 ? values[(z * B + y) * B + x] : std::ldexp(values[(z * B + y) * B + x], exponent);
                    out[(x * B + y) * B + z] = v;
                    word |= std::uint64_t(std::fabs(v) < background && x < inGrid.x && y < inGrid.y && z < inGrid.z) << (y * B + z);
                }
            active.getWord<std::uint64_t>(openvdb::Index(x)) = word;
        }
        leaf->setValueMask(active);
        return leaf;
    };
    constexpr std::size_t kChunk = 1 << 12; // bricks (8 MB of values)
    std::vector<std::unique_ptr<Leaf>> leaves(std::min(kChunk, storage.bricks.size()));
    openvdb::tree::ValueAccessor<openvdb::FloatTree> access(tree); // caches the path to the last leaf: bricks come in order
    for (std::size_t first = 0; first < storage.bricks.size(); first += kChunk) {
        const std::size_t last = std::min(storage.bricks.size(), first + kChunk);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(first, last, 256), [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t b = range.begin(); b != range.end(); ++b) leaves[b - first] = makeLeaf(b);
        });
        for (std::size_t b = first; b < last; ++b) access.addLeaf(leaves[b - first].release()); // the tree owns it
        if (givenUp) {
            releasePages(&givenUp->values[first * SparseField::kBrickSamples], (last - first) * SparseField::kBrickSamples * sizeof(float));
        }
    }
    if (givenUp) *givenUp = {};
    Grid scaled = field.grid();
    scaled.voxel = std::ldexp(scaled.voxel, exponent);
    for (int a = 0; a < 3; ++a) scaled.origin[a] = std::ldexp(scaled.origin[a], exponent);
    nameLevelSet(*grid, scaled);
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

// The field's channels beside the surface grid, each a grid of its name: a 3-wide channel as a
// Vec3SGrid of its vector type, a 1-wide one as an Int32Grid or FloatGrid; background: its `none`.
openvdb::GridCPtrVec channelGrids(const Field& field, const openvdb::FloatGrid& surface) {
    openvdb::GridCPtrVec grids;
    const std::size_t n = field.grid.sampleCount();
    for (const ChannelValues& channel : field.channels) {
        const ChannelInfo& info = channel.info();
        const float* v = channel.floats.data();
        if (info.width == 3 && info.type == ChannelType::Float32) {
            const openvdb::Vec3SGrid::Ptr grid = channelGrid<openvdb::Vec3SGrid>(
                field, surface, info.name, openvdb::Vec3s(float(info.none)), [v, n](std::size_t i) { return openvdb::Vec3s(v[i], v[n + i], v[2 * n + i]); });
            grid->setVectorType(info.vector == ChannelVector::Direction  ? openvdb::VEC_COVARIANT_NORMALIZE
                                : info.vector == ChannelVector::Position ? openvdb::VEC_CONTRAVARIANT_ABSOLUTE
                                                                         : openvdb::VEC_INVARIANT);
            grids.push_back(grid);
        } else if (info.width == 1 && info.type == ChannelType::Int32) {
            const std::int32_t* t = channel.ints.data();
            grids.push_back(channelGrid<openvdb::Int32Grid>(field, surface, info.name, std::int32_t(info.none), [t](std::size_t i) { return t[i]; }));
        } else if (info.width == 1) {
            grids.push_back(channelGrid<openvdb::FloatGrid>(field, surface, info.name, float(info.none), [v](std::size_t i) { return v[i]; }));
        } else {
            throw Error(std::string("the ") + info.name + " channel's width and type have no OpenVDB grid here");
        }
    }
    return grids;
}

// The sdfgen_* metadata that give the exact grid back (a transform's double arithmetic may not),
// the band (in voxels, 0: dense) and the names.
void insertSdfgenMetadata(openvdb::FloatGrid& grid, const Grid& g, double band, const std::string& method, const std::string& source) {
    grid.insertMeta("sdfgen_dims", openvdb::Vec3IMetadata(openvdb::Vec3i(g.dims.x, g.dims.y, g.dims.z)));
    grid.insertMeta("sdfgen_origin", openvdb::Vec3DMetadata(openvdb::Vec3d(double(g.origin.x), double(g.origin.y), double(g.origin.z))));
    grid.insertMeta("sdfgen_voxel", openvdb::DoubleMetadata(g.voxel));
    grid.insertMeta("sdfgen_band", openvdb::DoubleMetadata(band));
    grid.insertMeta("sdfgen_method", openvdb::StringMetadata(method));
    grid.insertMeta("sdfgen_source", openvdb::StringMetadata(source));
}

// Without Blosc: distances hardly compress (6% on a band, 20% dense) and the write takes twice as long.
void writeGrids(const openvdb::GridCPtrVec& grids, const std::string& path) {
    writeFileAtomically(path, [&](std::ostream& out) {
        try {
            openvdb::io::Stream stream(out);
            stream.setCompression(openvdb::io::COMPRESS_ACTIVE_MASK);
            stream.write(grids);
        } catch (const openvdb::Exception& e) {
            throw Error(path + ": " + e.what());
        }
    });
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
        // A band: the level set of the field's band (sparseToGrid), as a band bake writes it.
        if (options.band > 0) {
            const SparseField band = sparseFromDense(field, float(options.band * h), path);
            grid = sparseToGrid(band, band.storage(), 0);
        } else {
            grid = fieldToGrid(field);
        }
    } catch (const openvdb::Exception& e) {
        throw Error(path + ": OpenVDB cannot hold this grid (" + e.what() + ")");
    }
    insertSdfgenMetadata(*grid, g, options.band, methodLine(field), field.source);
    openvdb::GridCPtrVec grids{grid};
    for (const openvdb::GridBase::ConstPtr& channel : channelGrids(field, *grid)) grids.push_back(channel);
    writeGrids(grids, path);
}

// `storage` and `givenUp` as sparseToGrid's.
void writeSparseVdbFile(const SparseField& field, const SparseField::Storage& storage, const std::string& path, SparseField::Storage* givenUp) {
    checkSparseField(field, path);
    const Grid& g = field.grid();
    if (!representableVoxel(g.voxel)) {
        throw Error(path + ": voxel size " + std::to_string(g.voxel) + " is below what an OpenVDB transform can hold (OpenVDB refuses voxels of volume under " +
                    std::to_string(kSmallestVoxelVolume) + ", sizes under about 1.45e-5)");
    }
    openvdb::FloatGrid::Ptr grid;
    try {
        grid = sparseToGrid(field, storage, 0, givenUp);
    } catch (const openvdb::Exception& e) {
        throw Error(path + ": OpenVDB cannot hold this grid (" + e.what() + ")");
    }
    insertSdfgenMetadata(*grid, g, double(field.background()) / g.voxel, methodLine(field), field.source);
    writeGrids({grid}, path);
}

void saveSparseVdbFile(const SparseField& field, const std::string& path) { writeSparseVdbFile(field, field.storage(), path, nullptr); }

void saveSparseVdbFileGivenUp(SparseField&& field, const std::string& path) {
    SparseField mine = std::move(field);
    SparseField::Storage storage = mine.release(); // mine keeps the grid, background and names
    writeSparseVdbFile(mine, storage, path, &storage);
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
    if (!(meta.band >= 0) || !std::isfinite(meta.band)) {
        throw Error(path + ": sdfgen_band " + std::to_string(meta.band) + " is not 0 (dense) or a band's width in voxels");
    }
    return meta;
}

// The file as OpenVDB reads it, a block at a time through a ReadWatch: OpenVDB's stream reader
// reports no progress of its own, and a Cancelled thrown here reaches the caller through the
// stream (which rethrows it, badbit being in its exceptions).
class WatchedFileBuffer : public std::streambuf {
public:
    WatchedFileBuffer(std::streambuf& file, ReadWatch& watch) : file_(file), watch_(watch), block_(std::size_t(1) << 20) {}

protected:
    int_type underflow() override {
        blockStart_ += egptr() - eback();
        const std::streamsize n = file_.sgetn(block_.data(), std::streamsize(block_.size()));
        setg(block_.data(), block_.data(), block_.data() + std::max<std::streamsize>(n, 0));
        if (n <= 0) return traits_type::eof();
        watch_.advance(std::uint64_t(n));
        return traits_type::to_int_type(*gptr());
    }
    pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode which) override {
        const off_type here = blockStart_ + (gptr() - eback());
        if (dir == std::ios_base::cur && off == 0) return pos_type(here); // tellg: the block stays
        if (dir == std::ios_base::cur) return seekpos(pos_type(here + off), which);
        return moved(file_.pubseekoff(off, dir, std::ios_base::in));
    }
    pos_type seekpos(pos_type pos, std::ios_base::openmode) override { return moved(file_.pubseekpos(pos, std::ios_base::in)); }

private:
    pos_type moved(pos_type pos) {
        if (pos != pos_type(off_type(-1))) {
            blockStart_ = off_type(pos);
            setg(block_.data(), block_.data(), block_.data());
        }
        return pos;
    }
    std::streambuf& file_;
    ReadWatch& watch_;
    std::vector<char> block_;
    off_type blockStart_ = 0; // the file offset of the block's first byte
};

// The file's bytes as a stream that OpenVDB and the layout walk can seek in.
class BytesBuffer : public std::streambuf {
public:
    explicit BytesBuffer(const std::string& bytes) {
        char* start = const_cast<char*>(bytes.data()); // only ever read
        setg(start, start, start + bytes.size());
    }

protected:
    pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode which) override {
        const off_type base = dir == std::ios_base::beg ? 0 : dir == std::ios_base::cur ? gptr() - eback() : egptr() - eback();
        return seekpos(pos_type(base + off), which);
    }
    pos_type seekpos(pos_type pos, std::ios_base::openmode) override {
        const off_type at = off_type(pos);
        if (at < 0 || at > egptr() - eback()) return pos_type(off_type(-1));
        setg(eback(), eback() + at, egptr());
        return pos;
    }
};

// What the rest of the reading needs from the file's bytes (read once), read by OpenVDB; `control`
// as loadField's.
openvdb::FloatGrid::Ptr readFloatGrid(const std::string& path, const std::string& bytes, const RunControl& control) {
    const std::uint64_t fileBytes = bytes.size();
    BytesBuffer buffer(bytes);
    std::istream in(&buffer);
    VdbLayout(in, fileBytes, path).check();
    in.seekg(0);
    ReadWatch watch(control, fileBytes);
    WatchedFileBuffer watched(buffer, watch);
    std::istream watchedIn(&watched);
    // OpenVDB does not look at the stream's state while it reads a tree: a read past the end must
    // throw at once, or a truncated file's counts make it allocate node after empty node.
    watchedIn.exceptions(std::ios::failbit | std::ios::badbit);
    // Read as a stream, not memory-mapped: a truncated file must fail, not fault, and it must end
    // exactly where the last grid does. The bytes checked are the bytes read: a file rewritten in
    // place meanwhile is not read again.
    openvdb::io::Stream stream(watchedIn, /*delayLoad=*/false);
    const openvdb::GridPtrVecPtr grids = stream.getGrids();
    if (watchedIn.tellg() != std::streampos(fileBytes)) throw Error(path + ": not a readable OpenVDB file (data after the last grid)");
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

// The grid a FloatGrid stands for, into field.grid, with its names, and its box in index space:
// for a grid sdfgen wrote, the grid of its metadata, which must agree with the transform and the
// tree; for another program's, the box of its active voxels, its low corner moved down onto the
// leaves' 8-voxel grid (so that each leaf is one brick when read sparse). Returns the metadata.
SdfgenMetadata readFrame(const openvdb::FloatGrid& grid, Field& field, openvdb::CoordBBox& box, const std::string& path) {
    if (grid.getGridClass() == openvdb::GRID_FOG_VOLUME) {
        throw Error(path + ": grid '" + printable(grid.getName()) + "' is a fog volume, not a signed distance field");
    }
    double h = 0;
    openvdb::Vec3d translation;
    linearMap(grid.transform(), h, translation, path);
    // What the writer could not write back (a transform OpenVDB itself refuses to make).
    if (!representableVoxel(h)) throw Error(path + ": the grid's voxel size " + std::to_string(h) + " is below what an OpenVDB transform can hold");
    const SdfgenMetadata meta = sdfgenMetadata(grid, path);

    field.method = "unknown";
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
        if (meta.hasMethod) parseMethodLine(meta.method, field, path);
        if (meta.hasSource) field.source = meta.source;
    } else {
        // Another program's grid: the box of its active voxels, from the leaf below.
        if (active.empty()) throw Error(path + ": grid '" + printable(grid.getName()) + "' has no active voxels");
        openvdb::Coord low = active.min();
        for (int a = 0; a < 3; ++a) low[a] &= ~(SparseField::kBrick - 1); // down, negative ones too
        box = openvdb::CoordBBox(low, active.max());
        for (int a = 0; a < 3; ++a) {
            field.grid.dims[a] = box.dim()[a];
            field.grid.origin[a] = translation[a] + h * (double(box.min()[a]) - 0.5);
        }
        field.grid.voxel = h;
        checkGrid(field.grid, path);
    }
    return meta;
}

// Throws Error naming `path` when `bytes` more do not fit in the memory available now.
void checkBytesFit(double bytes, const std::string& what, const std::string& path) {
    const std::uint64_t memory = availableMemoryBytes();
    if (memory > 0 && bytes > double(memory)) {
        throw Error(path + ": " + what + " need " + mebibytes(bytes) + ", more than the " + mebibytes(double(memory)) + " of memory available");
    }
}

// A level set (sdfgen's band field, or another program's) as a band field: each leaf a brick, the
// inactive negative tiles the inside boxes (runs of whole bricks per row of bricks). `first` is
// the index of sample (0, 0, 0), on the leaves' 8-voxel grid.
SparseField gridToSparse(const openvdb::FloatGrid& grid, Field&& frame, const openvdb::Coord& first, const std::string& path,
                         const RunControl& control) {
    constexpr int B = SparseField::kBrick;
    FieldHeader header = std::move(frame);
    header.background = grid.background();
    if (!(header.background > 0.0f) || !std::isfinite(header.background)) {
        throw Error(path + ": the level set's background " + std::to_string(header.background) + " is not a positive number");
    }
    const float background = header.background;
    const glm::ivec3 dims = header.grid.dims;
    SparseField::Storage storage;
    const openvdb::FloatTree& tree = grid.tree();

    // The leaves that hold samples of the grid, in z, y, x order.
    std::vector<const openvdb::FloatTree::LeafNodeType*> leaves;
    for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf) {
        const openvdb::Coord o = leaf->origin() - first;
        if (o.x() >= 0 && o.y() >= 0 && o.z() >= 0 && o.x() < dims.x && o.y() < dims.y && o.z() < dims.z) leaves.push_back(leaf.getLeaf());
    }
    checkBytesFit(double(leaves.size()) * SparseField::kBrickSamples * sizeof(float), std::to_string(leaves.size()) + " bricks", path);
    std::sort(leaves.begin(), leaves.end(), [](const auto* a, const auto* b) { // the same order as in the field
        const openvdb::Coord &p = a->origin(), &q = b->origin();
        return std::make_tuple(p.z(), p.y(), p.x()) < std::make_tuple(q.z(), q.y(), q.x());
    });
    storage.bricks.reserve(leaves.size());
    storage.values.resize(leaves.size() * SparseField::kBrickSamples);
    for (std::size_t b = 0; b < leaves.size(); ++b) {
        if (b % 4096 == 0) throwIfCancelled(control);
        const openvdb::Coord o = leaves[b]->origin() - first;
        storage.bricks.emplace_back(o.x() / B, o.y() / B, o.z() / B);
        float* values = &storage.values[b * SparseField::kBrickSamples];
        for (int z = 0; z < B; ++z)
            for (int y = 0; y < B; ++y)
                for (int x = 0; x < B; ++x) {
                    float v = background; // samples past the grid's end
                    if (o.x() + x < dims.x && o.y() + y < dims.y && o.z() + z < dims.z) {
                        v = leaves[b]->getValue(openvdb::FloatTree::LeafNodeType::coordToOffset(openvdb::Coord(x, y, z)));
                        if (!std::isfinite(v)) throw Error(path + ": the level set holds a value that is not finite");
                        v = std::clamp(v, -background, background);
                    }
                    values[(z * B + y) * B + x] = v;
                }
    }

    // The tiles: inside where negative, as runs of bricks along x in each row of bricks they cover.
    struct Run {
        int z, y, x0, x1; // in bricks
    };
    auto tiles = [&](const auto& visit) {
        auto tile = tree.cbeginValueAll();
        tile.setMaxDepth(tile.getLeafDepth() - 1);
        for (; tile; ++tile) {
            if (tile.isValueOn()) throw Error(path + ": the level set has active tiles (sdfgen reads level sets whose band lies in leaf voxels)");
            if (!(*tile < 0.0f)) continue;
            openvdb::CoordBBox box;
            tile.getBoundingBox(box);
            box.translate(-first);
            const openvdb::Coord lo = openvdb::Coord::maxComponent(box.min(), openvdb::Coord(0));
            const openvdb::Coord hi = openvdb::Coord::minComponent(box.max() + openvdb::Coord(1), openvdb::Coord(dims.x, dims.y, dims.z));
            if (lo.x() >= hi.x() || lo.y() >= hi.y() || lo.z() >= hi.z()) continue;
            // In bricks: tiles start on multiples of 8, and the grid's last brick may be cut.
            visit(openvdb::Coord(lo.x() / B, lo.y() / B, lo.z() / B),
                  openvdb::Coord((hi.x() + B - 1) / B, (hi.y() + B - 1) / B, (hi.z() + B - 1) / B));
        }
    };
    double rows = 0;
    tiles([&](const openvdb::Coord& lo, const openvdb::Coord& hi) { rows += double(hi.y() - lo.y()) * double(hi.z() - lo.z()); });
    checkBytesFit(rows * (sizeof(Run) + sizeof(storage.insideBoxes[0])), "the inside region's " + std::to_string(std::llround(rows)) + " rows of bricks", path);
    std::vector<Run> runs;
    runs.reserve(std::size_t(rows));
    tiles([&](const openvdb::Coord& lo, const openvdb::Coord& hi) {
        for (int z = lo.z(); z < hi.z(); ++z)
            for (int y = lo.y(); y < hi.y(); ++y) runs.push_back({z, y, lo.x(), hi.x()});
    });
    std::sort(runs.begin(), runs.end(), [](const Run& a, const Run& b) { return std::tie(a.z, a.y, a.x0) < std::tie(b.z, b.y, b.x0); });
    for (std::size_t n = 0; n < runs.size();) {
        Run run = runs[n++];
        while (n < runs.size() && runs[n].z == run.z && runs[n].y == run.y && runs[n].x0 == run.x1) run.x1 = runs[n++].x1;
        storage.insideBoxes.push_back(SparseField::insideBox(dims, run.x0, run.x1, run.y, run.z));
    }
    SparseField field(header, std::move(storage), path);
    checkSparseField(field, path);
    return field;
}

// Whether another program's grid of no class (or of class "unknown") is a level set in all but
// name: a positive background, no active tiles, every leaf value within +-background (so reading
// it as a band clamps nothing), and active voxels that do not fill their box (a band around a
// surface, not a dense grid). Such a grid read dense over the box of its active voxels could take
// gigabytes for a file of kilobytes, as a level set could.
bool levelSetButForItsClass(const openvdb::FloatGrid& grid) {
    const float background = grid.background();
    if (!(background > 0.0f) || !std::isfinite(background) || grid.tree().hasActiveTiles()) return false;
    for (auto leaf = grid.tree().cbeginLeaf(); leaf; ++leaf) {
        for (auto value = leaf->cbeginValueAll(); value; ++value) {
            if (!(std::fabs(*value) <= background)) return false;
        }
    }
    const openvdb::CoordBBox active = grid.evalActiveVoxelBoundingBox();
    return !active.empty() && grid.tree().activeVoxelCount() < active.volume();
}

// A band field's grid (sdfgen's), or another program's level set, named so or not: read as bricks
// and inside boxes.
bool readsAsBand(const openvdb::FloatGrid& grid, const SdfgenMetadata& meta) {
    if (meta.present) return meta.band > 0;
    return grid.getGridClass() == openvdb::GRID_LEVEL_SET || (grid.getGridClass() == openvdb::GRID_UNKNOWN && levelSetButForItsClass(grid));
}

// The grid as a band field (a level set, sdfgen's or another program's, named so or not: never
// made dense over the box of its active voxels, which two small spheres far apart make huge), or
// as a dense one (a dense grid, or another program's grid of no class that is not a level set).
AnyField loadGrid(const openvdb::FloatGrid& grid, const std::string& path, const RunControl& control) {
    Field field;
    openvdb::CoordBBox box;
    const SdfgenMetadata meta = readFrame(grid, field, box, path);
    if (readsAsBand(grid, meta)) return gridToSparse(grid, std::move(field), box.min(), path, control);
    const std::uint64_t extent[3] = {std::uint64_t(field.grid.dims.x), std::uint64_t(field.grid.dims.y), std::uint64_t(field.grid.dims.z)};
    checkDimsFit(extent, path);
    field.values.resize(field.grid.sampleCount());
    DenseField dense(box, field.values.data());
    openvdb::tools::copyToDense(grid, dense);
    checkField(field, path);
    return field;
}

// The whole file, read once, so that what is checked is what OpenVDB reads (a file rewritten in
// place, or a FIFO, is not read twice), with `control`'s progress and cancel. Refused above a
// quarter of the memory available: OpenVDB's grid, at least as large as its compressed bytes, is
// made beside them.
std::string readVdbBytes(const std::string& path, const RunControl& control) {
    const std::uint64_t available = availableMemoryBytes();
    const std::uint64_t limit = available ? available / 4 : maxInputBytes();
    struct stat info;
    const bool sized = stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode);
    if (sized && std::uint64_t(info.st_size) > limit) {
        throw Error(path + ": the file's " + mebibytes(double(info.st_size)) + " are more than a quarter of the memory available (" +
                    mebibytes(double(available)) + "); a .vdb is read whole into memory, its grid beside it");
    }
    ReadWatch watch(control, sized ? std::uint64_t(info.st_size) : 0); // a pipe: cancel without progress
    return readInputFile(path, InputKind::Binary, limit, [&](std::size_t bytes) { watch.advance(bytes); });
}

// Runs `read`, with OpenVDB's failures as Errors naming `path`.
template <class Read>
auto withErrorsNamed(const std::string& path, const Read& read) {
    try {
        return read();
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

// Runs `read` on the file's bytes, with OpenVDB's failures as Errors naming `path`; `control` for
// reading the bytes.
template <class Read>
auto readVdb(const std::string& path, const RunControl& control, const Read& read) {
    const std::string bytes = readVdbBytes(path, control);
    initializeOpenVdb();
    return withErrorsNamed(path, [&] { return read(bytes); });
}

// Progress: the file's bytes read in the first half, OpenVDB's read of them in the second.
AnyField loadVdbFile(const std::string& path, const RunControl& control) {
    const RunControl parse = control.phase(0.5, 1.0);
    return readVdb(path, control.phase(0.0, 0.5), [&](const std::string& bytes) { return loadGrid(*readFloatGrid(path, bytes, parse), path, control); });
}

// The exponent that scales a voxel too small for OpenVDB's transforms into one it holds (powers
// of two scale exactly): the field is meshed 2^exponent times larger and the points scaled back.
int meshingExponent(double voxel) {
    int exponent = 0;
    while (!representableVoxel(std::ldexp(voxel, exponent))) exponent += 8;
    return exponent;
}

void meshGrid(const openvdb::FloatGrid& grid, double iso, double adaptivity, int exponent, std::vector<glm::vec3>& points,
              std::vector<glm::uvec3>& triangles, std::vector<glm::uvec4>& quads) {
    std::vector<openvdb::Vec3s> vdbPoints;
    std::vector<openvdb::Vec3I> vdbTriangles;
    std::vector<openvdb::Vec4I> vdbQuads;
    openvdb::tools::volumeToMesh(grid, vdbPoints, vdbTriangles, vdbQuads, std::ldexp(iso, exponent), adaptivity);
    points.resize(vdbPoints.size());
    for (std::size_t i = 0; i < vdbPoints.size(); ++i) {
        points[i] = {std::ldexp(vdbPoints[i].x(), -exponent), std::ldexp(vdbPoints[i].y(), -exponent), std::ldexp(vdbPoints[i].z(), -exponent)};
    }
    triangles.resize(vdbTriangles.size());
    for (std::size_t i = 0; i < vdbTriangles.size(); ++i) triangles[i] = {vdbTriangles[i][0], vdbTriangles[i][1], vdbTriangles[i][2]};
    quads.resize(vdbQuads.size());
    for (std::size_t i = 0; i < vdbQuads.size(); ++i) quads[i] = {vdbQuads[i][0], vdbQuads[i][1], vdbQuads[i][2], vdbQuads[i][3]};
}

void surfacePolygons(const Field& field, double iso, double adaptivity, std::vector<glm::vec3>& points,
                     std::vector<glm::uvec3>& triangles, std::vector<glm::uvec4>& quads) {
    const int exponent = meshingExponent(field.grid.voxel);
    openvdb::FloatGrid::Ptr grid;
    if (exponent == 0) {
        grid = fieldToGrid(field);
    } else {
        Field scaled = field;
        scaled.grid.voxel = std::ldexp(field.grid.voxel, exponent);
        for (int a = 0; a < 3; ++a) scaled.grid.origin[a] = std::ldexp(field.grid.origin[a], exponent);
        for (float& v : scaled.values) v = std::ldexp(v, exponent);
        grid = fieldToGrid(scaled);
    }
    meshGrid(*grid, iso, adaptivity, exponent, points, triangles, quads);
}

void surfacePolygonsSparse(const SparseField& field, double iso, double adaptivity, std::vector<glm::vec3>& points,
                           std::vector<glm::uvec3>& triangles, std::vector<glm::uvec4>& quads) {
    const int exponent = meshingExponent(field.grid().voxel);
    meshGrid(*sparseToGrid(field, field.storage(), exponent), iso, adaptivity, exponent, points, triangles, quads);
}

} // namespace

} // namespace sdfgen::formats

extern "C" __attribute__((visibility("default"))) const sdfgen::OpenVdbPlugin* sdfgen_openvdb_plugin() {
    namespace f = sdfgen::formats;
    static const sdfgen::OpenVdbPlugin plugin{f::saveVdbFile, f::loadVdbFile, f::surfacePolygons, f::saveSparseVdbFile,
                                              f::saveSparseVdbFileGivenUp, f::surfacePolygonsSparse};
    return &plugin;
}
