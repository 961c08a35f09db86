// STL, binary and ASCII. A file is binary when its size is what its triangle count (bytes 80-83)
// says, 84 + 50 per triangle, as every binary writer makes it; otherwise it must be ASCII text
// starting with `solid`. Corners at the same position become one vertex, so that the facets form
// a connected mesh (the file stores each facet's corners on their own).
#include "core/mesh/input_file.hpp"
#include "core/mesh/mesh_readers.hpp"
#include "sdfgen/error.hpp"

#include <cctype>
#include <charconv>
#include <cstdlib>
#include <cstring>
#include <unordered_map>

namespace sdfgen {

namespace {

// Indices of positions, one per distinct position (-0 and +0 are the same), in order of first use.
template <class Vec>
class Welder {
public:
    explicit Welder(std::size_t corners) { index_.reserve(corners); }

    unsigned add(Vec p) {
        p += Vec(0); // -0 becomes +0
        const auto [it, added] = index_.try_emplace(p, unsigned(positions.size()));
        if (added) positions.push_back(p);
        return it->second;
    }

    std::vector<Vec> positions;

private:
    struct Hash {
        std::size_t operator()(const Vec& p) const {
            std::size_t h = 0;
            for (int axis = 0; axis < 3; ++axis) {
                typename Vec::value_type v = p[axis];
                std::uint64_t bits = 0;
                std::memcpy(&bits, &v, sizeof v);
                h = (h ^ bits) * 0x100000001b3ull + (h >> 29);
            }
            return h;
        }
    };
    std::unordered_map<Vec, unsigned, Hash> index_;
};

Mesh loadBinary(const std::string& path, std::string_view data, std::uint32_t count) {
    Welder<glm::vec3> welder(std::size_t(count) * 3);
    std::vector<glm::uvec3> triangles(count);
    for (std::uint32_t t = 0; t < count; ++t) {
        const char* facet = data.data() + 84 + std::size_t(t) * 50 + 12; // past the normal
        for (int c = 0; c < 3; ++c) {
            float xyz[3];
            std::memcpy(xyz, facet + 12 * c, sizeof xyz); // little-endian, as the host
            triangles[t][c] = welder.add(glm::vec3(xyz[0], xyz[1], xyz[2]));
        }
    }
    return buildMesh(path, welder.positions, std::move(triangles));
}

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }

// The words of ASCII STL text, with the line each is on.
class StlWords {
public:
    StlWords(const std::string& path, std::string_view text) : path_(path), text_(text) {}

    // The next word, empty at the end of the file.
    std::string_view next() {
        while (pos_ < text_.size() && isSpace(text_[pos_])) {
            if (text_[pos_] == '\n' || (text_[pos_] == '\r' && (pos_ + 1 >= text_.size() || text_[pos_ + 1] != '\n'))) ++line_;
            ++pos_;
        }
        const std::size_t start = pos_;
        while (pos_ < text_.size() && !isSpace(text_[pos_])) ++pos_;
        return text_.substr(start, pos_ - start);
    }

    // Skips the rest of the line (a solid's name).
    void skipLine() {
        while (pos_ < text_.size() && text_[pos_] != '\n' && text_[pos_] != '\r') ++pos_;
    }

    // The next word, which must be `keyword` (any case).
    void expect(const char* keyword) {
        const std::string_view word = next();
        if (word.empty()) fail("the file ends where '" + std::string(keyword) + "' was expected");
        if (!is(word, keyword)) fail("expected '" + std::string(keyword) + "', not '" + printable(word, 40) + "'");
    }

    double number() {
        const std::string_view word = next();
        const char* first = word.data();
        const char* last = first + word.size();
        if (first != last && *first == '+' && last - first > 1 && first[1] != '-') ++first; // from_chars has no '+'
        double value = 0.0;
        const auto [end, ec] = std::from_chars(first, last, value, std::chars_format::general);
        if (ec == std::errc::result_out_of_range && end == last && first != last) {
            value = std::strtod(std::string(word).c_str(), nullptr); // underflow to (nearly) zero; overflow caught later
        } else if (word.empty() || ec != std::errc() || end != last) {
            fail(word.empty() ? std::string("the file ends where a number was expected") : "expected a number, not '" + printable(word, 40) + "'");
        }
        return value;
    }

    static bool is(std::string_view word, const char* keyword) {
        const std::size_t n = std::strlen(keyword);
        if (word.size() != n) return false;
        for (std::size_t i = 0; i < n; ++i) {
            if (std::tolower(static_cast<unsigned char>(word[i])) != keyword[i]) return false;
        }
        return true;
    }

    [[noreturn]] void fail(const std::string& problem) const {
        throw Error(path_ + ":" + std::to_string(line_) + ": " + problem);
    }

private:
    const std::string& path_;
    std::string_view text_;
    std::size_t pos_ = 0;
    std::size_t line_ = 1;
};

Mesh loadAscii(const std::string& path, std::string_view text) {
    StlWords words(path, text);
    Welder<glm::dvec3> welder(0);
    std::vector<glm::uvec3> triangles;
    std::string_view word = words.next();
    if (!StlWords::is(word, "solid")) throw Error(path + ": not an STL file (neither binary nor text starting with 'solid')");
    words.skipLine();
    // solid NAME, facets, endsolid NAME; a file may hold several solids.
    while (true) {
        word = words.next();
        if (StlWords::is(word, "endsolid")) {
            words.skipLine();
            word = words.next();
            if (word.empty()) break;
            if (!StlWords::is(word, "solid")) words.fail("expected 'solid' or the end of the file, not '" + printable(word, 40) + "'");
            words.skipLine();
            continue;
        }
        if (!StlWords::is(word, "facet")) {
            words.fail(word.empty() ? std::string("the file ends without 'endsolid'")
                                    : "expected 'facet' or 'endsolid', not '" + printable(word, 40) + "'");
        }
        words.expect("normal");
        for (int i = 0; i < 3; ++i) words.number();
        words.expect("outer");
        words.expect("loop");
        glm::uvec3 triangle(0);
        int corners = 0;
        for (word = words.next(); StlWords::is(word, "vertex"); word = words.next(), ++corners) {
            if (corners == 3) words.fail("a facet has more than 3 vertices (an STL facet has 3)");
            glm::dvec3 p;
            for (int axis = 0; axis < 3; ++axis) {
                p[axis] = words.number();
                if (const std::string problem = coordinateProblem(p[axis]); !problem.empty()) words.fail(problem);
            }
            triangle[corners] = welder.add(p);
        }
        if (corners != 3) words.fail("a facet has " + std::to_string(corners) + " vertices (an STL facet has 3)");
        if (!StlWords::is(word, "endloop")) words.fail("expected 'vertex' or 'endloop', not '" + printable(word, 40) + "'");
        words.expect("endfacet");
        triangles.push_back(triangle);
    }
    return buildMesh(path, std::move(welder.positions), std::move(triangles));
}

} // namespace

Mesh loadStl(const std::string& path) {
    const std::string content = readInputFile(path, InputKind::Binary);
    if (content.size() >= 84) {
        std::uint32_t count = 0;
        std::memcpy(&count, content.data() + 80, 4);
        if (84 + 50 * std::uint64_t(count) == content.size()) return loadBinary(path, content, count);
    }
    const std::string_view ascii = withoutByteOrderMark(content);
    std::size_t start = 0;
    while (start < ascii.size() && isSpace(ascii[start])) ++start;
    const bool text = content.find('\0') == std::string::npos;
    if (text && StlWords::is(ascii.substr(start, 5), "solid")) return loadAscii(path, ascii);
    // Text has no NUL bytes: what does and is not of its declared size is a damaged binary file.
    if (content.size() >= 84 && !text) {
        std::uint32_t count = 0;
        std::memcpy(&count, content.data() + 80, 4);
        throw Error(path + ": a binary STL file declaring " + std::to_string(count) + " triangles has " +
                    std::to_string(84 + 50 * std::uint64_t(count)) + " bytes, this one " + std::to_string(content.size()));
    }
    throw Error(path + ": not an STL file (neither binary nor text starting with 'solid')");
}

} // namespace sdfgen
