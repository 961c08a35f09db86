#include "core/obj_scan.hpp"
#include "sdfgen/error.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
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
        line.fail("vertex coordinate '" + std::string(token) + "' is not a decimal number");
    }
    if (!std::isfinite(value) || std::fabs(value) > double(std::numeric_limits<float>::max())) {
        line.fail("vertex coordinate '" + std::string(token) + "' is not a finite number");
    }
    return value;
}

} // namespace

std::string_view withoutByteOrderMark(std::string_view text) {
    if (text.size() >= 3 && text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
    return text;
}

ObjScan scanObj(const std::string& path, std::string_view text) {
    ObjScan scan;
    // Positive indices may refer forward (resolved once every vertex is known); kept to check at the end.
    struct ForwardReference {
        std::size_t line;
        std::uint64_t index;
    };
    std::vector<ForwardReference> forward;
    const char* p = text.data();
    const char* const end = p + text.size();
    std::size_t lineNumber = 0;
    while (p < end) {
        ++lineNumber;
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

        if (lineEnd - start < 2 || !isBlank(start[1])) continue;
        ObjLine line(path, lineNumber, start + 2, lineEnd);
        if (start[0] == 'v') {
            glm::dvec3 v;
            for (int axis = 0; axis < 3; ++axis) v[axis] = parseCoordinate(line, line.token());
            scan.vertices.push_back(v);
        } else if (start[0] == 'f') {
            const std::uint64_t known = scan.vertices.size();
            std::size_t corners = 0;
            for (std::string_view token = line.token(); !token.empty(); token = line.token(), ++corners) {
                // v, v/vt, v//vn or v/vt/vn: only the vertex index is used.
                const std::string_view vertex = token.substr(0, token.find('/'));
                const bool negative = !vertex.empty() && vertex.front() == '-';
                const std::string_view digits = vertex.substr(negative ? 1 : 0);
                std::uint64_t index = 0;
                const auto [last, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), index);
                if (digits.empty() || last != digits.data() + digits.size() || (ec != std::errc() && ec != std::errc::result_out_of_range)) {
                    line.fail("face vertex '" + std::string(token) + "' is not a whole number");
                }
                if (token.find_first_not_of("0123456789/-") != std::string_view::npos) {
                    line.fail("face vertex '" + std::string(token) + "' is not of the form v, v/vt, v//vn or v/vt/vn");
                }
                if (ec == std::errc::result_out_of_range || index > std::uint64_t(std::numeric_limits<int>::max())) {
                    line.fail("face refers to vertex " + std::string(vertex) + ", beyond any vertex count this reader supports");
                }
                if (index == 0) line.fail("face vertex index is zero (OBJ counts vertices from 1)");
                if (negative && index > known) {
                    line.fail("face refers to vertex " + std::string(vertex) + " but only " + std::to_string(known) +
                              " vertices precede it");
                }
                if (!negative && index > known) forward.push_back({lineNumber, index});
            }
            if (corners < 3) {
                line.fail("face has " + std::to_string(corners) + (corners == 1 ? " vertex" : " vertices") +
                          " (a face needs at least 3)");
            }
            ++scan.faces;
        }
    }
    for (const ForwardReference& ref : forward) {
        if (ref.index > scan.vertices.size()) {
            throw Error(path + ":" + std::to_string(ref.line) + ": face refers to vertex " + std::to_string(ref.index) +
                        " but the file has " + std::to_string(scan.vertices.size()) + " vertices");
        }
    }
    return scan;
}

} // namespace sdfgen
