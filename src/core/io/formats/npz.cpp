// NumPy .npz: a zip archive (stored, uncompressed, as numpy.savez writes it) of .npy members:
// sdf (the values, as in .npy), origin (3, float64), voxel_size (float64 scalar), dims (3, int64),
// method and source (unicode scalars). np.load(path)["sdf"][i, j, k] is sample (i, j, k). A field
// with channels adds gradient and closest ((nx, ny, nz, 3) float32) and triangle ((nx, ny, nz) int32).
#include "core/io/formats/format.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/formats/npy.hpp"
#include "sdfgen/error.hpp"

#include <zip.h>

#include <cerrno>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <cstring>
#include <memory>
#include <utility>
#include <sys/stat.h>

namespace sdfgen::formats {

namespace {

constexpr zip_uint64_t kMaxMetadataBytes = 1 << 20; // origin, dims, method, source: small arrays

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
        if (!std::ifstream(path, std::ios::binary)) throw Error(path + ": cannot open file (" + std::strerror(errno) + ")");
        struct stat info;
        if (stat(path.c_str(), &info) != 0 || !S_ISREG(info.st_mode)) throw Error(path + ": not a regular file");
        fileBytes_ = std::uint64_t(info.st_size);
        int code = 0;
        archive_.reset(zip_open(path.c_str(), ZIP_RDONLY | ZIP_CHECKCONS, &code));
        if (!archive_) {
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
    for (const auto& [name, vector] : {std::pair{"gradient.npy", &field.gradient}, {"closest.npy", &field.closest}}) {
        if (!vector->empty()) members.push_back({name, npyHeader("<f4", true, {nx, ny, nz, 3}), vector->data(), vector->size() * sizeof(float)});
    }
    if (!field.triangle.empty()) {
        members.push_back({"triangle.npy", npyHeader("<i4", true, {nx, ny, nz}), field.triangle.data(), field.triangle.size() * sizeof(std::int32_t)});
    }
    writeNpz(path, members);
}

Field loadNpz(const std::string& path) {
    const ArchiveReader archive(path);
    Field field;
    {
        const std::string where = path + ": sdf.npy";
        zip_uint64_t size = 0;
        auto file = archive.open("sdf.npy", size);
        const ReadBytes read = ArchiveReader::reader(file.get());
        const NpyHeader header = readNpyHeader(read, where);
        if (header.headerBytes > size) throw Error(where + ": member is shorter than its header");
        readNpyFieldValues(header, read, size - header.headerBytes, field, where);
        archive.checkAtEnd(file.get(), "sdf.npy");
    }
    const std::vector<double> origin = parseNpyNumbers(archive.readSmall("origin.npy"), path + ": origin.npy");
    if (origin.size() != 3) throw Error(path + ": origin.npy has " + std::to_string(origin.size()) + " values, not 3");
    for (int a = 0; a < 3; ++a) field.grid.origin[a] = origin[std::size_t(a)];
    const std::vector<double> voxel = parseNpyNumbers(archive.readSmall("voxel_size.npy"), path + ": voxel_size.npy");
    if (voxel.size() != 1) throw Error(path + ": voxel_size.npy is not a single number");
    if (!(voxel[0] > 0)) throw Error(path + ": voxel_size.npy: voxel size must be positive");
    field.grid.voxel = voxel[0];
    if (archive.has("dims.npy")) {
        const std::vector<double> dims = parseNpyNumbers(archive.readSmall("dims.npy"), path + ": dims.npy");
        if (dims.size() != 3 || dims[0] != field.grid.dims.x || dims[1] != field.grid.dims.y || dims[2] != field.grid.dims.z) {
            throw Error(path + ": dims.npy does not match the shape of sdf.npy");
        }
    }
    field.method = "unknown";
    if (archive.has("method.npy")) parseMethodLine(parseNpyString(archive.readSmall("method.npy"), path + ": method.npy"), field, path + ": method.npy");
    if (archive.has("source.npy")) field.source = parseNpyString(archive.readSmall("source.npy"), path + ": source.npy");
    checkField(field, path);
    return field;
}

} // namespace sdfgen::formats
