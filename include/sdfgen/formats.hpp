#pragma once
#include "sdfgen/any_field.hpp"
#include "sdfgen/bake.hpp"
#include "sdfgen/field.hpp"
#include "sdfgen/run_control.hpp"
#include "sdfgen/sparse_field.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace sdfgen {

// How a field is written; formats ignore what does not apply to them.
struct SaveOptions {
    // .vdb: keep only voxels within this many voxels of the surface (inactive background +-band*h,
    // as OpenVDB level sets do); 0 writes every sample (dense).
    double band = 0;
};

// Saves `field` in the format its extension names (.sdf, .npy, .npz, .vdb, .nrrd), atomically.
// An unknown extension is an Error naming the path and the known extensions, and so is a field
// with channels (Field::channels) for a format that cannot hold them.
void saveField(const Field& field, const std::string& path, const SaveOptions& options = {});

// Throws saveField's Error for `path` before a bake: an unknown extension, or `channels` that its
// format cannot hold (.npz and .vdb hold them; .sdf, .npy and .nrrd the distance only).
void checkFormatHoldsChannels(const std::string& path, const Channels& channels);

// Loads a field in any of those formats as the file holds it, opening and reading the file once,
// validated as strictly as the text format: a band field (a sparse .npz, or a .vdb level set: see
// saveSparseField) as a SparseField, any other as a Field. `control` gets the fraction of the file
// read and stops the read (Cancelled) when its cancel is raised.
AnyField loadAnyField(const std::string& path, const RunControl& control = {});
// loadAnyField's field as dense: a band field made dense (SparseField::toDense), or refused when
// that does not fit in memory.
Field loadField(const std::string& path, const RunControl& control = {});

// Saves a narrow-band field: .vdb (a level set: the band's voxels active, ±background tiles for the
// rest) and .npz (its bricks and boxes as arrays, docs/field-format.md) keep it sparse; the dense formats
// (.sdf, .npy, .nrrd) get SparseField::toDense, or an Error naming the reason and the sparse formats
// when that would not fit in memory. Atomic, as saveField.
void saveSparseField(const SparseField& field, const std::string& path);
// The same, giving the field up: a .vdb's leaves take the bricks' memory as they are made (the
// band is never held twice), and the field is left empty, saved or not.
void saveSparseField(SparseField&& field, const std::string& path);
// Saves a field as it is: a band field as saveSparseField(SparseField&&) does (given up: left
// empty, saved or not), a dense one as saveField with `options`.
void saveAnyField(AnyField&& field, const std::string& path, const SaveOptions& options = {});
// loadAnyField's field as sparse: a band field as it is, a dense one through its samples (bricks
// where a sample lies within `band` voxels of the surface; 3 when the file names no band).
SparseField loadSparseField(const std::string& path, const RunControl& control = {});

// The extensions saveField and loadField accept, with the dot (".sdf", ...).
std::vector<std::string> fieldFormatExtensions();

// The formats saveField and loadField know, in the order help texts list them: the extension
// (with the dot), what the file holds, and whether it holds the channels besides the distance.
struct FieldFormatInfo {
    const char* extension;
    const char* description;
    bool holdsChannels;
};
std::vector<FieldFormatInfo> knownFieldFormats();
// "A, B or C": the extensions of the formats that hold channels, for messages.
std::string channelFormatList();

// Points from an (N, 3) float32 or float64 .npy file (C or Fortran order) as x y z interleaved
// doubles. Error naming `path` for another dtype or shape, or a file that holds more or fewer
// bytes than its header declares.
std::vector<double> loadPointsNpy(const std::string& path);
// `values` as a C-order .npy array of `shape` (float32, float64 or int64, by their type), written
// atomically. Error naming `path` when the shape does not hold exactly values.size() values.
void saveNpy(const std::string& path, const std::vector<float>& values, const std::vector<std::uint64_t>& shape);
void saveNpy(const std::string& path, const std::vector<double>& values, const std::vector<std::uint64_t>& shape);
void saveNpy(const std::string& path, const std::vector<std::int64_t>& values, const std::vector<std::uint64_t>& shape);

} // namespace sdfgen
