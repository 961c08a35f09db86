// The table of field formats behind saveField and loadField. A new format is one file in this
// folder plus one line here.
#include "core/io/formats/format.hpp"
#include "sdfgen/error.hpp"
#include "core/io/file_extension.hpp"

#include <glm/common.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>

namespace sdfgen {

namespace formats {

const std::vector<FieldFormat>& fieldFormats() {
    static const std::vector<FieldFormat> table = {
        {".sdf", "sdfgen text (docs/field-format.md)", false, saveText, loadText},
        {".npy", "NumPy float32 array (nx, ny, nz), values only", false, saveNpy, loadNpy},
        {".npz", "NumPy archive: the array as 'sdf' plus origin, voxel_size, dims, method, source, and any channels", true, saveNpz,
         loadNpz},
        {".vdb", "OpenVDB FloatGrid 'surface', level set class, and any channels as grids of their names", true, saveVdb, loadVdb},
        {".nrrd", "NRRD raw float32 (ParaView, 3D Slicer, teem)", false, saveNrrd, loadNrrd},
    };
    return table;
}

namespace {

const FieldFormat& formatOf(const std::string& path) {
    const std::string extension = lowerExtension(path);
    for (const FieldFormat& format : fieldFormats()) {
        if (extension == format.extension) return format;
    }
    std::string known;
    for (const FieldFormat& format : fieldFormats()) known += (known.empty() ? "" : ", ") + std::string(format.extension);
    throw Error(path + ": unknown field format " + (extension.empty() ? "(no extension)" : "'" + extension + "'") +
                "; known: " + known);
}

} // namespace
} // namespace formats

void checkFormatHoldsChannels(const std::string& path, const Channels& channels) {
    const formats::FieldFormat& format = formats::formatOf(path);
    if (channels.any() && !format.holdsChannels) {
        throw Error(path + ": " + format.extension + " holds the distance (sdf) only; for channels " + toString(channels).substr(4) +
                    " write " + channelFormatList());
    }
}

void saveField(const Field& field, const std::string& path, const SaveOptions& options) {
    Channels channels;
    channels.gradient = !field.gradient.empty();
    channels.closest = !field.closest.empty();
    channels.triangle = !field.triangle.empty();
    checkFormatHoldsChannels(path, channels);
    formats::formatOf(path).save(field, path, options);
}

Field loadField(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw Error(path + ": is a directory, not a field file");
    return formats::formatOf(path).load(path);
}

void saveSparseField(const SparseField& field, const std::string& path) {
    const formats::FieldFormat& format = formats::formatOf(path);
    field.check(path);
    if (format.saveSparse) return format.saveSparse(field, path);
    Field dense;
    try {
        dense = field.toDense();
    } catch (const Error& e) {
        throw Error(path + ": " + format.extension + " holds dense fields only, and " + e.what());
    }
    format.save(dense, path, {});
}

bool isSparseFieldFile(const std::string& path) {
    const formats::FieldFormat& format = formats::formatOf(path);
    return format.isSparse && format.isSparse(path);
}

SparseField loadSparseField(const std::string& path) {
    const formats::FieldFormat& format = formats::formatOf(path);
    if (format.isSparse && format.isSparse(path)) return format.loadSparse(path);
    // A dense field: bricks where a sample lies within the band, boxes of whole inside bricks.
    const Field dense = loadField(path);
    const std::string named = dense.parameter("band");
    const double band = named.empty() ? 3.0 : std::strtod(named.c_str(), nullptr);
    SparseField sparse;
    sparse.source = dense.source;
    sparse.method = dense.method;
    sparse.parameters = dense.parameters;
    sparse.grid = dense.grid;
    sparse.background = dense.background > 0 ? dense.background : float(band * dense.grid.voxel);
    if (!(sparse.background > 0.0f) || !std::isfinite(sparse.background)) throw Error(path + ": no band can be made at this grid's scale");
    constexpr int kBrick = SparseField::kBrick;
    const glm::ivec3 dims = dense.grid.dims, bricks = (dims + (kBrick - 1)) / kBrick;
    for (int bz = 0; bz < bricks.z; ++bz)
        for (int by = 0; by < bricks.y; ++by) {
            int runStart = -1;
            for (int bx = 0; bx <= bricks.x; ++bx) {
                int side = -1; // 1 all inside, 0 all outside, -1 stored (or past the row's end)
                if (bx < bricks.x) {
                    const glm::ivec3 lo = glm::ivec3(bx, by, bz) * kBrick, hi = glm::min(lo + kBrick, dims);
                    bool in = false, out = false, band = false;
                    for (int k = lo.z; k < hi.z; ++k)
                        for (int j = lo.y; j < hi.y; ++j)
                            for (int i = lo.x; i < hi.x; ++i) {
                                const float v = dense.at(i, j, k);
                                band |= std::fabs(v) < sparse.background;
                                (std::signbit(v) ? in : out) = true;
                            }
                    side = band || (in && out) ? -1 : in ? 1 : 0;
                    if (side < 0) {
                        sparse.bricks.emplace_back(bx, by, bz);
                        for (int k = lo.z; k < lo.z + kBrick; ++k)
                            for (int j = lo.y; j < lo.y + kBrick; ++j)
                                for (int i = lo.x; i < lo.x + kBrick; ++i) {
                                    float v = sparse.background;
                                    if (i < dims.x && j < dims.y && k < dims.z) {
                                        v = dense.at(i, j, k);
                                        if (!(std::fabs(v) < sparse.background)) v = std::signbit(v) ? -sparse.background : sparse.background;
                                    }
                                    sparse.values.push_back(v);
                                }
                    }
                }
                if (side == 1 && runStart < 0) runStart = bx;
                if (side != 1 && runStart >= 0) {
                    sparse.insideBoxes.push_back({runStart * kBrick, by * kBrick, bz * kBrick, std::min(bx * kBrick, dims.x),
                                                  std::min(by * kBrick + kBrick, dims.y), std::min(bz * kBrick + kBrick, dims.z)});
                    runStart = -1;
                }
            }
        }
    sparse.check(path);
    return sparse;
}

std::vector<std::string> fieldFormatExtensions() {
    std::vector<std::string> extensions;
    for (const formats::FieldFormat& format : formats::fieldFormats()) extensions.emplace_back(format.extension);
    return extensions;
}

std::vector<FieldFormatInfo> knownFieldFormats() {
    std::vector<FieldFormatInfo> known;
    for (const formats::FieldFormat& format : formats::fieldFormats()) known.push_back({format.extension, format.description, format.holdsChannels});
    return known;
}

std::string channelFormatList() {
    std::vector<const char*> holding;
    for (const formats::FieldFormat& format : formats::fieldFormats()) {
        if (format.holdsChannels) holding.push_back(format.extension);
    }
    std::string list;
    for (std::size_t i = 0; i < holding.size(); ++i) list += (i == 0 ? "" : i + 1 == holding.size() ? " or " : ", ") + std::string(holding[i]);
    return list;
}

} // namespace sdfgen
