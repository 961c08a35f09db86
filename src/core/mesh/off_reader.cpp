// OFF (Object File Format), the text form: a keyword line (OFF, with the C, N and ST prefixes of
// its variants, whose extra per-vertex values are skipped), the counts "V F [E]", V vertex lines
// (x y z first) and F face lines (n, then n vertex indices counted from 0, then anything, such as
// a colour). Polygons are triangulated as a fan around their first corner. # starts a comment.
#include "core/mesh/input_file.hpp"
#include "core/mesh/mesh_readers.hpp"
#include "sdfgen/error.hpp"

#include <charconv>
#include <cstdlib>

namespace sdfgen {

namespace {

// The file's lines without comments, one at a time, split into tokens.
class OffLines {
public:
    OffLines(const std::string& path, std::string_view text) : path_(path), text_(text) {}

    // The next line with a token on it; false at the end of the file.
    bool next() {
        while (pos_ < text_.size()) {
            std::size_t end = pos_;
            while (end < text_.size() && text_[end] != '\n' && text_[end] != '\r') ++end;
            std::string_view line = text_.substr(pos_, end - pos_);
            ++number_;
            pos_ = end;
            if (pos_ < text_.size() && text_[pos_] == '\r') {
                if (++pos_ < text_.size() && text_[pos_] == '\n') ++pos_;
            } else if (pos_ < text_.size()) {
                ++pos_;
            }
            if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
            rest_ = line;
            if (!token().empty()) {
                rest_ = line;
                return true;
            }
        }
        return false;
    }

    // The line's next token (empty at its end).
    std::string_view token() {
        std::size_t i = 0;
        while (i < rest_.size() && (rest_[i] == ' ' || rest_[i] == '\t')) ++i;
        std::size_t j = i;
        while (j < rest_.size() && rest_[j] != ' ' && rest_[j] != '\t') ++j;
        const std::string_view t = rest_.substr(i, j - i);
        rest_.remove_prefix(j);
        return t;
    }

    std::uint64_t count(const char* what) { return count(token(), what); }
    std::uint64_t count(std::string_view t, const char* what) const {
        std::uint64_t value = 0;
        const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
        if (t.empty() || ec != std::errc() || end != t.data() + t.size()) {
            fail(std::string("expected the ") + what + ", a whole number, not '" + printable(t, 40) + "'");
        }
        return value;
    }

    double coordinate() {
        const std::string_view t = token();
        if (t.empty()) fail("a vertex has fewer than 3 coordinates");
        const char* first = t.data();
        const char* last = first + t.size();
        if (*first == '+' && last - first > 1 && first[1] != '-') ++first; // from_chars has no '+'
        double value = 0.0;
        const auto [end, ec] = std::from_chars(first, last, value, std::chars_format::general);
        if (ec == std::errc::result_out_of_range && end == last) {
            value = std::strtod(std::string(t).c_str(), nullptr); // underflow to (nearly) zero; overflow caught later
        } else if (ec != std::errc() || end != last) {
            fail("vertex coordinate '" + printable(t, 40) + "' is not a number");
        }
        if (const std::string problem = coordinateProblem(value, t); !problem.empty()) fail(problem);
        return value;
    }

    std::int64_t index() {
        const std::string_view t = token();
        if (t.empty()) fail("a face has fewer vertex indices than its count says");
        std::int64_t value = 0;
        const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
        if (ec == std::errc::result_out_of_range && end == t.data() + t.size()) {
            fail("face refers to vertex " + printable(t, 40) + ", beyond any vertex count");
        }
        if (ec != std::errc() || end != t.data() + t.size()) fail("vertex index '" + printable(t, 40) + "' is not a whole number");
        return value;
    }

    std::string where() const { return path_ + ":" + std::to_string(number_); }
    [[noreturn]] void fail(const std::string& problem) const { throw Error(where() + ": " + problem); }
    std::uint64_t bytesLeft() const { return text_.size() - pos_; }
    std::uint64_t lineBytesLeft() const { return rest_.size(); }

private:
    const std::string& path_;
    std::string_view text_;
    std::size_t pos_ = 0;
    std::size_t number_ = 0;
    std::string_view rest_;
};

} // namespace

Mesh loadOff(const std::string& path) {
    const std::string content = readInputFile(path, InputKind::Text);
    OffLines lines(path, withoutByteOrderMark(content));
    if (!lines.next()) throw Error(path + ": empty file (an OFF file starts with OFF)");
    const std::string keyword(lines.token());
    const std::size_t off = keyword.rfind("OFF");
    if (off == std::string::npos || off + 3 != keyword.size()) throw Error(path + ": not an OFF file (it does not start with OFF)");
    const std::string prefix = keyword.substr(0, off);
    if (prefix != "" && prefix != "C" && prefix != "N" && prefix != "NC" && prefix != "CN" && prefix != "ST" &&
        prefix != "STC" && prefix != "STN" && prefix != "STCN" && prefix != "STNC") {
        lines.fail("'" + printable(keyword, 40) + "' files (other than 3 coordinates per vertex) are not supported");
    }
    std::string_view word = lines.token();
    if (word == "BINARY") lines.fail("binary OFF files are not supported");
    if (word.empty()) { // the counts on a line of their own, else on the keyword's
        if (!lines.next()) lines.fail("the file ends before the vertex and face counts");
        word = lines.token();
    }
    const std::uint64_t vertexCount = lines.count(word, "vertex count");
    const std::uint64_t faceCount = lines.count("face count");
    // A vertex line takes at least 6 bytes ("0 0 0\n"), a face line 2 ("0\n"), the last one less its newline.
    checkDeclaredCount(path, vertexCount, "vertices", 6, lines.bytesLeft() + 1);
    checkDeclaredCount(path, faceCount, "faces", 2, lines.bytesLeft() + 1 - vertexCount * 6);
    if (vertexCount > 0xffffffffu) throw Error(path + ": " + std::to_string(vertexCount) + " vertices, more than the 2^32 - 1 sdfgen supports");

    std::vector<glm::dvec3> positions(vertexCount);
    for (glm::dvec3& p : positions) {
        if (!lines.next()) throw Error(path + ": the file ends after " + std::to_string(&p - positions.data()) + " of its " + std::to_string(vertexCount) + " vertices");
        for (int axis = 0; axis < 3; ++axis) p[axis] = lines.coordinate();
    }
    std::vector<glm::uvec3> triangles;
    triangles.reserve(faceCount);
    std::vector<std::int64_t> corners;
    std::uint64_t skipped = 0;
    for (std::uint64_t f = 0; f < faceCount; ++f) {
        if (!lines.next()) throw Error(path + ": the file ends after " + std::to_string(f) + " of its " + std::to_string(faceCount) + " faces");
        const std::uint64_t n = lines.count("face's vertex count");
        if (n > lines.lineBytesLeft() / 2 + 1) lines.fail("a face claims " + std::to_string(n) + " vertices, more than its line holds");
        corners.resize(n);
        for (std::int64_t& c : corners) c = lines.index();
        if (!addPolygon(corners, vertexCount, [&] { return lines.where() + ": face"; }, triangles)) ++skipped;
    }
    std::uint64_t extraLines = 0;
    while (lines.next()) ++extraLines;
    Mesh mesh = buildMesh(path, std::move(positions), std::move(triangles));
    if (skipped) mesh.warnings.push_back(skippedFacesWarning(path, skipped));
    if (extraLines) {
        mesh.warnings.push_back(path + ": " + std::to_string(extraLines) + " lines after the " + std::to_string(faceCount) +
                                " faces the header declares were not read");
    }
    return mesh;
}

} // namespace sdfgen
