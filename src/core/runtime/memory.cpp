#include "core/runtime/memory.hpp"
#include "core/runtime/parallel.hpp"
#include "sdfgen/error.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <cmath>
#include <fstream>
#include <string>
#include <sys/mman.h>
#include <unistd.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace sdfgen {

namespace {

// A whole number of bytes at the start of a cgroup file, or nothing (missing, unreadable, or
// "max": no limit).
std::optional<std::uint64_t> readBytes(const std::filesystem::path& path) {
    std::ifstream in(path);
    std::string text;
    if (!(in >> text) || !std::isdigit(static_cast<unsigned char>(text[0]))) return std::nullopt;
    errno = 0;
    char* end = nullptr;
    const unsigned long long value = std::strtoull(text.c_str(), &end, 10);
    if (errno != 0 || *end != '\0') return std::nullopt;
    return std::uint64_t(value);
}

// The whole pages of `page` bytes (the system's by default) within [data, data + bytes), as
// addresses [begin, end) (empty: end <= begin).
std::pair<std::uintptr_t, std::uintptr_t> wholePages(void* data, std::size_t bytes, std::uintptr_t page = std::uintptr_t(sysconf(_SC_PAGESIZE))) {
    return {(std::uintptr_t(data) + page - 1) / page * page, (std::uintptr_t(data) + bytes) / page * page};
}

} // namespace

void adviseHugePages(void* data, std::size_t bytes) {
#ifdef MADV_HUGEPAGE
    if (bytes < kHugePagesFrom) return;
    const auto [begin, end] = wholePages(data, bytes, std::uintptr_t(2) << 20);
    if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
    (void)data, (void)bytes;
#endif
}

void populatePages(void* data, std::size_t bytes, const RunControl& control) {
    adviseHugePages(data, bytes);
#ifdef MADV_POPULATE_WRITE
    const std::pair<std::uintptr_t, std::uintptr_t> pages = wholePages(data, bytes);
    const std::uintptr_t begin = pages.first, end = pages.second; // not a structured binding: the lambda below captures them
    if (end <= begin) return;
    constexpr std::uintptr_t kChunk = std::uintptr_t(32) << 20;
    parallelFor((end - begin + kChunk - 1) / kChunk, control, [&](std::size_t n) {
        const std::uintptr_t from = begin + n * kChunk;
        madvise(reinterpret_cast<void*>(from), std::min(kChunk, end - from), MADV_POPULATE_WRITE); // an old kernel: EINVAL, nothing done
    });
#else
    (void)data, (void)bytes, (void)control;
#endif
}

void releasePages(void* data, std::size_t bytes) {
    const auto [begin, end] = wholePages(data, bytes);
    if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_DONTNEED);
}

std::string mebibytes(double bytes) { return std::to_string(std::llround(std::min(bytes / (1 << 20), 9e18))) + " MiB"; }

CgroupMemory cgroupMemory(const std::string& cgroupFile, const std::string& root) {
    namespace fs = std::filesystem;
    CgroupMemory memory;
    // From the process's own group up to the hierarchy's root: a parent's limit binds its children.
    // Inside a container the listed path may not exist below the mount; its root still does.
    auto walk = [&memory](const fs::path& hierarchy, fs::path group, const char* limitName, const char* usageName) {
        for (;; group = group.parent_path()) {
            const fs::path folder = hierarchy / group.relative_path();
            if (const std::optional<std::uint64_t> limit = readBytes(folder / limitName)) {
                const std::uint64_t used = readBytes(folder / usageName).value_or(0);
                memory.limit = std::min(memory.limit, *limit);
                memory.room = std::min(memory.room, *limit > used ? *limit - used : 0);
            }
            if (group == group.root_path()) break;
        }
    };
    // Each line is ID:CONTROLLERS:PATH: v2's is 0::PATH, v1's memory controller's N:memory:PATH
    // (the list may name several controllers).
    std::ifstream in(cgroupFile);
    std::string line;
    while (std::getline(in, line)) {
        const std::size_t first = line.find(':');
        const std::size_t second = first == std::string::npos ? first : line.find(':', first + 1);
        if (second == std::string::npos) continue;
        const std::string controllers = line.substr(first + 1, second - first - 1);
        const fs::path group = line.substr(second + 1);
        if (!group.is_absolute()) continue;
        if (line.compare(0, first, "0") == 0 && controllers.empty()) {
            const fs::path v2 = fs::exists(fs::path(root) / "cgroup.controllers") ? fs::path(root) : fs::path(root) / "unified";
            walk(v2, group, "memory.max", "memory.current");
            continue;
        }
        for (std::size_t at = 0; at <= controllers.size();) {
            const std::size_t comma = std::min(controllers.find(',', at), controllers.size());
            if (controllers.compare(at, comma - at, "memory") == 0) {
                walk(fs::path(root) / "memory", group, "memory.limit_in_bytes", "memory.usage_in_bytes");
            }
            at = comma + 1;
        }
    }
    return memory;
}

std::uint64_t usableMemoryBytes() {
    const std::uint64_t physical = physicalMemoryBytes();
    const std::uint64_t limit = cgroupMemory().limit;
    if (physical == 0) return limit == UINT64_MAX ? 0 : limit;
    return std::min(physical, limit);
}

std::uint64_t availableMemoryBytes() {
    double available = -1;
    std::ifstream meminfo("/proc/meminfo");
    std::string key;
    double kib = 0;
    while (meminfo >> key >> kib) {
        if (key == "MemAvailable:") {
            available = kib * 1024.0;
            break;
        }
        meminfo.ignore(1 << 10, '\n');
    }
    const std::uint64_t room = cgroupMemory().room;
    if (room != UINT64_MAX) available = available < 0 ? double(room) : std::min(available, double(room));
    if (available < 0) return physicalMemoryBytes();
    return std::uint64_t(available);
}

void releaseFreedMemory() {
#ifdef __GLIBC__
    malloc_trim(0);
#endif
}

} // namespace sdfgen
