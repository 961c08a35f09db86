#include "sdfgen/field.hpp"
#include "sdfgen/error.hpp"
#include "core/io/formats/format.hpp"
#include "core/io/atomic_file.hpp"
#include "core/mesh/input_file.hpp"
#include "core/runtime/memory.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <charconv>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <sys/stat.h>
#include <unistd.h>

namespace sdfgen {

namespace {

constexpr const char* kMagic = "sdfgen-text";
constexpr int kVersion = 1;

// What the method line's words (name, keys, values) may be: the reader splits on ' ' and '='.
bool isToken(std::string_view s) {
    return !s.empty() && s.find_first_of(std::string_view(" \t\r\n=\0", 6)) == std::string_view::npos;
}

// Cursor over the file's lines that turns every problem into "PATH:LINE: problem".
class LineReader {
public:
    LineReader(std::string path, const std::string& text) : path_(std::move(path)), text_(text) {}

    bool atEnd() const { return pos_ >= text_.size(); }
    std::size_t lineNumber() const { return line_; }
    std::size_t bytesLeft() const { return atEnd() ? 0 : text_.size() - pos_; }

    std::string_view next(const char* what) {
        if (atEnd()) fail("file ends where " + std::string(what) + " was expected");
        const std::size_t end = std::min(text_.find('\n', pos_), text_.size());
        std::string_view line(text_.data() + pos_, end - pos_);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        pos_ = end + 1;
        ++line_;
        return line;
    }

    // The rest of a line that must start with `keyword` and a space.
    std::string_view keyed(const char* keyword) {
        std::string_view line = next(("'" + std::string(keyword) + "'").c_str());
        const std::size_t n = std::strlen(keyword);
        if (line.substr(0, n) != keyword || line.size() <= n || line[n] != ' ') {
            fail("expected a '" + std::string(keyword) + " ...' line, found '" + printable(line) + "'");
        }
        return line.substr(n + 1);
    }

    template <class Number>
    Number number(std::string_view& rest, const char* what) {
        while (!rest.empty() && rest.front() == ' ') rest.remove_prefix(1);
        Number value{};
        const auto [end, ec] = std::from_chars(rest.data(), rest.data() + rest.size(), value);
        if (ec != std::errc() || end == rest.data() || (end != rest.data() + rest.size() && *end != ' ')) {
            fail(std::string(what) + " is not a valid number: '" + printable(rest.substr(0, rest.find(' '))) + "'");
        }
        if constexpr (std::is_floating_point_v<Number>) {
            if (!std::isfinite(value)) fail(std::string(what) + " is not finite");
        }
        rest.remove_prefix(std::size_t(end - rest.data()));
        return value;
    }

    void endOfLine(std::string_view rest) {
        if (rest.find_first_not_of(' ') != std::string_view::npos) {
            fail("unexpected text at end of line: '" + printable(rest) + "'");
        }
    }

    [[noreturn]] void fail(const std::string& problem) const {
        throw Error(path_ + ":" + std::to_string(std::max<std::size_t>(line_, 1)) + ": " + problem);
    }

private:
    std::string path_;
    const std::string& text_;
    std::size_t pos_ = 0;
    std::size_t line_ = 0;
};

} // namespace

void saveFieldText(const Field& field, const std::string& path) {
    formats::checkField(field, path);

    char number[64];
    auto format = [&](auto v) {
        // Shortest text that reads back as the identical float or double (values are float; the
        // grid's origin and voxel size are double).
        const auto result = std::to_chars(number, number + sizeof(number), v);
        return std::string_view(number, std::size_t(result.ptr - number));
    };
    std::ostringstream header;
    header << kMagic << ' ' << kVersion << '\n' << "source " << field.source << '\n';
    header << "dims " << field.grid.dims.x << ' ' << field.grid.dims.y << ' ' << field.grid.dims.z << '\n';
    header << "origin " << format(field.grid.origin.x);
    header << ' ' << format(field.grid.origin.y);
    header << ' ' << format(field.grid.origin.z) << '\n';
    header << "voxel " << format(field.grid.voxel) << '\n';
    header << "method " << field.method;
    for (const auto& [key, value] : field.parameters) header << ' ' << key << '=' << value;
    header << "\nvalues\n";
    const std::string head = header.str();

    writeFileAtomically(path, [&](std::ostream& out) {
        out.write(head.data(), std::streamsize(head.size()));
        // Formatting is most of the time (a 256³ field is 13 M numbers): blocks of values are
        // formatted in parallel, a group at a time (a few MB of text), and written in order.
        constexpr std::size_t kBlock = 1 << 14, kGroup = 16;
        const std::size_t count = field.values.size();
        std::vector<std::string> texts(kGroup);
        for (std::size_t start = 0; out && start < count; start += kBlock * kGroup) {
            const std::size_t blocks = std::min(kGroup, (count - start + kBlock - 1) / kBlock);
            tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t b) {
                std::string& text = texts[b];
                text.clear();
                char digits[32];
                for (std::size_t i = start + b * kBlock; i < std::min(count, start + (b + 1) * kBlock); ++i) {
                    char* end = std::to_chars(digits, digits + sizeof(digits) - 1, field.values[i]).ptr;
                    *end++ = '\n';
                    text.append(digits, end);
                }
            });
            for (std::size_t b = 0; out && b < blocks; ++b) out.write(texts[b].data(), std::streamsize(texts[b].size()));
        }
    });
}

Field loadFieldText(const std::string& path, const RunControl& control) {
    std::string text = readInputFile(path, InputKind::Text);
    if (withoutByteOrderMark(text).size() != text.size()) text.erase(0, 3);

    LineReader reader(path, text);
    Field field;
    {
        std::string_view rest = reader.keyed(kMagic);
        const int version = reader.number<int>(rest, "version");
        reader.endOfLine(rest);
        if (version != kVersion) reader.fail("unsupported version " + std::to_string(version) + " (this build reads 1)");
    }
    field.source = std::string(reader.keyed("source"));
    // The writer refuses a line break in the source name, so a CR left inside it is not ours.
    if (field.source.find('\r') != std::string::npos) reader.fail("source name has a carriage return");
    {
        std::string_view rest = reader.keyed("dims");
        double samples = 1.0;
        for (int a = 0; a < 3; ++a) {
            field.grid.dims[a] = reader.number<int>(rest, "dimension");
            if (field.grid.dims[a] < 1) reader.fail("dimensions must be at least 1");
            samples *= field.grid.dims[a];
        }
        reader.endOfLine(rest);
        const std::uint64_t memory = availableMemoryBytes();
        if (memory > 0 && samples * sizeof(float) > double(memory)) {
            reader.fail("dimensions too large: they need " + std::to_string(std::llround(samples * sizeof(float) / 0x1p20)) + " MiB, more than the " +
                        std::to_string(memory >> 20) + " MiB of memory available");
        }
    }
    {
        std::string_view rest = reader.keyed("origin");
        for (int a = 0; a < 3; ++a) field.grid.origin[a] = reader.number<double>(rest, "origin coordinate");
        reader.endOfLine(rest);
    }
    {
        std::string_view rest = reader.keyed("voxel");
        field.grid.voxel = reader.number<double>(rest, "voxel size");
        reader.endOfLine(rest);
        if (!(field.grid.voxel > 0.0)) reader.fail("voxel size must be positive");
        formats::checkGrid(field.grid, path);
    }
    {
        std::string_view rest = reader.keyed("method");
        std::size_t space = rest.find(' ');
        field.method = std::string(rest.substr(0, space));
        if (field.method.empty()) reader.fail("missing method name");
        if (!isToken(field.method)) reader.fail("method name '" + printable(field.method) + "' is not a single word");
        while (space != std::string_view::npos) {
            rest.remove_prefix(space + 1);
            space = rest.find(' ');
            const std::string_view item = rest.substr(0, space);
            if (item.empty()) continue;
            const std::size_t eq = item.find('=');
            if (eq == std::string_view::npos || eq == 0 || eq + 1 == item.size()) {
                reader.fail("method parameter '" + printable(item) + "' is not key=value");
            }
            const std::string_view key = item.substr(0, eq), value = item.substr(eq + 1);
            if (!isToken(key) || !isToken(value)) {
                reader.fail("method parameter '" + printable(item) + "' is not key=value with single words");
            }
            field.parameters.emplace_back(std::string(key), std::string(value));
        }
    }
    if (reader.next("'values'") != "values") reader.fail("expected the line 'values'");

    const std::size_t count = field.grid.sampleCount();
    // Every value takes at least two bytes ("0\n"): a header that promises more than the file
    // holds is refused before any memory is taken for it.
    if (reader.bytesLeft() / 2 < count) {
        const std::size_t lines = std::size_t(std::count(text.end() - std::ptrdiff_t(reader.bytesLeft()), text.end(), '\n'));
        const bool partial = reader.bytesLeft() > 0 && text.back() != '\n';
        throw Error(path + ":" + std::to_string(reader.lineNumber() + lines + partial) + ": file ends after " +
                    std::to_string(lines) + " of " + std::to_string(count) + " values");
    }
    field.values.resize(count);
    ReadWatch watch(control, count);
    constexpr std::size_t kValuesPerCheck = std::size_t(1) << 16;
    for (std::size_t i = 0; i < count; ++i) {
        if (i % kValuesPerCheck == 0) watch.advance(std::min(kValuesPerCheck, count - i));
        if (reader.atEnd()) {
            reader.fail("file ends after " + std::to_string(i) + " of " + std::to_string(count) + " values");
        }
        std::string_view line = reader.next("a value");
        field.values[i] = reader.number<float>(line, "value");
        reader.endOfLine(line);
    }
    if (!reader.atEnd()) {
        reader.next("");
        reader.fail("unexpected content after the last of " + std::to_string(count) + " values");
    }
    // Every line the writer makes ends in a line break: without one the last value may be cut short.
    if (text.back() != '\n') reader.fail("the file ends in the middle of the last value (truncated?)");
    return field;
}

} // namespace sdfgen

namespace sdfgen::formats {

namespace {
void saveText(const Field& field, const std::string& path, const SaveOptions&) { saveFieldText(field, path); }
Field loadText(const std::string& path, const RunControl& control) { return loadFieldText(path, control); }
} // namespace

FieldFormat textFormat() { return {".sdf", "sdfgen text (docs/field-format.md)", false, saveText, loadDense<loadText>}; }

} // namespace sdfgen::formats
