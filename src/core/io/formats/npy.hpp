#pragma once
// The NumPy .npy array format (numpy.lib.format, versions 1 to 3), shared by the .npy and .npz
// formats: header writing and strict parsing, and the field's float32 (nx, ny, nz) array.
#include "sdfgen/field.hpp"
#include "sdfgen/run_control.hpp"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "sdfgen's binary field formats assume a little-endian machine"
#endif

namespace sdfgen::formats {

struct NpyHeader {
    std::string descr;                // dtype, e.g. "<f4"
    bool fortranOrder = false;
    std::vector<std::uint64_t> shape; // empty for a scalar
    std::size_t headerBytes = 0;      // magic, version, length and dictionary: where the data starts

    // Elements in the array; Error naming `where` when the product overflows.
    std::uint64_t count(const std::string& where) const;
    // Bytes of data: count() * itemSize(); Error naming `where` when that overflows.
    std::uint64_t dataBytes(const std::string& where) const;
    // Bytes per element of descr ("<f4" -> 4); 0 when descr is not a fixed-size number or string.
    std::size_t itemSize() const;
};

// Reads up to `size` bytes into `data`, returning how many it read (fewer only at the end).
using ReadBytes = std::function<std::size_t(void* data, std::size_t size)>;

// The dtype of a channel's values ("<f4", "<i4"): both 4 bytes.
inline const char* npyType(ChannelType type) { return type == ChannelType::Int32 ? "<i4" : "<f4"; }

// The complete header (version 1.0: magic, version, length, dictionary padded to 64 bytes).
std::string npyHeader(const std::string& descr, bool fortranOrder, const std::vector<std::uint64_t>& shape);

// Reads and parses a header; Error("WHERE: problem") for anything that is not a valid .npy header.
NpyHeader readNpyHeader(const ReadBytes& read, const std::string& where);

// The field's array: float32 little-endian, 3 dimensions; Fortran order is the field's own layout,
// C order is transposed. `dataBytes` is how many bytes follow the header (checked against the
// shape before anything is allocated). Sets field.grid.dims and field.values. `control` as loadField's.
void readNpyFieldValues(const NpyHeader& header, const ReadBytes& read, std::uint64_t dataBytes, Field& field,
                        const std::string& where, const RunControl& control);

// A .npy holding the field's values as (nx, ny, nz) float32 in Fortran order (x fastest), the
// layout of Field::values, so the data is the buffer as is.
std::string npyFieldHeader(const Field& field);

// Small arrays for the .npz metadata, complete .npy files in memory.
std::string npyFloat64Array(const std::vector<double>& values, bool scalar);
std::string npyInt64Array(const std::vector<std::int64_t>& values);
std::string npyUnicodeScalar(const std::string& utf8);

// Parses a complete small .npy held in memory (an .npz member) as numbers or a string; Error
// naming `where` when it is malformed or of another type.
std::vector<double> parseNpyNumbers(const std::string& bytes, const std::string& where);
std::string parseNpyString(const std::string& bytes, const std::string& where);

} // namespace sdfgen::formats
