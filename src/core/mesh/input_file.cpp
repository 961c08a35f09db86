#include "core/mesh/input_file.hpp"
#include "sdfgen/error.hpp"

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace sdfgen {

namespace {

std::string mebibytes(std::uint64_t bytes) { return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB"; }

[[noreturn]] void tooLarge(const std::string& path, std::uint64_t maxBytes) {
    throw Error(path + ": larger than the input limit of " + mebibytes(maxBytes) +
                " (set SDFGEN_MAX_INPUT_MB to raise it)");
}

} // namespace

std::uint64_t maxInputBytes() {
    if (const char* limit = std::getenv("SDFGEN_MAX_INPUT_MB")) {
        char* end = nullptr;
        const unsigned long long mb = std::strtoull(limit, &end, 10);
        if (end != limit && *end == '\0' && mb > 0 && mb < (1ull << 43)) return std::uint64_t(mb) << 20;
    }
    return std::uint64_t(4) << 30;
}

std::string_view withoutByteOrderMark(std::string_view text) {
    if (text.size() >= 3 && text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
    return text;
}

std::size_t lineNumberAt(const std::string& text, std::size_t offset) {
    std::size_t line = 1;
    for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
        if (text[i] == '\n' || (text[i] == '\r' && (i + 1 >= text.size() || text[i + 1] != '\n'))) ++line;
    }
    return line;
}

std::string readInputFile(const std::string& path, InputKind kind, std::uint64_t maxBytes, const std::function<void(std::size_t)>& onRead) {
    const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw Error(path + ": cannot open file (" + std::strerror(errno) + ")");
    std::string text;
    try {
        struct stat status {};
        if (fstat(fd, &status) != 0) throw Error(path + ": cannot read file (" + std::strerror(errno) + ")");
        if (S_ISDIR(status.st_mode)) throw Error(path + ": is a directory, not a file");
        if (S_ISREG(status.st_mode)) {
            if (std::uint64_t(status.st_size) > maxBytes) tooLarge(path, maxBytes);
            text.reserve(std::size_t(status.st_size));
        }
        char chunk[1 << 16];
        while (true) {
            const ssize_t n = read(fd, chunk, sizeof(chunk));
            if (n < 0 && errno == EINTR) continue;
            if (n < 0) throw Error(path + ": read error (" + std::strerror(errno) + ")");
            if (n == 0) break;
            if (text.size() + std::size_t(n) > maxBytes) tooLarge(path, maxBytes);
            const std::size_t start = text.size();
            text.append(chunk, std::size_t(n));
            if (onRead) onRead(std::size_t(n));
            if (kind == InputKind::Text) {
                if (const void* nul = std::memchr(chunk, '\0', std::size_t(n))) {
                    const std::size_t offset = start + std::size_t(static_cast<const char*>(nul) - chunk);
                    throw Error(path + ":" + std::to_string(lineNumberAt(text, offset)) +
                                ": NUL byte (a text file was expected)");
                }
            }
        }
    } catch (...) {
        close(fd);
        throw;
    }
    close(fd);
    return text;
}

} // namespace sdfgen
