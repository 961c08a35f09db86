// NumPy .npz: a zip archive (stored, uncompressed, as numpy.savez writes it) of .npy members:
// sdf (the values, as in .npy), origin (3, float64), voxel_size (float64 scalar), dims (3, int64),
// method and source (unicode scalars). np.load(path)["sdf"][i, j, k] is sample (i, j, k). A field
// with channels adds each under its name ((nx, ny, nz, width) of its type, (nx, ny, nz) for width 1).
// A band field (SparseField) has no sdf but its bricks and boxes, laid out for numpy
// (docs/field-format.md): brick_origins (B, 3) int32, the first sample of each brick; brick_values
// (8, 8, 8, B) float32 in Fortran order, values[i, j, k, b], which is SparseField::values as is;
// inside_boxes (R, 6) int32; background (float32 scalar); and the grid and names as above.
#include "core/io/formats/format.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/formats/npy.hpp"
#include "core/runtime/memory.hpp"
#include "sdfgen/error.hpp"

#include <zip.h>

#include <cerrno>
#include <cmath>
#include <filesystem>
#include <fcntl.h>
#include <fstream>
#include <cstring>
#include <limits>
#include <memory>
#include <utility>
#include <sys/stat.h>
#include <unistd.h>

namespace sdfgen::formats {

namespace {

constexpr zip_uint64_t kMaxMetadataBytes = 1 << 20; // origin, dims, method, source: small arrays
// The members that make an archive a band field's.
constexpr const char* kBrickOrigins = "brick_origins.npy";
constexpr const char* kBrickValues = "brick_values.npy";
constexpr const char* kInsideBoxes = "inside_boxes.npy";
constexpr const char* kBackground = "background.npy";

struct ZipCloser {
    void operator()(zip_t* archive) const { zip_discard(archive); }
};
struct ZipFileCloser {
    void operator()(zip_file_t* file) const { zip_fclose(file); }
};
struct ZipSourceFree {
    void operator()(zip_source_t* source) const { zip_source_free(source); }
};

std::string zipProblem(zip_error_t* error) {
    std::string text = zip_error_strerror(error);
    zip_error_fini(error);
    return text;
}

// Adds the members to `archive` as numpy.savez lays them out (stored, uncompressed) and closes it,
// which writes it out. The members' data is read where it lies, not copied first.
void addMembersAndClose(zip_t* archive, const std::vector<NpzMember>& members, const std::string& path) {
    for (const NpzMember& m : members) {
        // The field's values go in as they are, behind their header (libzip only reads fragments).
        const zip_buffer_fragment_t fragments[2] = {
            {reinterpret_cast<zip_uint8_t*>(const_cast<char*>(m.head.data())), m.head.size()},
            {static_cast<zip_uint8_t*>(const_cast<void*>(m.data)), m.size}};
        zip_source_t* member = zip_source_buffer_fragment(archive, fragments, m.size > 0 ? 2 : 1, 0);
        const zip_int64_t index = member ? zip_file_add(archive, m.name.c_str(), member, ZIP_FL_ENC_UTF_8) : -1;
        if (index < 0) {
            if (member) zip_source_free(member);
            const std::string problem = zip_strerror(archive);
            zip_discard(archive);
            throw Error(path + ": cannot add " + m.name + " to the archive (" + problem + ")");
        }
        zip_set_file_compression(archive, zip_uint64_t(index), ZIP_CM_STORE, 0);
    }
    if (zip_close(archive) != 0) {
        const std::string problem = zip_strerror(archive);
        zip_discard(archive);
        throw Error(path + ": cannot write the archive (" + problem + ")");
    }
}

// The archive in memory, for a target that is not a regular file (a pipe, /dev/stdout), which
// libzip cannot write in place.
std::string buildArchive(const std::vector<NpzMember>& members, const std::string& path) {
    zip_error_t error;
    zip_error_init(&error);
    std::unique_ptr<zip_source_t, ZipSourceFree> buffer(zip_source_buffer_create(nullptr, 0, 0, &error));
    if (!buffer) throw Error(path + ": cannot create the archive (" + zipProblem(&error) + ")");
    zip_t* archive = zip_open_from_source(buffer.get(), ZIP_CREATE | ZIP_TRUNCATE, &error);
    if (!archive) throw Error(path + ": cannot create the archive (" + zipProblem(&error) + ")");
    zip_source_keep(buffer.get()); // the archive releases its reference on close; the bytes stay here
    addMembersAndClose(archive, members, path);
    zip_stat_t stat;
    if (zip_source_stat(buffer.get(), &stat) != 0 || !(stat.valid & ZIP_STAT_SIZE) || zip_source_open(buffer.get()) != 0) {
        throw Error(path + ": cannot read back the archive built in memory");
    }
    std::string bytes(stat.size, '\0');
    const zip_int64_t n = zip_source_read(buffer.get(), bytes.data(), stat.size);
    zip_source_close(buffer.get());
    if (n != zip_int64_t(stat.size)) throw Error(path + ": cannot read back the archive built in memory");
    return bytes;
}

class ArchiveReader {
public:
    explicit ArchiveReader(const std::string& path) : path_(path) {
        // One open file for the size the members are checked against and for libzip's reading:
        // by name, a file swapped in between would be read against another file's size.
        const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd < 0) throw Error(path + ": cannot open file (" + std::strerror(errno) + ")");
        struct stat info;
        if (fstat(fd, &info) != 0 || !S_ISREG(info.st_mode)) {
            close(fd);
            throw Error(path + ": not a regular file");
        }
        fileBytes_ = std::uint64_t(info.st_size);
        int code = 0;
        archive_.reset(zip_fdopen(fd, ZIP_RDONLY | ZIP_CHECKCONS, &code)); // libzip's on success only
        if (!archive_) {
            close(fd);
            zip_error_t error;
            zip_error_init_with_code(&error, code);
            throw Error(path + ": not a valid .npz (zip) archive: " + zipProblem(&error));
        }
    }

    bool has(const std::string& name) const { return zip_name_locate(archive_.get(), name.c_str(), 0) >= 0; }

    // A member opened for reading, and its uncompressed size.
    std::unique_ptr<zip_file_t, ZipFileCloser> open(const std::string& name, zip_uint64_t& size) const {
        const zip_int64_t index = zip_name_locate(archive_.get(), name.c_str(), 0);
        if (index < 0) throw Error(path_ + ": the archive has no '" + name + "'");
        zip_stat_t stat;
        const zip_uint64_t needed = ZIP_STAT_SIZE | ZIP_STAT_COMP_SIZE | ZIP_STAT_COMP_METHOD;
        if (zip_stat_index(archive_.get(), zip_uint64_t(index), 0, &stat) != 0 || (stat.valid & needed) != needed) {
            throw Error(path_ + ": cannot read the size of '" + name + "'");
        }
        // The sizes the archive claims, checked against what its bytes can hold before anything
        // is allocated for them: stored data is as long as it is in the file; deflate expands
        // at most 1032:1 (a 258-byte match per two bits, plus the block headers' bytes).
        if (stat.comp_size > fileBytes_) {
            throw Error(path_ + ": '" + name + "' claims " + std::to_string(stat.comp_size) + " compressed bytes in a file of " +
                        std::to_string(fileBytes_));
        }
        if (stat.comp_method == ZIP_CM_STORE) {
            if (stat.size != stat.comp_size) {
                throw Error(path_ + ": stored '" + name + "' claims " + std::to_string(stat.size) + " bytes but holds " +
                            std::to_string(stat.comp_size));
            }
        } else if (stat.comp_method == ZIP_CM_DEFLATE) {
            if (stat.size / 1032 > stat.comp_size + 1) {
                throw Error(path_ + ": '" + name + "' claims " + std::to_string(stat.size) + " bytes from " + std::to_string(stat.comp_size) +
                            " compressed, more than deflate can expand to");
            }
        } else {
            throw Error(path_ + ": '" + name + "' uses compression method " + std::to_string(stat.comp_method) +
                        " (numpy writes stored or deflated members)");
        }
        size = stat.size;
        std::unique_ptr<zip_file_t, ZipFileCloser> file(zip_fopen_index(archive_.get(), zip_uint64_t(index), 0));
        if (!file) throw Error(path_ + ": cannot open '" + name + "' (" + zip_strerror(archive_.get()) + ")");
        return file;
    }

    // Reads exactly up to the end of the member; the checksum is verified when the end is reached.
    static ReadBytes reader(zip_file_t* file) {
        return [file](void* data, std::size_t size) -> std::size_t {
            std::size_t done = 0;
            while (done < size) {
                const zip_int64_t n = zip_fread(file, static_cast<char*>(data) + done, size - done);
                if (n <= 0) break;
                done += std::size_t(n);
            }
            return done;
        };
    }

    void checkAtEnd(zip_file_t* file, const std::string& name) const {
        char extra;
        if (zip_fread(file, &extra, 1) != 0) {
            throw Error(path_ + ": '" + name + "' is corrupt (" + zip_file_strerror(file) + ")");
        }
    }

    std::string readSmall(const std::string& name) const {
        zip_uint64_t size = 0;
        auto file = open(name, size);
        if (size > kMaxMetadataBytes) throw Error(path_ + ": '" + name + "' is too large for metadata");
        std::string bytes(size, '\0');
        if (reader(file.get())(bytes.data(), size) != size) {
            throw Error(path_ + ": '" + name + "' is truncated or corrupt (" + zip_file_strerror(file.get()) + ")");
        }
        checkAtEnd(file.get(), name);
        return bytes;
    }

private:
    std::string path_;
    std::uint64_t fileBytes_ = 0;
    std::unique_ptr<zip_t, ZipCloser> archive_;
};

// origin, voxel_size, dims (required when `needDims`, else checked against the shape read from
// sdf), method and source into `field`.
void readGridAndNames(const ArchiveReader& archive, const std::string& path, Field& field, bool needDims) {
    const std::vector<double> origin = parseNpyNumbers(archive.readSmall("origin.npy"), path + ": origin.npy");
    if (origin.size() != 3) throw Error(path + ": origin.npy has " + std::to_string(origin.size()) + " values, not 3");
    for (int a = 0; a < 3; ++a) field.grid.origin[a] = origin[std::size_t(a)];
    const std::vector<double> voxel = parseNpyNumbers(archive.readSmall("voxel_size.npy"), path + ": voxel_size.npy");
    if (voxel.size() != 1) throw Error(path + ": voxel_size.npy is not a single number");
    if (!(voxel[0] > 0)) throw Error(path + ": voxel_size.npy: voxel size must be positive");
    field.grid.voxel = voxel[0];
    if (needDims || archive.has("dims.npy")) {
        const std::vector<double> dims = parseNpyNumbers(archive.readSmall("dims.npy"), path + ": dims.npy");
        if (needDims) {
            if (dims.size() != 3) throw Error(path + ": dims.npy has " + std::to_string(dims.size()) + " values, not 3");
            for (int a = 0; a < 3; ++a) {
                const double d = dims[std::size_t(a)];
                if (!(d >= 1 && d <= double(std::numeric_limits<int>::max())) || d != std::floor(d)) {
                    throw Error(path + ": dims.npy: dimension " + std::to_string(d) + " is not a whole number from 1 to 2^31-1");
                }
                field.grid.dims[a] = int(d);
            }
        } else if (dims.size() != 3 || dims[0] != field.grid.dims.x || dims[1] != field.grid.dims.y || dims[2] != field.grid.dims.z) {
            throw Error(path + ": dims.npy does not match the shape of sdf.npy");
        }
    }
    field.method = "unknown";
    if (archive.has("method.npy")) parseMethodLine(parseNpyString(archive.readSmall("method.npy"), path + ": method.npy"), field, path + ": method.npy");
    if (archive.has("source.npy")) field.source = parseNpyString(archive.readSmall("source.npy"), path + ": source.npy");
}

// Throws Error naming `where` when `bytes` more cannot be held in the memory available now.
void checkBytesFit(std::uint64_t bytes, const std::string& where) {
    const std::uint64_t memory = availableMemoryBytes();
    if (memory > 0 && bytes > memory) {
        throw Error(where + ": needs " + mebibytes(double(bytes)) + ", more than the " + mebibytes(double(memory)) + " of memory available");
    }
}

// An integer member of shape (rows, columns), int32 or int64 in either order, as int32 rows (C
// order); every count is checked against the member's bytes before anything is allocated.
std::vector<std::int32_t> readIntRows(const ArchiveReader& archive, const std::string& name, std::uint64_t columns, const std::string& path) {
    const std::string where = path + ": " + name;
    zip_uint64_t size = 0;
    auto file = archive.open(name, size);
    const ReadBytes read = ArchiveReader::reader(file.get());
    const NpyHeader header = readNpyHeader(read, where);
    if (header.descr != "<i4" && header.descr != "<i8") throw Error(where + ": dtype '" + printable(header.descr) + "' is not int32 or int64");
    if (header.shape.size() != 2 || header.shape[1] != columns) {
        throw Error(where + ": shape is not (n, " + std::to_string(columns) + ")");
    }
    const std::uint64_t bytes = header.dataBytes(where);
    if (header.headerBytes > size || bytes != size - header.headerBytes) {
        throw Error(where + ": holds " + std::to_string(size >= header.headerBytes ? size - header.headerBytes : 0) + " bytes of data for " +
                    std::to_string(bytes));
    }
    checkBytesFit(bytes + header.count(where) * sizeof(std::int32_t), where);
    const std::uint64_t rows = header.shape[0], count = header.count(where);
    std::vector<std::int64_t> wide(header.descr == "<i8" ? count : 0);
    std::vector<std::int32_t> narrow(count);
    if (read(header.descr == "<i8" ? static_cast<void*>(wide.data()) : static_cast<void*>(narrow.data()), bytes) != bytes) {
        throw Error(where + ": is truncated or corrupt (" + zip_file_strerror(file.get()) + ")");
    }
    archive.checkAtEnd(file.get(), name);
    for (std::uint64_t n = 0; n < wide.size(); ++n) {
        if (wide[n] < std::numeric_limits<std::int32_t>::min() || wide[n] > std::numeric_limits<std::int32_t>::max()) {
            throw Error(where + ": value " + std::to_string(wide[n]) + " is beyond int32");
        }
        narrow[n] = std::int32_t(wide[n]);
    }
    if (!header.fortranOrder) return narrow;
    std::vector<std::int32_t> rowMajor(count);
    for (std::uint64_t r = 0; r < rows; ++r)
        for (std::uint64_t c = 0; c < columns; ++c) rowMajor[r * columns + c] = narrow[c * rows + r];
    return rowMajor;
}

// brick_values: float32 (8, 8, 8, bricks), in Fortran order (SparseField::values as is) or in C order.
std::vector<float> readBrickValues(const ArchiveReader& archive, std::uint64_t bricks, const std::string& path, const RunControl& control) {
    const std::string where = path + ": " + kBrickValues;
    zip_uint64_t size = 0;
    auto file = archive.open(kBrickValues, size);
    const ReadBytes read = ArchiveReader::reader(file.get());
    const NpyHeader header = readNpyHeader(read, where);
    if (header.descr != "<f4") throw Error(where + ": dtype '" + printable(header.descr) + "' is not little-endian float32 ('<f4')");
    constexpr std::uint64_t B = SparseField::kBrick;
    if (header.shape != std::vector<std::uint64_t>{B, B, B, bricks}) {
        throw Error(where + ": shape is not (8, 8, 8, " + std::to_string(bricks) + ") for the " + std::to_string(bricks) + " brick origins");
    }
    const std::uint64_t bytes = header.dataBytes(where);
    if (header.headerBytes > size || bytes != size - header.headerBytes) {
        throw Error(where + ": holds " + std::to_string(size >= header.headerBytes ? size - header.headerBytes : 0) + " bytes of data for " +
                    std::to_string(bytes));
    }
    checkBytesFit(header.fortranOrder ? bytes : 2 * bytes, where);
    std::vector<float> values(header.count(where));
    // A block at a time, so that the read can report progress and stop at a Cancel.
    ReadWatch watch(control, bytes);
    constexpr std::uint64_t kBlock = std::uint64_t(1) << 20;
    for (std::uint64_t done = 0; done < bytes;) {
        const std::uint64_t n = std::min(kBlock, bytes - done);
        if (read(reinterpret_cast<char*>(values.data()) + done, n) != n) {
            throw Error(where + ": is truncated or corrupt (" + zip_file_strerror(file.get()) + ")");
        }
        done += n;
        watch.advance(n);
    }
    archive.checkAtEnd(file.get(), kBrickValues);
    if (header.fortranOrder) return values;
    // C order: [i, j, k, b] at ((i * 8 + j) * 8 + k) * bricks + b.
    std::vector<float> brickMajor(values.size());
    for (std::uint64_t b = 0; b < bricks; ++b)
        for (std::uint64_t k = 0; k < B; ++k)
            for (std::uint64_t j = 0; j < B; ++j)
                for (std::uint64_t i = 0; i < B; ++i) brickMajor[((b * B + k) * B + j) * B + i] = values[((i * B + j) * B + k) * bricks + b];
    return brickMajor;
}

} // namespace

void writeNpz(const std::string& path, const std::vector<NpzMember>& members) {
    // Written by libzip straight into the temporary file: an archive built in memory first would
    // hold a copy of every member (the channels of a res-256 field: 400 MB more, and seconds).
    writeFileAtomicallyAt(path, [&](const std::string& target) {
        std::error_code ec;
        if (!std::filesystem::is_regular_file(target, ec)) {
            const std::string archive = buildArchive(members, path);
            std::ofstream out(target, std::ios::binary);
            out.write(archive.data(), std::streamsize(archive.size()));
            out.flush();
            if (!out) throw Error(path + ": cannot write (" + std::strerror(errno) + ")");
            return;
        }
        int code = 0;
        zip_t* archive = zip_open(target.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &code);
        if (!archive) {
            zip_error_t error;
            zip_error_init_with_code(&error, code);
            throw Error(path + ": cannot create the archive (" + zipProblem(&error) + ")");
        }
        addMembersAndClose(archive, members, path);
    });
}

namespace {

void saveNpz(const Field& field, const std::string& path, const SaveOptions&) {
    checkField(field, path);
    const Grid& g = field.grid;
    std::vector<NpzMember> members = {
        {"sdf.npy", npyFieldHeader(field), field.values.data(), field.values.size() * sizeof(float)},
        {"origin.npy", npyFloat64Array({double(g.origin.x), double(g.origin.y), double(g.origin.z)}, false)},
        {"voxel_size.npy", npyFloat64Array({double(g.voxel)}, true)},
        {"dims.npy", npyInt64Array({g.dims.x, g.dims.y, g.dims.z})},
        {"method.npy", npyUnicodeScalar(methodLine(field))},
        {"source.npy", npyUnicodeScalar(field.source)},
    };
    // The channels in Fortran order, as sdf: the planar buffers as they are (component last).
    const std::uint64_t nx = std::uint64_t(g.dims.x), ny = std::uint64_t(g.dims.y), nz = std::uint64_t(g.dims.z);
    for (const ChannelValues& channel : field.channels) {
        const ChannelInfo& info = channel.info();
        std::vector<std::uint64_t> shape{nx, ny, nz};
        if (info.width > 1) shape.push_back(std::uint64_t(info.width));
        members.push_back({channel.name + ".npy", npyHeader(npyType(info.type), true, shape), channel.data(), channel.size() * 4});
    }
    writeNpz(path, members);
}

// The band field of an archive that has brick_origins.
SparseField loadBandNpz(const ArchiveReader& archive, const std::string& path, const RunControl& control) {
    Field names;
    readGridAndNames(archive, path, names, true);
    checkGrid(names.grid, path);
    FieldHeader header = std::move(names);
    const std::vector<double> background = parseNpyNumbers(archive.readSmall(kBackground), path + ": " + kBackground);
    if (background.size() != 1) throw Error(path + ": " + kBackground + " is not a single number");
    header.background = float(background[0]);
    const std::vector<std::int32_t> origins = readIntRows(archive, kBrickOrigins, 3, path);
    SparseField::Storage storage;
    const std::size_t bricks = origins.size() / 3;
    storage.bricks.resize(bricks);
    for (std::size_t b = 0; b < bricks; ++b) {
        for (int a = 0; a < 3; ++a) {
            const std::int32_t first = origins[3 * b + std::size_t(a)];
            if (first % SparseField::kBrick != 0) {
                throw Error(path + ": " + kBrickOrigins + ": brick " + std::to_string(b) + " does not start on a multiple of 8");
            }
            storage.bricks[b][a] = first / SparseField::kBrick;
        }
    }
    storage.values = readBrickValues(archive, bricks, path, control);
    const std::vector<std::int32_t> boxes = readIntRows(archive, kInsideBoxes, 6, path);
    storage.insideBoxes.resize(boxes.size() / 6);
    if (!boxes.empty()) std::memcpy(storage.insideBoxes.data(), boxes.data(), boxes.size() * sizeof(std::int32_t));
    SparseField field(header, std::move(storage), path);
    checkSparseField(field, path);
    return field;
}

AnyField loadNpz(const std::string& path, const RunControl& control) {
    const ArchiveReader archive(path);
    if (archive.has(kBrickOrigins)) return loadBandNpz(archive, path, control);
    Field field;
    {
        const std::string where = path + ": sdf.npy";
        zip_uint64_t size = 0;
        auto file = archive.open("sdf.npy", size);
        const ReadBytes read = ArchiveReader::reader(file.get());
        const NpyHeader header = readNpyHeader(read, where);
        if (header.headerBytes > size) throw Error(where + ": member is shorter than its header");
        readNpyFieldValues(header, read, size - header.headerBytes, field, where, control);
        archive.checkAtEnd(file.get(), "sdf.npy");
    }
    readGridAndNames(archive, path, field, false);
    checkField(field, path);
    return field;
}

void saveSparseNpz(const SparseField& field, const std::string& path) {
    checkSparseField(field, path);
    const Grid& g = field.grid();
    std::vector<std::int32_t> origins;
    origins.reserve(3 * field.bricks().size());
    for (const glm::ivec3& brick : field.bricks()) {
        for (int a = 0; a < 3; ++a) origins.push_back(brick[a] * SparseField::kBrick);
    }
    const float backgroundValue = field.background();
    std::string background = npyHeader("<f4", false, {});
    background.append(reinterpret_cast<const char*>(&backgroundValue), sizeof(float));
    const std::uint64_t bricks = field.bricks().size(), B = SparseField::kBrick;
    const std::vector<NpzMember> members = {
        {kBrickOrigins, npyHeader("<i4", false, {bricks, 3}), origins.data(), origins.size() * sizeof(std::int32_t)},
        {kBrickValues, npyHeader("<f4", true, {B, B, B, bricks}), field.values().data(), field.values().size() * sizeof(float)},
        {kInsideBoxes, npyHeader("<i4", false, {field.insideBoxes().size(), 6}), field.insideBoxes().data(),
         field.insideBoxes().size() * sizeof(field.insideBoxes()[0])},
        {kBackground, background},
        {"origin.npy", npyFloat64Array({double(g.origin.x), double(g.origin.y), double(g.origin.z)}, false)},
        {"voxel_size.npy", npyFloat64Array({double(g.voxel)}, true)},
        {"dims.npy", npyInt64Array({g.dims.x, g.dims.y, g.dims.z})},
        {"method.npy", npyUnicodeScalar(methodLine(field))},
        {"source.npy", npyUnicodeScalar(field.source)},
    };
    writeNpz(path, members);
}

} // namespace

FieldFormat npzFormat() {
    return {".npz", "NumPy archive: the array as 'sdf' plus origin, voxel_size, dims, method, source, and any channels; a band field as bricks",
            true, saveNpz, loadNpz, saveSparseNpz};
}

} // namespace sdfgen::formats
