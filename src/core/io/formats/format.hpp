#pragma once
// Field file formats as plug-ins: each format is one file in src/core/io/formats/ that defines its
// save and load functions and a function returning its FieldFormat, which registry.cpp declares
// and lists. What several formats share is declared here.
#include "core/io/read_watch.hpp"
#include "core/runtime/printable.hpp"
#include "sdfgen/field.hpp"
#include "sdfgen/formats.hpp"

#include <cstdint>
#include <functional>
#include <ostream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace sdfgen {

// Writes the sdfgen-text format (docs/field-format.md) atomically: a temporary file in the same
// folder is renamed over `path` only once complete. Throws Error naming `path` on failure.
void saveFieldText(const Field& field, const std::string& path);

// Reads and validates an sdfgen-text file; errors name the file and the line of the first problem.
// `control` as loadField's.
Field loadFieldText(const std::string& path, const RunControl& control = {});

} // namespace sdfgen

namespace sdfgen::formats {

struct FieldFormat {
    const char* extension;   // with the dot, lower case
    const char* description; // for help texts (knownFieldFormats)
    bool holdsChannels;      // writes Field::channels (see sdfgen/channels.hpp)
    void (*save)(const Field& field, const std::string& path, const SaveOptions& options);
    // The field as the file holds it, dense or band (loadAnyField), the file read once.
    AnyField (*load)(const std::string& path, const RunControl& control);
    // The narrow-band side, null for the dense-only formats (saveSparseField writes those the
    // field's dense form).
    void (*saveSparse)(const SparseField& field, const std::string& path) = nullptr;
    // saveSparse for a field given up (saveSparseField(SparseField&&)); null where saveSparse needs no second copy.
    void (*saveSparseGivenUp)(SparseField&& field, const std::string& path) = nullptr;
};

// Every registered format, in the order the help texts list them.
const std::vector<FieldFormat>& fieldFormats();

// The rules every writer checks before writing anything and every reader checks on what it read:
// values match the grid, the grid is valid, values are finite, source and method fit on one line
// (the text format's rules). Throws Error naming `path`.
void checkField(const Field& field, const std::string& path);

// Throws Error naming `path` when the grid is not one a field can be: no samples, an origin or
// voxel size that is not finite, a voxel size that is not a positive normal float32, samples whose
// coordinates leave float32's range (meshes and distances are float32) or coincide (a voxel size
// lost in the origin's rounding).
void checkGrid(const Grid& grid, const std::string& path);
// Throws Error naming `path` unless `channel` is a registered one holding its width x `count`
// values of its type ("the gradient channel has 9 values for WHAT").
void checkChannelSize(const ChannelValues& channel, std::size_t count, const std::string& path, const std::string& what);

// checkField for a narrow-band field: what its file can hold of its grid and names (its samples
// are valid by construction).
void checkSparseField(const SparseField& field, const std::string& path);

// The background of a dense field read as a band field: Field::background when set, else the
// `band` parameter (voxels) times the voxel size, else 3 voxels.
float bandBackground(const Field& field);
// The band field of a dense one: bricks where a sample lies within `background` of the surface or
// the side changes, values clamped to +-background; inside boxes where whole bricks are inside.
// Errors name `where`.
SparseField sparseFromDense(const Field& field, float background, const std::string& where);

// Throws Error naming `path` when a grid of these dimensions cannot be held in memory (the memory
// available now), before anything is allocated for it. Every dimension must be at least 1 and fit
// in an int.
void checkDimsFit(const std::uint64_t dims[3], const std::string& path);

// The method line of the text format without the keyword: "exact sign=auto/winding res=64 ...".
std::string methodLine(const Field& field);
std::string methodLine(const SparseField& field);
// Splits a method line into the field's method and parameters; Error naming `path` when malformed.
void parseMethodLine(const std::string& line, Field& field, const std::string& path);

// One .npy member of an .npz archive: its header (or whole small array) and the data after it.
struct NpzMember {
    std::string name;
    std::string head;
    const void* data = nullptr;
    std::size_t size = 0;
};
// Writes the members as an .npz (stored zip, as numpy.savez lays it out), atomically.
void writeNpz(const std::string& path, const std::vector<NpzMember>& members);

// FieldFormat::load for a format that holds dense fields only.
template <Field (*load)(const std::string&, const RunControl&)>
AnyField loadDense(const std::string& path, const RunControl& control) {
    return load(path, control);
}

} // namespace sdfgen::formats
