// PLY (Stanford polygon files): ASCII and binary of either byte order, every scalar type under
// both its names, any elements and properties (those not used are skipped). Read: the `vertex`
// element's x, y, z; `face` polygons (vertex_indices or vertex_index), triangulated as a fan around
// their first corner; `tristrips` (vertex_indices, -1 starting a new strip, every second triangle
// of a strip turned so that all face the same way).
#include "core/mesh/input_file.hpp"
#include "core/mesh/mesh_readers.hpp"
#include "sdfgen/error.hpp"

#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>

namespace sdfgen {

namespace {

enum class Type { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

struct TypeName {
    const char* name;
    Type type;
};

const TypeName kTypeNames[] = {
    {"char", Type::Int8},     {"int8", Type::Int8},       {"uchar", Type::UInt8},   {"uint8", Type::UInt8},
    {"short", Type::Int16},   {"int16", Type::Int16},     {"ushort", Type::UInt16}, {"uint16", Type::UInt16},
    {"int", Type::Int32},     {"int32", Type::Int32},     {"uint", Type::UInt32},   {"uint32", Type::UInt32},
    {"float", Type::Float32}, {"float32", Type::Float32}, {"double", Type::Float64}, {"float64", Type::Float64},
};

std::size_t sizeOf(Type type) {
    switch (type) {
    case Type::Int8:
    case Type::UInt8: return 1;
    case Type::Int16:
    case Type::UInt16: return 2;
    case Type::Int32:
    case Type::UInt32:
    case Type::Float32: return 4;
    case Type::Float64: return 8;
    }
    return 0;
}

bool isInteger(Type type) { return type != Type::Float32 && type != Type::Float64; }
bool isSigned(Type type) { return type == Type::Int8 || type == Type::Int16 || type == Type::Int32; }

struct Property {
    std::string name;
    Type type = Type::Float32; // of the value, or of a list's items
    bool list = false;
    Type countType = Type::UInt8;
};

struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::vector<Property> properties;
};

enum class Encoding { Ascii, LittleEndian, BigEndian };

struct Header {
    Encoding encoding = Encoding::Ascii;
    std::vector<Element> elements;
    std::size_t dataStart = 0; // offset of the first byte after end_header's line
};

std::vector<std::string_view> tokens(std::string_view line) {
    std::vector<std::string_view> out;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
        const std::size_t start = i;
        while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
        if (i > start) out.push_back(line.substr(start, i - start));
    }
    return out;
}

Header readHeader(const std::string& path, std::string_view text) {
    Header header;
    std::size_t pos = 0, lineNumber = 0;
    bool format = false;
    const auto fail = [&](const std::string& problem) { throw Error(path + ":" + std::to_string(lineNumber) + ": " + problem); };
    while (true) {
        const std::size_t newline = text.find('\n', pos);
        ++lineNumber;
        if (newline == std::string_view::npos) fail("the header ends without end_header");
        std::string_view line = text.substr(pos, newline - pos);
        pos = newline + 1;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        const std::vector<std::string_view> words = tokens(line);
        if (lineNumber == 1) {
            if (words.size() != 1 || words[0] != "ply") throw Error(path + ": not a PLY file (it does not start with 'ply')");
            continue;
        }
        if (words.empty() || words[0] == "comment" || words[0] == "obj_info") continue;
        const auto typeOf = [&](std::string_view name) {
            for (const TypeName& t : kTypeNames) {
                if (name == t.name) return t.type;
            }
            throw Error(path + ":" + std::to_string(lineNumber) + ": unknown property type '" + printable(name, 40) + "'");
        };
        if (words[0] == "format") {
            if (words.size() != 3 || words[2] != "1.0") fail("expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
            if (words[1] == "ascii") header.encoding = Encoding::Ascii;
            else if (words[1] == "binary_little_endian") header.encoding = Encoding::LittleEndian;
            else if (words[1] == "binary_big_endian") header.encoding = Encoding::BigEndian;
            else fail("unknown format '" + printable(words[1], 40) + "'");
            format = true;
        } else if (words[0] == "element") {
            if (words.size() != 3) fail("expected 'element NAME COUNT'");
            Element element;
            element.name = std::string(words[1]);
            const auto [end, ec] = std::from_chars(words[2].data(), words[2].data() + words[2].size(), element.count);
            if (ec != std::errc() || end != words[2].data() + words[2].size()) {
                fail("element count '" + printable(words[2], 40) + "' is not a whole number below 2^64");
            }
            header.elements.push_back(std::move(element));
        } else if (words[0] == "property") {
            if (header.elements.empty()) fail("a property before any element");
            Property property;
            if (words.size() == 5 && words[1] == "list") {
                property.list = true;
                property.countType = typeOf(words[2]);
                property.type = typeOf(words[3]);
                property.name = std::string(words[4]);
                if (!isInteger(property.countType)) fail("a list's count type must be an integer type");
            } else if (words.size() == 3) {
                property.type = typeOf(words[1]);
                property.name = std::string(words[2]);
            } else {
                fail("expected 'property TYPE NAME' or 'property list COUNT_TYPE TYPE NAME'");
            }
            header.elements.back().properties.push_back(std::move(property));
        } else if (words[0] == "end_header" && words.size() == 1) {
            break;
        } else {
            fail("unknown header line '" + printable(line, 40) + "'");
        }
    }
    if (!format) throw Error(path + ": the header has no format line");
    header.dataStart = pos;
    return header;
}

// Reads the values after the header, one at a time, as doubles (exact for every PLY type).
class DataReader {
public:
    DataReader(const std::string& path, std::string_view text, const Header& header)
        : path_(path), text_(text), pos_(header.dataStart), encoding_(header.encoding) {}

    double value(Type type) {
        return encoding_ == Encoding::Ascii ? asciiValue(type) : binaryValue(type);
    }

    // Skips `count` values of `type` (binary: at once; ASCII: token by token).
    void skip(Type type, std::uint64_t count) {
        if (encoding_ == Encoding::Ascii) {
            for (std::uint64_t i = 0; i < count; ++i) asciiValue(type);
        } else {
            if (count > remaining() / sizeOf(type)) fail("the file ends inside " + where());
            pos_ += std::size_t(count * sizeOf(type));
        }
    }

    // Bytes not read yet.
    std::uint64_t remaining() const { return text_.size() - pos_; }
    // The fewest bytes a value of `type` takes (ASCII: a digit and a separator).
    std::uint64_t minimumBytes(Type type) const { return encoding_ == Encoding::Ascii ? 2 : sizeOf(type); }

    // What a problem message names: "vertex 12 of 100" (`element` null: "the data").
    void at(const Element* element, std::uint64_t index) {
        element_ = element;
        index_ = index;
    }
    std::string where() const {
        if (!element_) return "the data";
        return element_->name + " " + std::to_string(index_ + 1) + " of " + std::to_string(element_->count);
    }
    // Bytes the last value may lack of minimumBytes (an ASCII file's last number needs no separator).
    std::uint64_t slack() const { return encoding_ == Encoding::Ascii ? 1 : 0; }

    [[noreturn]] void fail(const std::string& problem) const {
        if (encoding_ == Encoding::Ascii) {
            throw Error(path_ + ":" + std::to_string(lineNumberAt(std::string(text_.substr(0, pos_)), pos_)) + ": " + problem);
        }
        throw Error(path_ + ": " + problem + " (byte " + std::to_string(pos_) + ")");
    }

    // The bytes after the last element, white space aside (ASCII).
    std::uint64_t trailingBytes() const {
        std::size_t pos = pos_;
        if (encoding_ == Encoding::Ascii) {
            while (pos < text_.size() && std::strchr(" \t\r\n", text_[pos]) && text_[pos] != '\0') ++pos;
        }
        return text_.size() - pos;
    }

private:
    double binaryValue(Type type) {
        const std::size_t size = sizeOf(type);
        if (remaining() < size) fail("the file ends inside " + where());
        unsigned char bytes[8];
        std::memcpy(bytes, text_.data() + pos_, size);
        pos_ += size;
        if (encoding_ == Encoding::BigEndian) {
            for (std::size_t i = 0; i < size / 2; ++i) std::swap(bytes[i], bytes[size - 1 - i]);
        }
        // Little endian now (x86 and ARM Linux are little-endian hosts).
        switch (type) {
        case Type::Int8: return double(std::int8_t(bytes[0]));
        case Type::UInt8: return double(bytes[0]);
        case Type::Int16: { std::int16_t v; std::memcpy(&v, bytes, 2); return double(v); }
        case Type::UInt16: { std::uint16_t v; std::memcpy(&v, bytes, 2); return double(v); }
        case Type::Int32: { std::int32_t v; std::memcpy(&v, bytes, 4); return double(v); }
        case Type::UInt32: { std::uint32_t v; std::memcpy(&v, bytes, 4); return double(v); }
        case Type::Float32: { float v; std::memcpy(&v, bytes, 4); return double(v); }
        case Type::Float64: { double v; std::memcpy(&v, bytes, 8); return v; }
        }
        return 0.0;
    }

    double asciiValue(Type type) {
        while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\t' || text_[pos_] == '\r' || text_[pos_] == '\n')) ++pos_;
        const std::size_t start = pos_;
        while (pos_ < text_.size() && !(text_[pos_] == ' ' || text_[pos_] == '\t' || text_[pos_] == '\r' || text_[pos_] == '\n')) ++pos_;
        if (pos_ == start) fail("the file ends inside " + where());
        const std::string_view token = text_.substr(start, pos_ - start);
        const char* first = token.data();
        const char* last = first + token.size();
        if (*first == '+' && last - first > 1 && first[1] != '-') ++first; // from_chars has no '+'
        if (isInteger(type)) {
            std::int64_t v = 0;
            const auto [end, ec] = std::from_chars(first, last, v);
            const double low = isSigned(type) ? -std::ldexp(1.0, int(8 * sizeOf(type)) - 1) : 0.0;
            const double high = std::ldexp(1.0, int(8 * sizeOf(type)) - (isSigned(type) ? 1 : 0)) - 1.0;
            if (ec != std::errc() || end != last || double(v) < low || double(v) > high) {
                fail("'" + printable(token, 40) + "' in " + where() + " is not a whole number of its type's range");
            }
            return double(v);
        }
        double v = 0.0;
        const auto [end, ec] = std::from_chars(first, last, v, std::chars_format::general);
        if (ec == std::errc::result_out_of_range && end == last) {
            v = std::strtod(std::string(token).c_str(), nullptr); // underflow to (nearly) zero; overflow is caught later
        } else if (ec != std::errc() || end != last) {
            fail("'" + printable(token, 40) + "' in " + where() + " is not a number");
        }
        return v;
    }

    const std::string& path_;
    std::string_view text_;
    std::size_t pos_;
    Encoding encoding_;
    const Element* element_ = nullptr;
    std::uint64_t index_ = 0;
};

// The fewest bytes one instance of `element` takes (its lists empty).
std::uint64_t minimumBytes(const Element& element, const DataReader& data) {
    std::uint64_t bytes = 0;
    for (const Property& p : element.properties) bytes += data.minimumBytes(p.list ? p.countType : p.type);
    return bytes;
}

const Property* findProperty(const Element& element, std::initializer_list<const char*> names, bool list) {
    for (const char* name : names) {
        for (const Property& p : element.properties) {
            if (p.name == name && p.list == list) return &p;
        }
    }
    return nullptr;
}

// Reads one list's items (checked against the bytes left before any are stored); in a strip, an
// unsigned type's largest value reads as -1, the restart of files that store indices unsigned.
void readList(DataReader& data, const Property& p, bool strip, std::vector<std::int64_t>& items) {
    const double count = data.value(p.countType);
    if (count < 0) data.fail("a list in " + data.where() + " has a negative length");
    if (count > 0 && std::uint64_t(count) - 1 > data.remaining() / data.minimumBytes(p.type)) {
        data.fail("a list in " + data.where() + " claims " + std::to_string(std::uint64_t(count)) + " items, more than the file holds");
    }
    items.resize(std::size_t(count));
    for (std::int64_t& item : items) {
        const double v = data.value(p.type); // a whole number of at most 32 bits: p.type is an integer type
        item = strip && !isSigned(p.type) && v == std::ldexp(1.0, int(8 * sizeOf(p.type))) - 1.0 ? -1 : std::int64_t(v);
    }
}

} // namespace

Mesh loadPly(const std::string& path) {
    const std::string content = readInputFile(path, InputKind::Binary);
    const std::string_view text = withoutByteOrderMark(content);
    const Header header = readHeader(path, text);
    DataReader data(path, text, header);

    const Element* vertexElement = nullptr;
    for (const Element& e : header.elements) {
        if (e.name != "vertex") continue;
        // A second would silently replace the first's vertices.
        if (vertexElement) throw Error(path + ": the header declares more than one vertex element");
        vertexElement = &e;
    }
    if (!vertexElement) throw Error(path + ": the file has no vertex element");
    // Every element's declared instances must fit into the bytes after the header, all together.
    std::uint64_t declared = 0;
    for (const Element& e : header.elements) {
        const std::uint64_t each = minimumBytes(e, data);
        const std::string what = e.name == "vertex" ? "vertices" : e.name == "face" ? "faces" : "'" + printable(e.name, 40) + "' elements";
        checkDeclaredCount(path, e.count, what.c_str(), each, data.remaining() + data.slack() - declared);
        declared += e.count * each;
    }
    if (vertexElement->count > std::numeric_limits<std::uint32_t>::max()) {
        throw Error(path + ": " + std::to_string(vertexElement->count) + " vertices, more than the 2^32 - 1 sdfgen supports");
    }
    const std::uint64_t vertexCount = vertexElement->count;
    int axisOf[3] = {-1, -1, -1};
    bool floatCoordinates = true;
    for (int axis = 0; axis < 3; ++axis) {
        const char* name = axis == 0 ? "x" : axis == 1 ? "y" : "z";
        for (std::size_t i = 0; i < vertexElement->properties.size(); ++i) {
            const Property& p = vertexElement->properties[i];
            if (p.name == name && !p.list) {
                axisOf[axis] = int(i);
                floatCoordinates &= p.type == Type::Float32;
            }
        }
        if (axisOf[axis] < 0) throw Error(path + ": the vertex element has no property " + name);
    }

    std::vector<glm::dvec3> positions;
    std::vector<glm::uvec3> triangles;
    std::uint64_t skippedFaces = 0, faceElements = 0;
    std::vector<std::int64_t> items;
    for (const Element& element : header.elements) {
        const bool isVertex = &element == vertexElement;
        const Property* indices = nullptr;
        if (element.name == "face" || element.name == "tristrips") {
            indices = findProperty(element, {"vertex_indices", "vertex_index"}, true);
            if (!indices) throw Error(path + ": the " + element.name + " element has no vertex_indices list");
            if (!isInteger(indices->type)) throw Error(path + ": the " + element.name + " element's vertex indices are not of an integer type");
            ++faceElements;
        }
        if (element.properties.empty()) continue; // takes no bytes, whatever its count
        if (isVertex) positions.resize(std::size_t(element.count));
        if (element.name == "face") triangles.reserve(triangles.size() + std::size_t(element.count));
        for (std::uint64_t i = 0; i < element.count; ++i) {
            data.at(&element, i);
            for (std::size_t k = 0; k < element.properties.size(); ++k) {
                const Property& p = element.properties[k];
                if (isVertex && !p.list) {
                    const double v = data.value(p.type);
                    for (int axis = 0; axis < 3; ++axis) {
                        if (axisOf[axis] != int(k)) continue;
                        if (const std::string problem = coordinateProblem(v); !problem.empty()) data.fail(problem + " in " + data.where());
                        positions[std::size_t(i)][axis] = v;
                    }
                } else if (&p == indices) {
                    readList(data, p, element.name == "tristrips", items);
                    if (element.name == "face") {
                        const auto where = [&] { return path + ": " + data.where(); };
                        if (!addPolygon(items, vertexCount, where, triangles)) ++skippedFaces;
                        continue;
                    }
                    // A strip: triangle k is (k, k+1, k+2), its first two corners swapped for odd k;
                    // -1 ends a strip. Triangles with a repeated corner join strips and are no geometry.
                    std::size_t start = 0;
                    for (std::size_t j = 0; j <= items.size(); ++j) {
                        if (j < items.size() && items[j] != -1) {
                            if (items[j] < 0 || std::uint64_t(items[j]) >= vertexCount) {
                                badVertexIndex(path + ": " + data.where(), items[j], vertexCount);
                            }
                            continue;
                        }
                        for (std::size_t t = start; t + 2 < j; ++t) {
                            glm::uvec3 tri{unsigned(items[t]), unsigned(items[t + 1]), unsigned(items[t + 2])};
                            if ((t - start) % 2 == 1) std::swap(tri.x, tri.y);
                            if (tri.x != tri.y && tri.y != tri.z && tri.x != tri.z) triangles.push_back(tri);
                        }
                        start = j + 1;
                    }
                } else if (p.list) {
                    const double count = data.value(p.countType);
                    if (count < 0) data.fail("a list in " + data.where() + " has a negative length");
                    data.skip(p.type, std::uint64_t(count));
                } else {
                    data.skip(p.type, 1);
                }
            }
        }
    }
    data.at(nullptr, 0);
    if (faceElements == 0) throw Error(path + ": the file has no face or tristrips element (only points)");
    std::vector<std::string> warnings;
    if (const std::uint64_t extra = data.trailingBytes()) {
        warnings.push_back(path + ": " + std::to_string(extra) + " bytes after the elements the header declares were not read");
    }
    if (skippedFaces) warnings.push_back(skippedFacesWarning(path, skippedFaces));
    Mesh mesh = floatCoordinates
                    ? buildMesh(path, std::vector<glm::vec3>(positions.begin(), positions.end()), std::move(triangles))
                    : buildMesh(path, std::move(positions), std::move(triangles));
    mesh.warnings.insert(mesh.warnings.end(), warnings.begin(), warnings.end());
    return mesh;
}

} // namespace sdfgen
