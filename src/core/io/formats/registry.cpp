// The table of field formats behind saveField and loadField. A new format is one file in this
// folder that defines its FieldFormat, plus its lines here: the declaration and the table's entry.
#include "core/io/formats/format.hpp"
#include "sdfgen/error.hpp"
#include "core/runtime/file_extension.hpp"
#include "core/runtime/out_of_memory.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace sdfgen {

namespace formats {

// Each defined in the file of its name (.vdb in core/io/openvdb_plugin.cpp, which opens the plug-in).
FieldFormat textFormat();
FieldFormat npyFormat();
FieldFormat npzFormat();
FieldFormat vdbFormat();
FieldFormat nrrdFormat();

const std::vector<FieldFormat>& fieldFormats() {
    static const std::vector<FieldFormat> table = {
        textFormat(),
        npyFormat(),
        npzFormat(),
        vdbFormat(),
        nrrdFormat(),
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
    checkFormatHoldsChannels(path, channelsOf(field.channels));
    namingOutOfMemory(path, "writing it", [&] { formats::formatOf(path).save(field, path, options); });
}

namespace {

// Before the extension is looked at: a folder's name has none that means anything.
void refuseDirectory(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw Error(path + ": is a directory, not a field file");
}

} // namespace

AnyField loadAnyField(const std::string& path, const RunControl& control) {
    refuseDirectory(path);
    AnyField loaded = namingOutOfMemory(path, "reading it", [&] { return formats::formatOf(path).load(path, control); });
    // A band field's dense form saved in a dense format keeps only its `band` parameter.
    if (!loaded.isBand()) {
        Field& field = loaded.dense();
        if (field.background == 0 && !field.parameter("band").empty()) field.background = formats::bandBackground(field);
    }
    return loaded;
}

Field loadField(const std::string& path, const RunControl& control) {
    AnyField loaded = loadAnyField(path, control);
    if (!loaded.isBand()) return std::move(loaded.dense());
    return namingOutOfMemory(path, "reading it", [&] {
        try {
            return loaded.band().toDense();
        } catch (const Error& e) { // toDense names the field, not the file
            throw Error(path + ": " + e.what());
        }
    });
}

void saveSparseField(const SparseField& field, const std::string& path) {
    const formats::FieldFormat& format = formats::formatOf(path);
    if (format.saveSparse) return namingOutOfMemory(path, "writing it", [&] { format.saveSparse(field, path); });
    Field dense;
    try {
        dense = field.toDense();
    } catch (const Error& e) {
        throw Error(path + ": " + format.extension + " holds every sample, and " + e.what());
    }
    namingOutOfMemory(path, "writing it", [&] { format.save(dense, path, {}); });
}

void saveSparseField(SparseField&& field, const std::string& path) {
    const formats::FieldFormat& format = formats::formatOf(path);
    SparseField mine = std::move(field); // empty whatever happens
    if (format.saveSparseGivenUp) {
        return namingOutOfMemory(path, "writing it", [&] { format.saveSparseGivenUp(std::move(mine), path); });
    }
    saveSparseField(mine, path);
}

void saveAnyField(AnyField&& field, const std::string& path, const SaveOptions& options) {
    if (field.isBand()) return saveSparseField(std::move(field.band()), path);
    saveField(field.dense(), path, options);
}

SparseField loadSparseField(const std::string& path, const RunControl& control) {
    AnyField loaded = loadAnyField(path, control);
    if (loaded.isBand()) return std::move(loaded.band());
    const Field& dense = loaded.dense();
    return namingOutOfMemory(path, "reading it", [&] { return formats::sparseFromDense(dense, formats::bandBackground(dense), path); });
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
