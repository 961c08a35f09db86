#include "core/runtime/memory.hpp"
#include "core/accel/bvh.hpp"
#include "core/bake/methods.hpp"
#include "core/runtime/parallel.hpp"
#include "sdfgen/error.hpp"

#include <glm/geometric.hpp>
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

// The whole pages within [data, data + bytes), as addresses [begin, end) (empty: end <= begin).
std::pair<std::uintptr_t, std::uintptr_t> wholePages(void* data, std::size_t bytes) {
    const std::uintptr_t page = std::uintptr_t(sysconf(_SC_PAGESIZE));
    return {(std::uintptr_t(data) + page - 1) / page * page, (std::uintptr_t(data) + bytes) / page * page};
}

} // namespace

void populatePages(void* data, std::size_t bytes, const RunControl& control) {
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

std::uint64_t estimateBakeBytes(const Mesh& mesh, const Grid& grid, const BakeSettings& settings, bool onDevice, const Bvh* tree,
                                const RunControl& control) {
    const double samples = double(grid.dims.x) * double(grid.dims.y) * double(grid.dims.z);
    const double triangles = double(mesh.triangleCount()), vertices = double(mesh.positions.size());
    constexpr double kFloat = 4, kFlag = 1;
    // The field's values and the channels asked for (gradient and closest point: three floats each).
    const Channels& channels = settings.channels;
    const double result = samples * (kFloat + (channels.gradient ? 3 * kFloat : 0) + (channels.closest ? 3 * kFloat : 0) +
                                     (channels.triangle ? sizeof(std::int32_t) : 0));
    MemoryTerms terms;
    terms.samples = samples;
    terms.triangles = triangles;

    const DistanceMethodInfo& method = distanceMethod(settings.method);
    if (method.fixedSign) return std::uint64_t(result + method.memory(terms));

    // MeshTopology (merged positions and vertex normals, per-triangle corners, face normals, edge
    // neighbours, the sorted edge list and the union-find parents while it is built, the merge map).
    terms.topology = vertices * (24 + 24 + 4 + 48) + triangles * (12 + 12 + 12 + 48 + 12);
    // Winding: one crossing (16 bytes) per row the surface crosses, plus each row's vector.
    constexpr std::size_t kBlock = std::size_t(1) << 15; // triangles per partial sum
    const std::size_t triangleCount = mesh.triangleCount();
    std::vector<double> partial((triangleCount + kBlock - 1) / kBlock, 0.0);
    parallelFor(partial.size(), quiet(control), [&](std::size_t block) {
        double sum = 0;
        for (std::size_t t = block * kBlock; t < std::min(triangleCount, (block + 1) * kBlock); ++t) {
            if (tree && tree->copies(std::uint32_t(t)) == 0) continue; // a later copy: the scan weighs the first instead
            const glm::dvec3 a(mesh.vertex(t, 0)), b(mesh.vertex(t, 1)), c(mesh.vertex(t, 2));
            sum += 0.5 * std::fabs(glm::cross(b - a, c - a).x);
        }
        partial[block] = sum;
    });
    double projected = 0;
    for (double sum : partial) projected += sum;
    // The trees hold each set of copies once.
    const double uniqueTriangles = double(tree ? tree->triangleCount() : triangleCount);
    const double h = grid.voxel / mesh.unit; // the positions above are local
    const double rows = double(grid.dims.y) * double(grid.dims.z);
    terms.winding = terms.topology + rows * 24 + 16 * (projected / (h * h) + triangles);

    // Before the mesh check, auto may become either of its signs: the estimate takes the larger
    // of each part.
    bool signCastsRays = false, signReadsWide = false, signedInline = false;
    double signBytes = 0, signDeviceBytes = 0;
    for (SignMethod sign : possibleSigns(settings.sign, method.defaultSign)) {
        const SignMethodInfo& info = signMethod(sign);
        signCastsRays = signCastsRays || info.castsRays;
        signReadsWide = signReadsWide || info.readsWideTree;
        signedInline = signedInline || sign == method.signsInline;
        signBytes = std::max(signBytes, info.memory(terms));
        if (info.deviceMemory) signDeviceBytes = std::max(signDeviceBytes, info.deviceMemory(terms));
    }

    // Per-sample buffers alive at the peak besides the field (see bake.cpp). A method that signs as
    // it measures writes the signed field alone, and exact distances signed by the winding number
    // are negated in place. Otherwise a sign leaves inside flags, or a second, ray field.
    double perSample = 0;
    // The ray field's own tree (core/accel/ray_tree.hpp): each triangle prepared again (36 bytes), a
    // 36-byte record per binary leaf and the 256-byte wide nodes; 95 to 111 bytes per triangle
    // measured on the bundled, shared and generated meshes.
    const double rayTree = method.castsRays || signCastsRays ? triangles * 120 : 0;
    // The closest-point tree (core/accel/wide_bvh.hpp): 99 to 119 bytes per triangle measured on the
    // bundled, shared and generated meshes, and its packets' triangle lists while it is built.
    const bool closestPoints = (method.readsWideTree && !onDevice) || signReadsWide;
    const double wideTree = closestPoints ? uniqueTriangles * 130 : 0;
    if (!signedInline && signCastsRays) perSample = kFloat; // the ray field
    else if (!signedInline && method.castsRays) perSample = kFlag;

    // On a compute device, one pass at a time holds its host-side tables: the distance pass's or
    // the sign pass's (the registries' deviceMemory).
    if (onDevice && method.deviceMemory) signBytes += std::max(method.deviceMemory(terms, signedInline), signDeviceBytes);
    return std::uint64_t(std::min(result + samples * perSample + signBytes + rayTree + wideTree, 1.8e19));
}

void releaseFreedMemory() {
#ifdef __GLIBC__
    malloc_trim(0);
#endif
}

void checkBakeMemory(const Mesh& mesh, const Bvh& tree, const Grid& grid, const BakeSettings& settings, bool onDevice,
                     const RunControl& control) {
    const double needed = double(estimateBakeBytes(mesh, grid, settings, onDevice, &tree, control));
    const std::uint64_t available = availableMemoryBytes();
    if (available > 0 && needed > double(available)) {
        const SignMethod sign = settings.sign != SignMethod::Default ? settings.sign : distanceMethod(settings.method).defaultSign;
        throw Error("grid " + std::to_string(grid.dims.x) + "x" + std::to_string(grid.dims.y) + "x" + std::to_string(grid.dims.z) +
                    " (method " + toString(settings.method) + ", sign " + toString(sign) + ") needs about " +
                    mebibytes(needed) + " but only " + mebibytes(double(available)) + " of memory is available");
    }
}

} // namespace sdfgen
