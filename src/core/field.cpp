#include "sdfgen/field.hpp"
#include "sdfgen/error.hpp"

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

bool isToken(const std::string& s) {
    return !s.empty() && s.find_first_of(" \t\r\n=") == std::string::npos;
}

// Cursor over the file's lines that turns every problem into "PATH:LINE: problem".
class LineReader {
public:
    LineReader(std::string path, const std::string& text) : path_(std::move(path)), text_(text) {}

    bool atEnd() const { return pos_ >= text_.size(); }
    std::size_t lineNumber() const { return line_; }

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
            fail("expected a '" + std::string(keyword) + " ...' line, found '" + std::string(line.substr(0, 40)) + "'");
        }
        return line.substr(n + 1);
    }

    template <class Number>
    Number number(std::string_view& rest, const char* what) {
        while (!rest.empty() && rest.front() == ' ') rest.remove_prefix(1);
        Number value{};
        const auto [end, ec] = std::from_chars(rest.data(), rest.data() + rest.size(), value);
        if (ec != std::errc() || end == rest.data() || (end != rest.data() + rest.size() && *end != ' ')) {
            fail(std::string(what) + " is not a valid number: '" + std::string(rest.substr(0, rest.find(' '))) + "'");
        }
        if constexpr (std::is_floating_point_v<Number>) {
            if (!std::isfinite(value)) fail(std::string(what) + " is not finite");
        }
        rest.remove_prefix(std::size_t(end - rest.data()));
        return value;
    }

    void endOfLine(std::string_view rest) {
        if (rest.find_first_not_of(' ') != std::string_view::npos) {
            fail("unexpected text at end of line: '" + std::string(rest) + "'");
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

std::string Field::parameter(const std::string& key) const {
    for (const auto& [k, v] : parameters) {
        if (k == key) return v;
    }
    return "";
}

void saveFieldText(const Field& field, const std::string& path) {
    if (field.values.size() != field.grid.sampleCount()) {
        throw Error(path + ": field has " + std::to_string(field.values.size()) + " values for a grid of " +
                    std::to_string(field.grid.sampleCount()));
    }
    if (field.grid.dims.x < 1 || field.grid.dims.y < 1 || field.grid.dims.z < 1) throw Error(path + ": grid has no samples");
    if (!(field.grid.voxel > 0.0) || !std::isfinite(field.grid.voxel) || !std::isfinite(field.grid.origin.x) ||
        !std::isfinite(field.grid.origin.y) || !std::isfinite(field.grid.origin.z)) {
        throw Error(path + ": grid origin or voxel size is not a finite (positive) number");
    }
    for (std::size_t i = 0; i < field.values.size(); ++i) {
        if (!std::isfinite(field.values[i])) throw Error(path + ": value " + std::to_string(i) + " is not finite");
    }
    if (field.source.find_first_of("\r\n") != std::string::npos) throw Error(path + ": source name has a line break");
    if (!isToken(field.method)) throw Error(path + ": method name '" + field.method + "' is not a single word");
    for (const auto& [key, value] : field.parameters) {
        if (!isToken(key) || !isToken(value)) throw Error(path + ": bad method parameter '" + key + "=" + value + "'");
    }

    std::string tempPath = path + ".tmp-XXXXXX";
    const int fd = mkstemp(tempPath.data());
    if (fd < 0) throw Error(path + ": cannot create a temporary file beside it (" + std::strerror(errno) + ")");
    fchmod(fd, 0644); // mkstemp makes the file private; a saved field is an ordinary document
    FILE* file = fdopen(fd, "wb");
    auto failWith = [&](const char* what) {
        const std::string reason = std::strerror(errno);
        if (file) std::fclose(file); else close(fd);
        std::remove(tempPath.c_str());
        throw Error(path + ": " + what + " (" + reason + ")");
    };
    if (!file) failWith("cannot open temporary file");

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
    bool ok = std::fwrite(head.data(), 1, head.size(), file) == head.size();

    std::string buffer;
    buffer.reserve(1 << 16);
    for (std::size_t i = 0; ok && i < field.values.size(); ++i) {
        buffer += format(field.values[i]);
        buffer += '\n';
        if (buffer.size() > (1 << 16) - 32 || i + 1 == field.values.size()) {
            ok = std::fwrite(buffer.data(), 1, buffer.size(), file) == buffer.size();
            buffer.clear();
        }
    }
    if (!ok || std::fflush(file) != 0 || fsync(fileno(file)) != 0) failWith("write failed");
    if (std::fclose(file) != 0) {
        file = nullptr;
        failWith("write failed");
    }
    file = nullptr;
    if (std::rename(tempPath.c_str(), path.c_str()) != 0) {
        const std::string reason = std::strerror(errno);
        std::remove(tempPath.c_str());
        throw Error(path + ": cannot replace the file (" + reason + ")");
    }
}

Field loadFieldText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open file (" + std::strerror(errno) + ")");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw Error(path + ": read error");

    LineReader reader(path, text);
    Field field;
    {
        std::string_view rest = reader.keyed(kMagic);
        const int version = reader.number<int>(rest, "version");
        reader.endOfLine(rest);
        if (version != kVersion) reader.fail("unsupported version " + std::to_string(version) + " (this build reads 1)");
    }
    field.source = std::string(reader.keyed("source"));
    {
        std::string_view rest = reader.keyed("dims");
        double samples = 1.0;
        for (int a = 0; a < 3; ++a) {
            field.grid.dims[a] = reader.number<int>(rest, "dimension");
            if (field.grid.dims[a] < 1) reader.fail("dimensions must be at least 1");
            samples *= field.grid.dims[a];
        }
        reader.endOfLine(rest);
        const std::uint64_t memory = physicalMemoryBytes();
        if (memory > 0 && samples * sizeof(float) > double(memory)) reader.fail("dimensions too large for this machine");
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
    }
    {
        std::string_view rest = reader.keyed("method");
        std::size_t space = rest.find(' ');
        field.method = std::string(rest.substr(0, space));
        if (!isToken(field.method)) reader.fail("missing method name");
        while (space != std::string_view::npos) {
            rest.remove_prefix(space + 1);
            space = rest.find(' ');
            const std::string_view item = rest.substr(0, space);
            if (item.empty()) continue;
            const std::size_t eq = item.find('=');
            if (eq == std::string_view::npos || eq == 0 || eq + 1 == item.size()) {
                reader.fail("method parameter '" + std::string(item) + "' is not key=value");
            }
            field.parameters.emplace_back(std::string(item.substr(0, eq)), std::string(item.substr(eq + 1)));
        }
    }
    if (reader.next("'values'") != "values") reader.fail("expected the line 'values'");

    const std::size_t count = field.grid.sampleCount();
    field.values.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
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
