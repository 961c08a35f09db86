// NRRD (teem's format, read by ParaView, 3D Slicer, ITK): a text header, then the values as raw
// little-endian float32, x fastest. "space origin" is the centre of the first sample and "space
// directions" the voxel edges, so that sample (i, j, k) is at origin + (i + 1/2, j + 1/2, k + 1/2) h.
#include "core/io/formats/format.hpp"
#include "core/io/atomic_file.hpp"
#include "sdfgen/error.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <sys/stat.h>

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "sdfgen's binary field formats assume a little-endian machine"
#endif

namespace sdfgen::formats {

namespace {

constexpr std::size_t kMaxHeaderBytes = 1 << 20;

// The fields of NRRD's specification (format version 5), by the name used here and the other
// spelling the specification allows.
struct FieldName {
    const char* name;
    const char* alias;
};
constexpr FieldName kFields[] = {
    {"dimension", nullptr}, {"type", nullptr}, {"encoding", nullptr}, {"sizes", nullptr}, {"endian", nullptr},
    {"content", nullptr}, {"min", nullptr}, {"max", nullptr}, {"old min", "oldmin"}, {"old max", "oldmax"},
    {"data file", "datafile"}, {"line skip", "lineskip"}, {"byte skip", "byteskip"}, {"number", nullptr},
    {"sample units", "sampleunits"}, {"space", nullptr}, {"space dimension", nullptr}, {"space units", nullptr},
    {"space origin", nullptr}, {"space directions", nullptr}, {"measurement frame", nullptr}, {"spacings", nullptr},
    {"thicknesses", nullptr}, {"axis mins", "axismins"}, {"axis maxs", "axismaxs"}, {"centers", "centerings"},
    {"labels", nullptr}, {"units", nullptr}, {"kinds", nullptr}, {"block size", "blocksize"},
};

std::string number(double v) {
    char text[32];
    const auto result = std::to_chars(text, text + sizeof text, v); // shortest exact round trip
    return std::string(text, result.ptr);
}

// Reads one "x y z" style list of doubles from `text` (separated by spaces, commas or parentheses).
std::vector<double> numbers(const std::string& text, const std::string& path, const std::string& field) {
    std::vector<double> values;
    const char* p = text.data();
    const char* end = p + text.size();
    while (p < end) {
        if (*p == ' ' || *p == ',' || *p == '(' || *p == ')' || *p == '\t') {
            ++p;
            continue;
        }
        double v = 0;
        const auto result = std::from_chars(p, end, v);
        if (result.ec != std::errc() || !std::isfinite(v)) throw Error(path + ": '" + field + "' holds a value that is not a finite number: '" + printable(text) + "'");
        values.push_back(v);
        p = result.ptr;
    }
    return values;
}

void saveNrrd(const Field& field, const std::string& path, const SaveOptions&) {
    checkField(field, path);
    const Grid& g = field.grid;
    const double h = g.voxel;
    std::ostringstream header;
    header << "NRRD0004\n"
           << "# sdfgen signed distance field: negative inside; sample (i,j,k) at space origin + (i,j,k) * voxel\n"
           << "type: float\n"
           << "dimension: 3\n"
           << "space dimension: 3\n"
           << "sizes: " << g.dims.x << ' ' << g.dims.y << ' ' << g.dims.z << '\n'
           << "space directions: (" << number(h) << ",0,0) (0," << number(h) << ",0) (0,0," << number(h) << ")\n"
           << "space origin: (" << number(double(g.origin.x) + 0.5 * h) << ',' << number(double(g.origin.y) + 0.5 * h) << ','
           << number(double(g.origin.z) + 0.5 * h) << ")\n"
           << "kinds: domain domain domain\n"
           << "endian: little\n"
           << "encoding: raw\n"
           << "sdfgen_origin:=" << number(double(g.origin.x)) << ' ' << number(double(g.origin.y)) << ' ' << number(double(g.origin.z)) << '\n'
           << "sdfgen_voxel:=" << number(h) << '\n'
           << "sdfgen_method:=" << methodLine(field) << '\n'
           << "sdfgen_source:=" << field.source << '\n'
           << '\n';
    const std::string head = header.str();
    writeFileAtomically(path, [&](std::ostream& out) {
        out.write(head.data(), std::streamsize(head.size()));
        out.write(reinterpret_cast<const char*>(field.values.data()), std::streamsize(field.values.size() * sizeof(float)));
    });
}

// An NRRD header: its fields (by canonical name) and key/value pairs, and its length in bytes.
struct NrrdHeader {
    std::string path;
    std::map<std::string, std::string> fields;    // "field: value", by canonical name
    std::map<std::string, std::string> keyValues; // "key:=value"
    std::size_t bytes = 0;

    const std::string& require(const char* name) const {
        const auto it = fields.find(name);
        if (it == fields.end()) throw Error(path + ": the NRRD header has no '" + name + "' (sdfgen reads 3D grids with 'space directions')");
        return it->second;
    }
    // The field's value, one of `accepted` (the first named as what sdfgen reads).
    const std::string& requireValue(const char* name, std::initializer_list<const char*> accepted) const {
        const std::string& value = require(name);
        for (const char* ok : accepted) {
            if (value == ok) return value;
        }
        throw Error(path + ": NRRD " + name + " '" + printable(value) + "' is not supported (sdfgen reads " + *accepted.begin() + ")");
    }
};

// The header: lines up to the first empty one. Each field and key may appear once (NRRD's rule);
// a field's other spelling counts as the same field.
NrrdHeader readNrrdHeader(std::FILE* file, const std::string& path) {
    NrrdHeader header;
    header.path = path;
    std::map<std::string, std::string>& fields = header.fields;
    std::map<std::string, std::string>& keyValues = header.keyValues;
    std::size_t& headerBytes = header.bytes;
    std::string line;
    std::size_t lineNumber = 0;
    for (;;) {
        line.clear();
        int c;
        while ((c = std::fgetc(file)) != EOF && c != '\n') {
            line += char(c);
            if (++headerBytes > kMaxHeaderBytes) throw Error(path + ": no end of the NRRD header in the first MiB");
        }
        if (c == EOF) throw Error(path + ": file ends inside the NRRD header" + (lineNumber ? "" : " (not an NRRD file)"));
        ++headerBytes;
        ++lineNumber;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (lineNumber == 1) {
            if (line.size() != 8 || line.compare(0, 7, "NRRD000") != 0 || line[7] < '1' || line[7] > '5') {
                throw Error(path + ": not an NRRD file (first line '" + printable(line, 40) + "')");
            }
            continue;
        }
        if (line.empty()) break;
        if (line[0] == '#') continue;
        const std::string where = path + ":" + std::to_string(lineNumber);
        const std::size_t keyValue = line.find(":=");
        const std::size_t colon = line.find(": ");
        if (keyValue != std::string::npos && (colon == std::string::npos || keyValue < colon)) {
            const std::string key = line.substr(0, keyValue);
            if (!keyValues.emplace(key, line.substr(keyValue + 2)).second) {
                throw Error(where + ": key '" + printable(key) + "' appears twice in the NRRD header");
            }
        } else if (colon != std::string::npos) {
            const std::string name = line.substr(0, colon);
            const auto known = std::find_if(std::begin(kFields), std::end(kFields), [&](const FieldName& f) {
                return name == f.name || (f.alias && name == f.alias);
            });
            if (known == std::end(kFields)) throw Error(where + ": '" + printable(name) + "' is not an NRRD field");
            if (!fields.emplace(known->name, line.substr(colon + 2)).second) {
                throw Error(where + ": field '" + known->name + "' appears twice in the NRRD header");
            }
        } else {
            throw Error(where + ": not an NRRD header line: '" + printable(line, 40) + "'");
        }
    }
    return header;
}

// The fields sdfgen reads an NRRD by, checked: one raw float per sample of a 3D grid placed by
// 'space directions'. Returns whether the data is big-endian.
bool checkNrrdFields(const NrrdHeader& header) {
    const std::string& path = header.path;
    const std::map<std::string, std::string>& fields = header.fields;
    header.requireValue("type", {"float"});
    header.requireValue("dimension", {"3"});
    header.requireValue("encoding", {"raw"});
    const bool bigEndian = header.requireValue("endian", {"little", "big"}) == "big";
    if (fields.count("data file")) throw Error(path + ": detached NRRD data files are not supported");
    for (const char* unsupported : {"line skip", "byte skip"}) {
        const auto it = fields.find(unsupported);
        if (it != fields.end() && it->second != "0") throw Error(path + ": NRRD '" + unsupported + "' is not supported");
    }
    // The grid is placed by 'space directions' and 'space origin'; the per-axis alternatives
    // would contradict them.
    for (const char* conflicting : {"spacings", "axis mins", "axis maxs"}) {
        if (fields.count(conflicting)) {
            throw Error(path + ": NRRD '" + conflicting + "' is not supported (sdfgen places the grid by 'space directions')");
        }
    }
    if (fields.count("block size")) throw Error(path + ": NRRD 'block size' applies to type block, not float");
    if (fields.count("space") && fields.count("space dimension")) {
        throw Error(path + ": the NRRD header gives both 'space' and 'space dimension' (NRRD allows one)");
    }
    if (const auto space = fields.find("space"); space != fields.end()) {
        static const char* const kSpaces3D[] = {"right-anterior-superior", "RAS", "left-anterior-superior", "LAS",
                                                "left-posterior-superior", "LPS", "scanner-xyz", "3D-right-handed",
                                                "3D-left-handed"};
        if (std::find(std::begin(kSpaces3D), std::end(kSpaces3D), space->second) == std::end(kSpaces3D)) {
            throw Error(path + ": NRRD space '" + printable(space->second) + "' is not a 3D space (sdfgen reads 3D grids)");
        }
    } else {
        header.requireValue("space dimension", {"3"});
    }
    // A field is one scalar per sample: every axis is a domain axis (NRRD's kinds domain and space,
    // or none given). A range kind (RGB-color, vector, list, ...) would make an axis components.
    if (const auto kinds = fields.find("kinds"); kinds != fields.end()) {
        std::istringstream words(kinds->second);
        std::string kind;
        int axes = 0;
        while (words >> kind) {
            if (kind != "domain" && kind != "space" && kind != "???" && kind != "none") {
                throw Error(path + ": NRRD kind '" + printable(kind) + "' on axis " + std::to_string(axes) +
                            " is not a spatial axis (sdfgen reads a scalar per sample: kinds domain or space)");
            }
            ++axes;
        }
        if (axes != 3) throw Error(path + ": NRRD 'kinds' has " + std::to_string(axes) + " entries for 3 axes");
    }
    return bigEndian;
}

// The grid the header places (sdfgen's exact origin and voxel when its keys give them), and the
// method and source it names, into `field`.
void readNrrdGrid(const NrrdHeader& header, Field& field) {
    const std::string& path = header.path;
    const std::map<std::string, std::string>& keyValues = header.keyValues;
    const std::vector<double> sizes = numbers(header.require("sizes"), path, "sizes");
    if (sizes.size() != 3) throw Error(path + ": 'sizes' does not have 3 values");
    std::uint64_t dims[3];
    for (int a = 0; a < 3; ++a) {
        if (!(sizes[std::size_t(a)] >= 1) || sizes[std::size_t(a)] != std::floor(sizes[std::size_t(a)]) || sizes[std::size_t(a)] > 0x1p62) {
            throw Error(path + ": 'sizes' must be positive integers");
        }
        dims[a] = std::uint64_t(sizes[std::size_t(a)]);
    }
    checkDimsFit(dims, path);

    const std::vector<double> directions = numbers(header.require("space directions"), path, "space directions");
    if (directions.size() != 9) throw Error(path + ": 'space directions' does not hold 3 vectors of 3");
    const double h = directions[0];
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
            if (directions[std::size_t(3 * r + c)] != (r == c ? h : 0.0)) {
                throw Error(path + ": 'space directions' is not an axis-aligned grid of cubic voxels (sdfgen grids are)");
            }
        }
    }
    if (!(h > 0)) throw Error(path + ": voxel size in 'space directions' must be positive");
    const std::vector<double> firstSample = numbers(header.require("space origin"), path, "space origin");
    if (firstSample.size() != 3) throw Error(path + ": 'space origin' does not have 3 values");

    for (int a = 0; a < 3; ++a) field.grid.dims[a] = int(dims[a]);
    field.grid.voxel = h;
    // sdfgen's own exact origin and voxel when present (the centre form adds a rounding step).
    const auto exactOrigin = keyValues.find("sdfgen_origin");
    const auto exactVoxel = keyValues.find("sdfgen_voxel");
    std::vector<double> origin(3);
    for (int a = 0; a < 3; ++a) origin[std::size_t(a)] = firstSample[std::size_t(a)] - 0.5 * h;
    if (exactOrigin != keyValues.end() && exactVoxel != keyValues.end()) {
        origin = numbers(exactOrigin->second, path, "sdfgen_origin");
        const std::vector<double> voxel = numbers(exactVoxel->second, path, "sdfgen_voxel");
        if (origin.size() != 3 || voxel.size() != 1 || !(voxel[0] > 0)) throw Error(path + ": malformed 'sdfgen_origin' or 'sdfgen_voxel'");
        if (std::fabs(voxel[0] - h) > 1e-9 * h) throw Error(path + ": 'sdfgen_voxel' does not match 'space directions'");
        for (int a = 0; a < 3; ++a) {
            if (std::fabs(origin[std::size_t(a)] + 0.5 * h - firstSample[std::size_t(a)]) > 1e-6 * h) {
                throw Error(path + ": 'sdfgen_origin' does not match 'space origin'");
            }
        }
        field.grid.voxel = voxel[0];
    }
    for (int a = 0; a < 3; ++a) field.grid.origin[a] = origin[std::size_t(a)];
    checkGrid(field.grid, path);
    field.method = "unknown";
    if (const auto it = keyValues.find("sdfgen_method"); it != keyValues.end()) parseMethodLine(it->second, field, path);
    if (const auto it = keyValues.find("sdfgen_source"); it != keyValues.end()) field.source = it->second;
}

Field loadNrrd(const std::string& path, const RunControl& control) {
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), std::fclose);
    if (!file) throw Error(path + ": cannot open file (" + std::strerror(errno) + ")");
    struct stat info;
    if (fstat(fileno(file.get()), &info) != 0 || !S_ISREG(info.st_mode)) throw Error(path + ": not a regular file");
    const NrrdHeader header = readNrrdHeader(file.get(), path);
    const bool bigEndian = checkNrrdFields(header);
    Field field;
    readNrrdGrid(header, field);

    const std::uint64_t expected = std::uint64_t(field.grid.sampleCount()) * sizeof(float);
    const std::uint64_t available = std::uint64_t(info.st_size) - header.bytes;
    if (available < expected) {
        throw Error(path + ": file is truncated: " + std::to_string(expected) + " bytes of data expected, " + std::to_string(available) + " found");
    }
    if (available > expected) throw Error(path + ": " + std::to_string(available - expected) + " unexpected bytes after the data");
    field.values.resize(field.grid.sampleCount());
    // A block at a time, so that the read can report progress and stop at a Cancel.
    ReadWatch watch(control, expected);
    constexpr std::uint64_t kBlock = std::uint64_t(1) << 20;
    for (std::uint64_t done = 0; done < expected;) {
        const std::uint64_t n = std::min(kBlock, expected - done);
        if (std::fread(reinterpret_cast<char*>(field.values.data()) + done, 1, n, file.get()) != n) throw Error(path + ": read error");
        done += n;
        watch.advance(n);
    }
    if (bigEndian) {
        for (float& v : field.values) {
            std::uint32_t bits;
            std::memcpy(&bits, &v, 4);
            bits = __builtin_bswap32(bits);
            std::memcpy(&v, &bits, 4);
        }
    }
    checkField(field, path);
    return field;
}

} // namespace

FieldFormat nrrdFormat() { return {".nrrd", "NRRD raw float32 (ParaView, 3D Slicer, teem)", false, saveNrrd, loadDense<loadNrrd>}; }

} // namespace sdfgen::formats
