// NumPy .npy: the field as a float32 (nx, ny, nz) array in Fortran order, so that a[i, j, k] is
// sample (i, j, k) and the data on disk is Field::values as is. The file carries no grid; .npz does.
#include "core/io/formats/npy.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/formats/format.hpp"
#include "sdfgen/error.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <sys/stat.h>

namespace sdfgen::formats {

namespace {

constexpr char kMagic[] = "\x93NUMPY";
constexpr std::size_t kMagicSize = 6;
constexpr std::size_t kMaxHeaderBytes = 1 << 16; // numpy itself refuses longer dictionaries

// Cursor over the header dictionary, a Python literal such as
// {'descr': '<f4', 'fortran_order': True, 'shape': (3, 4, 5), }
class DictParser {
public:
    DictParser(const std::string& text, const std::string& where) : text_(text), where_(where) {}

    NpyHeader parse() {
        NpyHeader header;
        bool haveDescr = false, haveOrder = false, haveShape = false;
        expect('{');
        while (!peek('}')) {
            const std::string key = stringLiteral();
            expect(':');
            if (key == "descr") {
                header.descr = stringLiteral();
                haveDescr = true;
            } else if (key == "fortran_order") {
                header.fortranOrder = boolean();
                haveOrder = true;
            } else if (key == "shape") {
                header.shape = tuple();
                haveShape = true;
            } else {
                fail("unexpected key '" + printable(key) + "' in the header");
            }
            if (!peek('}')) expect(',');
        }
        expect('}');
        skipSpace();
        if (pos_ != text_.size()) fail("unexpected text after the header dictionary");
        if (!haveDescr || !haveOrder || !haveShape) fail("the header lacks 'descr', 'fortran_order' or 'shape'");
        return header;
    }

private:
    void skipSpace() {
        while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\n')) ++pos_;
    }
    bool peek(char c) {
        skipSpace();
        return pos_ < text_.size() && text_[pos_] == c;
    }
    void expect(char c) {
        if (!peek(c)) fail(std::string("malformed header: expected '") + c + "'");
        ++pos_;
    }
    std::string stringLiteral() {
        skipSpace();
        if (pos_ >= text_.size() || (text_[pos_] != '\'' && text_[pos_] != '"')) fail("malformed header: expected a string");
        const char quote = text_[pos_++];
        const std::size_t end = text_.find(quote, pos_);
        if (end == std::string::npos) fail("malformed header: unterminated string");
        std::string s = text_.substr(pos_, end - pos_);
        if (s.find('\\') != std::string::npos) fail("malformed header: escapes in a string");
        pos_ = end + 1;
        return s;
    }
    bool boolean() {
        skipSpace();
        if (text_.compare(pos_, 4, "True") == 0) {
            pos_ += 4;
            return true;
        }
        if (text_.compare(pos_, 5, "False") == 0) {
            pos_ += 5;
            return false;
        }
        fail("malformed header: 'fortran_order' is not True or False");
    }
    std::vector<std::uint64_t> tuple() {
        std::vector<std::uint64_t> values;
        expect('(');
        while (!peek(')')) {
            std::uint64_t value = 0;
            std::size_t digits = 0;
            while (pos_ < text_.size() && text_[pos_] >= '0' && text_[pos_] <= '9') {
                if (value > (std::numeric_limits<std::uint64_t>::max() - 9) / 10) fail("a dimension in 'shape' is too large");
                value = value * 10 + std::uint64_t(text_[pos_++] - '0');
                ++digits;
            }
            if (digits == 0) fail("malformed header: 'shape' is not a tuple of non-negative integers");
            values.push_back(value);
            if (!peek(')')) expect(',');
        }
        expect(')');
        return values;
    }
    [[noreturn]] void fail(const std::string& problem) const { throw Error(where_ + ": " + problem); }

    const std::string& text_;
    const std::string& where_;
    std::size_t pos_ = 0;
};

std::string shapeText(const std::vector<std::uint64_t>& shape) {
    std::string text = "(";
    for (std::size_t i = 0; i < shape.size(); ++i) text += (i ? ", " : "") + std::to_string(shape[i]);
    return text + (shape.size() == 1 ? ",)" : ")");
}

// UTF-8 to code points for numpy's '<U' strings. A byte that is not part of valid UTF-8 becomes
// U+DC00 + byte (Python's "surrogateescape"), so any file name survives the round trip.
std::u32string decodeUtf8(const std::string& s) {
    std::u32string out;
    for (std::size_t i = 0; i < s.size();) {
        const unsigned char c = static_cast<unsigned char>(s[i]);
        const int length = c < 0x80 ? 1 : (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : (c >> 3) == 30 ? 4 : 0;
        char32_t code = length == 1 ? c : length == 2 ? (c & 0x1F) : length == 3 ? (c & 0x0F) : (c & 0x07);
        bool valid = length > 0 && i + std::size_t(length) <= s.size();
        for (int k = 1; valid && k < length; ++k) {
            const unsigned char next = static_cast<unsigned char>(s[i + std::size_t(k)]);
            valid = (next >> 6) == 2;
            code = (code << 6) | (next & 0x3F);
        }
        // Overlong forms, surrogates and values past U+10FFFF are not valid UTF-8 either.
        static constexpr char32_t kMinimum[5] = {0, 0, 0x80, 0x800, 0x10000};
        valid = valid && code >= kMinimum[length] && code <= 0x10FFFF && !(code >= 0xD800 && code <= 0xDFFF);
        if (valid) {
            out += code;
            i += std::size_t(length);
        } else {
            out += char32_t(0xDC00 + c);
            ++i;
        }
    }
    return out;
}

std::string encodeUtf8(const std::u32string& s, const std::string& where) {
    std::string out;
    for (const char32_t code : s) {
        if (code >= 0xDC80 && code <= 0xDCFF) {
            out += char(code - 0xDC00); // an escaped byte (see decodeUtf8)
        } else if (code < 0x80) {
            out += char(code);
        } else if (code < 0x800) {
            out += char(0xC0 | (code >> 6));
            out += char(0x80 | (code & 0x3F));
        } else if (code < 0x10000 && !(code >= 0xD800 && code <= 0xDFFF)) {
            out += char(0xE0 | (code >> 12));
            out += char(0x80 | ((code >> 6) & 0x3F));
            out += char(0x80 | (code & 0x3F));
        } else if (code >= 0x10000 && code <= 0x10FFFF) {
            out += char(0xF0 | (code >> 18));
            out += char(0x80 | ((code >> 12) & 0x3F));
            out += char(0x80 | ((code >> 6) & 0x3F));
            out += char(0x80 | (code & 0x3F));
        } else {
            throw Error(where + ": string holds an invalid character");
        }
    }
    return out;
}

ReadBytes memoryReader(const std::string& bytes, std::size_t& pos) {
    return [&bytes, &pos](void* data, std::size_t size) {
        const std::size_t n = std::min(size, bytes.size() - pos);
        std::memcpy(data, bytes.data() + pos, n);
        pos += n;
        return n;
    };
}

} // namespace

std::uint64_t NpyHeader::count(const std::string& where) const {
    std::uint64_t n = 1;
    for (const std::uint64_t d : shape) {
        if (d != 0 && n > std::numeric_limits<std::uint64_t>::max() / d) throw Error(where + ": shape " + shapeText(shape) + " is too large");
        n *= d;
    }
    return n;
}

std::uint64_t NpyHeader::dataBytes(const std::string& where) const {
    std::uint64_t bytes = 0;
    if (__builtin_mul_overflow(count(where), std::uint64_t(itemSize()), &bytes)) {
        throw Error(where + ": shape " + shapeText(shape) + " of " + std::to_string(itemSize()) + "-byte items is more than 2^64 bytes");
    }
    return bytes;
}

std::size_t NpyHeader::itemSize() const {
    if (descr.size() < 3) return 0;
    const char kind = descr[1];
    std::size_t digits = 0;
    std::size_t size = 0;
    for (std::size_t i = 2; i < descr.size(); ++i) {
        if (descr[i] < '0' || descr[i] > '9' || ++digits > 6) return 0;
        size = size * 10 + std::size_t(descr[i] - '0');
    }
    if (kind == 'U') return size * 4;
    return kind == 'f' || kind == 'i' || kind == 'u' ? size : 0;
}

std::string npyHeader(const std::string& descr, bool fortranOrder, const std::vector<std::uint64_t>& shape) {
    std::string dict = "{'descr': '" + descr + "', 'fortran_order': " + (fortranOrder ? "True" : "False") +
                       ", 'shape': " + shapeText(shape) + ", }";
    // numpy pads the dictionary with spaces and a final newline so that the data starts on a
    // multiple of 64 bytes (aligned for memory mapping).
    const std::size_t prefix = kMagicSize + 2 + 2;
    dict.append((64 - (prefix + dict.size() + 1) % 64) % 64, ' ');
    dict += '\n';
    std::string header(kMagic, kMagicSize);
    header += '\x01';
    header += '\x00';
    header += char(dict.size() & 0xFF);
    header += char(dict.size() >> 8);
    return header + dict;
}

NpyHeader readNpyHeader(const ReadBytes& read, const std::string& where) {
    unsigned char start[kMagicSize + 2];
    if (read(start, sizeof start) != sizeof start || std::memcmp(start, kMagic, kMagicSize) != 0) {
        throw Error(where + ": not a NumPy .npy file (no \\x93NUMPY magic)");
    }
    const int major = start[kMagicSize];
    if (major < 1 || major > 3) throw Error(where + ": unsupported .npy version " + std::to_string(major));
    // Version 1 has a 2-byte header length, versions 2 and 3 a 4-byte one.
    unsigned char lengthBytes[4] = {0, 0, 0, 0};
    const std::size_t lengthSize = major == 1 ? 2 : 4;
    if (read(lengthBytes, lengthSize) != lengthSize) throw Error(where + ": file ends inside the .npy header");
    const std::size_t length = std::size_t(lengthBytes[0]) | std::size_t(lengthBytes[1]) << 8 |
                               std::size_t(lengthBytes[2]) << 16 | std::size_t(lengthBytes[3]) << 24;
    if (length > kMaxHeaderBytes) throw Error(where + ": .npy header of " + std::to_string(length) + " bytes is too long");
    std::string dict(length, '\0');
    if (read(dict.data(), length) != length) throw Error(where + ": file ends inside the .npy header");
    NpyHeader header = DictParser(dict, where).parse();
    header.headerBytes = kMagicSize + 2 + lengthSize + length;
    return header;
}

void readNpyFieldValues(const NpyHeader& header, const ReadBytes& read, std::uint64_t dataBytes, Field& field,
                        const std::string& where, const RunControl& control) {
    if (header.descr != "<f4") {
        throw Error(where + ": dtype '" + printable(header.descr) + "' is not supported (a field is little-endian float32, '<f4')");
    }
    if (header.shape.size() != 3) {
        throw Error(where + ": shape " + shapeText(header.shape) + " is not 3-dimensional (nx, ny, nz)");
    }
    const std::uint64_t dims[3] = {header.shape[0], header.shape[1], header.shape[2]};
    checkDimsFit(dims, where);
    const std::uint64_t expected = header.dataBytes(where);
    if (dataBytes < expected) {
        throw Error(where + ": file is truncated: shape " + shapeText(header.shape) + " needs " + std::to_string(expected) +
                    " bytes of data, it has " + std::to_string(dataBytes));
    }
    if (dataBytes > expected) {
        throw Error(where + ": " + std::to_string(dataBytes - expected) + " unexpected bytes after the data");
    }
    for (int a = 0; a < 3; ++a) field.grid.dims[a] = int(dims[a]);
    // Read a block at a time into reserved (untouched) memory, so that data that ends before its
    // declared size (a compressed member that lies about it) fails having taken only what it held.
    std::vector<float> data;
    try {
        data.reserve(field.grid.sampleCount());
    } catch (const std::bad_alloc&) {
        throw Error(where + ": not enough memory for the " + std::to_string(expected >> 20) + " MiB of data its header declares");
    }
    constexpr std::size_t kBlock = std::size_t(1) << 20; // values
    ReadWatch watch(control, expected);
    while (data.size() < field.grid.sampleCount()) {
        const std::size_t start = data.size();
        const std::size_t n = std::min(kBlock, field.grid.sampleCount() - start);
        data.resize(start + n);
        if (read(data.data() + start, n * sizeof(float)) != n * sizeof(float)) {
            throw Error(where + ": data ends before the " + std::to_string(expected) + " bytes its header declares (truncated or corrupt)");
        }
        watch.advance(n * sizeof(float));
    }
    if (header.fortranOrder) {
        field.values = std::move(data);
    } else {
        // C order: a[i, j, k] is at (i * ny + j) * nz + k.
        const std::size_t nx = dims[0], ny = dims[1], nz = dims[2];
        field.values.resize(data.size());
        for (std::size_t k = 0; k < nz; ++k) {
            for (std::size_t j = 0; j < ny; ++j) {
                for (std::size_t i = 0; i < nx; ++i) field.values[(k * ny + j) * nx + i] = data[(i * ny + j) * nz + k];
            }
        }
    }
    for (std::size_t i = 0; i < field.values.size(); ++i) {
        if (!std::isfinite(field.values[i])) throw Error(where + ": value " + std::to_string(i) + " is not finite");
    }
}

std::string npyFieldHeader(const Field& field) {
    const Grid& g = field.grid;
    return npyHeader("<f4", true, {std::uint64_t(g.dims.x), std::uint64_t(g.dims.y), std::uint64_t(g.dims.z)});
}

std::string npyFloat64Array(const std::vector<double>& values, bool scalar) {
    std::string bytes = npyHeader("<f8", false, scalar ? std::vector<std::uint64_t>{} : std::vector<std::uint64_t>{values.size()});
    bytes.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(double));
    return bytes;
}

std::string npyInt64Array(const std::vector<std::int64_t>& values) {
    std::string bytes = npyHeader("<i8", false, {values.size()});
    bytes.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(std::int64_t));
    return bytes;
}

std::string npyUnicodeScalar(const std::string& utf8) {
    std::u32string text = decodeUtf8(utf8);
    if (text.empty()) text += U'\0'; // numpy has no zero-length string type; it strips trailing NULs
    std::string bytes = npyHeader("<U" + std::to_string(text.size()), false, {});
    for (const char32_t code : text) {
        for (int b = 0; b < 4; ++b) bytes += char((std::uint32_t(code) >> (8 * b)) & 0xFF);
    }
    return bytes;
}

std::vector<double> parseNpyNumbers(const std::string& bytes, const std::string& where) {
    std::size_t pos = 0;
    const NpyHeader header = readNpyHeader(memoryReader(bytes, pos), where);
    const std::uint64_t count = header.count(where);
    const std::size_t item = header.itemSize();
    const bool isFloat = header.descr == "<f8" || header.descr == "<f4";
    const bool isInt = header.descr == "<i8" || header.descr == "<i4";
    if (!isFloat && !isInt) throw Error(where + ": dtype '" + printable(header.descr) + "' is not a little-endian number");
    if (header.shape.size() > 1) throw Error(where + ": shape " + shapeText(header.shape) + " is not a scalar or a vector");
    const std::uint64_t expected = header.dataBytes(where);
    if (bytes.size() - pos != expected) {
        throw Error(where + ": holds " + std::to_string(bytes.size() - pos) + " bytes of data for shape " +
                    shapeText(header.shape) + " (" + std::to_string(expected) + " expected)");
    }
    std::vector<double> values(count);
    for (std::size_t i = 0; i < count; ++i) {
        const char* p = bytes.data() + pos + i * item;
        if (header.descr == "<f8") {
            std::memcpy(&values[i], p, 8);
        } else if (header.descr == "<f4") {
            float f;
            std::memcpy(&f, p, 4);
            values[i] = f;
        } else if (header.descr == "<i8") {
            std::int64_t v;
            std::memcpy(&v, p, 8);
            values[i] = double(v);
        } else {
            std::int32_t v;
            std::memcpy(&v, p, 4);
            values[i] = v;
        }
        if (!std::isfinite(values[i])) throw Error(where + ": value " + std::to_string(i) + " is not finite");
    }
    return values;
}

std::string parseNpyString(const std::string& bytes, const std::string& where) {
    std::size_t pos = 0;
    const NpyHeader header = readNpyHeader(memoryReader(bytes, pos), where);
    if (header.descr.compare(0, 2, "<U") != 0 || header.itemSize() == 0) {
        throw Error(where + ": dtype '" + printable(header.descr) + "' is not a string ('<U')");
    }
    if (!header.shape.empty()) throw Error(where + ": shape " + shapeText(header.shape) + " is not a scalar string");
    if (bytes.size() - pos != header.itemSize()) throw Error(where + ": string data has the wrong length");
    std::u32string text;
    for (std::size_t i = pos; i + 4 <= bytes.size(); i += 4) {
        const char32_t code = char32_t(std::uint8_t(bytes[i])) | char32_t(std::uint8_t(bytes[i + 1])) << 8 |
                              char32_t(std::uint8_t(bytes[i + 2])) << 16 | char32_t(std::uint8_t(bytes[i + 3])) << 24;
        text += code;
    }
    while (!text.empty() && text.back() == U'\0') text.pop_back();
    return encodeUtf8(text, where);
}

namespace {

void saveNpy(const Field& field, const std::string& path, const SaveOptions&) {
    checkField(field, path);
    const std::string header = npyFieldHeader(field);
    writeFileAtomically(path, [&](std::ostream& out) {
        out.write(header.data(), std::streamsize(header.size()));
        out.write(reinterpret_cast<const char*>(field.values.data()), std::streamsize(field.values.size() * sizeof(float)));
    });
}

Field loadNpy(const std::string& path, const RunControl& control) {
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), std::fclose);
    if (!file) throw Error(path + ": cannot open file (" + std::strerror(errno) + ")");
    struct stat info;
    if (fstat(fileno(file.get()), &info) != 0 || !S_ISREG(info.st_mode)) throw Error(path + ": not a regular file");
    const ReadBytes read = [&](void* data, std::size_t size) { return std::fread(data, 1, size, file.get()); };
    const NpyHeader header = readNpyHeader(read, path);
    Field field;
    field.method = "unknown"; // a bare .npy holds only the values: unit voxels at the origin
    readNpyFieldValues(header, read, std::uint64_t(info.st_size) - header.headerBytes, field, path, control);
    checkField(field, path);
    return field;
}

} // namespace

FieldFormat npyFormat() { return {".npy", "NumPy float32 array (nx, ny, nz), values only", false, saveNpy, loadDense<loadNpy>}; }

} // namespace sdfgen::formats
