#include "core/mesh/obj_scan.hpp"
#include "core/runtime/printable.hpp"
#include "core/runtime/parallel.hpp"
#include "sdfgen/error.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>

namespace sdfgen {

namespace {

bool isBlank(char c) { return c == ' ' || c == '\t'; }

// One line of the file, for parsing tokens and reporting problems.
class ObjLine {
public:
    ObjLine(const std::string& path, std::size_t number, const char* begin, const char* end)
        : path_(path), number_(number), p_(begin), end_(end) {}

    // The next run of non-blank characters (empty at the end of the line).
    std::string_view token() {
        while (p_ < end_ && isBlank(*p_)) ++p_;
        const char* start = p_;
        while (p_ < end_ && !isBlank(*p_)) ++p_;
        return std::string_view(start, std::size_t(p_ - start));
    }

    [[noreturn]] void fail(const std::string& problem) const {
        throw Error(path_ + ":" + std::to_string(number_) + ": " + problem);
    }

    std::size_t number() const { return number_; }

private:
    const std::string& path_;
    std::size_t number_;
    const char* p_;
    const char* end_;
};

double parseCoordinate(ObjLine& line, std::string_view token) {
    if (token.empty()) line.fail("vertex has fewer than 3 coordinates");
    const char* first = token.data();
    const char* last = first + token.size();
    if (*first == '+' && last - first > 1 && *(first + 1) != '-') ++first; // from_chars has no '+'
    double value = 0.0;
    const auto [end, ec] = std::from_chars(first, last, value, std::chars_format::general);
    if (ec == std::errc::result_out_of_range && end == last) {
        // Underflow reads as (nearly) zero, as it should; overflow is reported below.
        value = std::strtod(std::string(token).c_str(), nullptr);
    } else if (ec != std::errc() || end != last) {
        line.fail("vertex coordinate '" + printable(token, 40) + "' is not a decimal number");
    }
    if (!std::isfinite(value) || std::fabs(value) > double(std::numeric_limits<float>::max())) {
        line.fail("vertex coordinate '" + printable(token, 40) + "' is not a finite number");
    }
    return value;
}

// One line's kind, by its first characters as tinyobjloader tells them apart.
enum class LineKind { Vertex, Face, TinyobjOnly, Other };

LineKind kindOf(const char* start, const char* lineEnd) {
    const std::ptrdiff_t length = lineEnd - start;
    if (length >= 2 && isBlank(start[1])) {
        switch (start[0]) {
        case 'v': return LineKind::Vertex;
        case 'f': return LineKind::Face;
        case 'l': // lines and points: tinyobjloader refuses some that this scan does not read
        case 'p': return LineKind::TinyobjOnly;
        default: return LineKind::Other;
        }
    }
    // Skin weights (tinyobjloader's extension): refused when a joint is negative.
    if (length >= 3 && start[0] == 'v' && start[1] == 'w' && isBlank(start[2])) return LineKind::TinyobjOnly;
    return LineKind::Other;
}

// Calls visit(start, lineEnd, kind) for each line of [p, end), `start` past the leading blanks,
// until visit returns false. Lines end in \n, \r\n or a lone \r.
template <class Visit>
void forEachLine(const char* p, const char* const end, const Visit& visit) {
    while (p < end) {
        const char* lineEnd = p;
        while (lineEnd < end && *lineEnd != '\n' && *lineEnd != '\r') ++lineEnd;
        const char* start = p;
        while (start < lineEnd && isBlank(*start)) ++start;
        p = lineEnd;
        if (p < end && *p == '\r') {
            if (++p < end && *p == '\n') ++p;
        } else if (p < end) {
            ++p;
        }
        if (!visit(start, lineEnd, kindOf(start, lineEnd))) return;
    }
}

// Whether tinyobjloader reads a texture or normal index as written (atoi): an optional '-' and
// 1 to 9 digits, not zero.
bool plainIndex(std::string_view part) {
    if (!part.empty() && part.front() == '-') part.remove_prefix(1);
    if (part.empty() || part.size() > 9) return false;
    bool nonzero = false;
    for (const char c : part) {
        if (c < '0' || c > '9') return false;
        nonzero |= c != '0';
    }
    return nonzero;
}

// Whether what follows a face corner's vertex index ("", "/vt", "//vn" or "/vt/vn") is read by
// tinyobjloader as written.
bool plainCornerTail(std::string_view tail) {
    if (tail.empty()) return true;
    tail.remove_prefix(1); // the '/'
    if (!tail.empty() && tail.front() == '/') return plainIndex(tail.substr(1));
    const std::size_t slash = tail.find('/');
    if (slash == std::string_view::npos) return plainIndex(tail);
    return plainIndex(tail.substr(0, slash)) && plainIndex(tail.substr(slash + 1));
}

// Positive indices may refer forward (resolved once every vertex is known); kept to check at the end.
struct ForwardReference {
    std::size_t line;
    std::uint64_t index;
};

// A piece of the text, split after a \n, with what precedes it (the first pass's counts).
struct Chunk {
    const char* begin = nullptr;
    const char* end = nullptr;
    std::size_t lines = 0, vertices = 0, faces = 0;
    std::size_t firstLine = 0, firstVertex = 0, firstFace = 0; // counts in the chunks before
    std::string error;                                          // the chunk's first problem
    std::vector<ForwardReference> forward;
    bool trianglesOnly = true;
};

// Reads one chunk's vertices and faces into `scan` at the chunk's place (second pass).
void scanChunk(const std::string& path, Chunk& chunk, ObjScan& scan) {
    std::size_t lineNumber = chunk.firstLine;
    std::size_t vertex = chunk.firstVertex, face = chunk.firstFace;
    try {
        forEachLine(chunk.begin, chunk.end, [&](const char* start, const char* lineEnd, LineKind kind) {
            ++lineNumber;
            if (kind == LineKind::TinyobjOnly) chunk.trianglesOnly = false;
            if (kind != LineKind::Vertex && kind != LineKind::Face) return true;
            ObjLine line(path, lineNumber, start + 2, lineEnd);
            if (kind == LineKind::Vertex) {
                glm::dvec3& v = scan.vertices[vertex++];
                for (int axis = 0; axis < 3; ++axis) v[axis] = parseCoordinate(line, line.token());
                return true;
            }
            const std::uint64_t known = vertex;
            std::size_t corners = 0;
            glm::uvec3 triangle(0);
            for (std::string_view token = line.token(); !token.empty(); token = line.token(), ++corners) {
                // v, v/vt, v//vn or v/vt/vn: only the vertex index is used.
                // One look at each character (this loop reads most of a large file).
                std::size_t slash = std::string_view::npos;
                bool plainCharacters = true; // digits, '/' and '-' only
                for (std::size_t i = 0; i < token.size(); ++i) {
                    const char c = token[i];
                    if (c == '/') {
                        if (slash == std::string_view::npos) slash = i;
                    } else if ((c < '0' || c > '9') && c != '-') {
                        plainCharacters = false;
                    }
                }
                const std::string_view vertexPart = token.substr(0, slash);
                const bool negative = !vertexPart.empty() && vertexPart.front() == '-';
                const std::string_view digits = vertexPart.substr(negative ? 1 : 0);
                std::uint64_t index = 0;
                const auto [last, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), index);
                if (digits.empty() || last != digits.data() + digits.size() || (ec != std::errc() && ec != std::errc::result_out_of_range)) {
                    line.fail("face vertex '" + printable(token, 40) + "' is not a whole number");
                }
                if (!plainCharacters) {
                    line.fail("face vertex '" + printable(token, 40) + "' is not of the form v, v/vt, v//vn or v/vt/vn");
                }
                if (ec == std::errc::result_out_of_range || index > std::uint64_t(std::numeric_limits<int>::max())) {
                    line.fail("face refers to vertex " + std::string(vertexPart) + ", beyond any vertex count this reader supports");
                }
                if (index == 0) line.fail("face vertex index is zero (OBJ counts vertices from 1)");
                if (negative && index > known) {
                    line.fail("face refers to vertex " + std::string(vertexPart) + " but only " + std::to_string(known) +
                              " vertices precede it");
                }
                if (!negative && index > known) chunk.forward.push_back({lineNumber, index});
                if (slash != std::string_view::npos && !plainCornerTail(token.substr(slash))) chunk.trianglesOnly = false;
                if (corners < 3) triangle[int(corners)] = unsigned(negative ? known - index : index - 1);
            }
            if (corners < 3) {
                line.fail("face has " + std::to_string(corners) + (corners == 1 ? " vertex" : " vertices") +
                          " (a face needs at least 3)");
            }
            if (corners > 3) chunk.trianglesOnly = false;
            if (chunk.trianglesOnly) scan.triangles[face] = triangle;
            ++face;
            return true;
        });
    } catch (const Error& e) {
        chunk.error = e.what();
    }
}

} // namespace

ObjScan scanObj(const std::string& path, std::string_view text, std::size_t chunkBytes) {
    // Two parallel passes over pieces split after a \n (so that no \r\n is cut): the first counts
    // each piece's lines, vertices and faces, the second reads each piece straight into its place
    // with its true line numbers and vertex counts, so that errors and relative indices read as in
    // one pass. The first problem in the file is the one reported.
    std::vector<Chunk> chunks;
    const char* const end = text.data() + text.size();
    for (const char* p = text.data(); p < end;) {
        const char* split = end;
        if (std::size_t(end - p) > chunkBytes) {
            const void* newline = std::memchr(p + chunkBytes, '\n', std::size_t(end - p) - chunkBytes);
            if (newline) split = static_cast<const char*>(newline) + 1;
        }
        chunks.emplace_back();
        chunks.back().begin = p;
        chunks.back().end = split;
        p = split;
    }
    const RunControl allThreads;
    parallelFor(chunks.size(), allThreads, [&](std::size_t c) {
        Chunk& chunk = chunks[c];
        forEachLine(chunk.begin, chunk.end, [&](const char*, const char*, LineKind kind) {
            ++chunk.lines;
            chunk.vertices += kind == LineKind::Vertex;
            chunk.faces += kind == LineKind::Face;
            return true;
        });
    });
    ObjScan scan;
    for (std::size_t c = 1; c < chunks.size(); ++c) {
        const Chunk& before = chunks[c - 1];
        chunks[c].firstLine = before.firstLine + before.lines;
        chunks[c].firstVertex = before.firstVertex + before.vertices;
        chunks[c].firstFace = before.firstFace + before.faces;
    }
    if (!chunks.empty()) {
        scan.vertices.resize(chunks.back().firstVertex + chunks.back().vertices);
        scan.faces = chunks.back().firstFace + chunks.back().faces;
        scan.triangles.resize(scan.faces);
    }
    parallelFor(chunks.size(), allThreads, [&](std::size_t c) { scanChunk(path, chunks[c], scan); });

    for (const Chunk& chunk : chunks) {
        if (!chunk.error.empty()) throw Error(chunk.error);
    }
    for (const Chunk& chunk : chunks) {
        for (const ForwardReference& ref : chunk.forward) {
            if (ref.index > scan.vertices.size()) {
                throw Error(path + ":" + std::to_string(ref.line) + ": face refers to vertex " + std::to_string(ref.index) +
                            " but the file has " + std::to_string(scan.vertices.size()) + " vertices");
            }
        }
        scan.trianglesOnly &= chunk.trianglesOnly;
    }
    if (!scan.trianglesOnly) std::vector<glm::uvec3>().swap(scan.triangles);
    return scan;
}

} // namespace sdfgen
