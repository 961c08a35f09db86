#include "core/memory.hpp"
#include "sdfgen/error.hpp"

#include <glm/geometric.hpp>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>
#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace sdfgen {

namespace {

// A whole number read from the start of a file (e.g. a cgroup limit), or -1.
double readNumber(const char* path) {
    std::ifstream in(path);
    double value = -1;
    if (!(in >> value)) return -1; // also "max": no limit
    return value;
}

std::string mebibytes(double bytes) { return std::to_string(std::llround(std::min(bytes / (1 << 20), 9e18))) + " MiB"; }

} // namespace

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
    const double limit = readNumber("/sys/fs/cgroup/memory.max");
    const double used = readNumber("/sys/fs/cgroup/memory.current");
    if (limit >= 0 && used >= 0) {
        const double room = std::max(0.0, limit - used);
        available = available < 0 ? room : std::min(available, room);
    }
    if (available < 0) return physicalMemoryBytes();
    return std::uint64_t(available);
}

std::uint64_t estimateBakeBytes(const Mesh& mesh, const Grid& grid, const BakeSettings& settings) {
    const double samples = double(grid.dims.x) * double(grid.dims.y) * double(grid.dims.z);
    const double triangles = double(mesh.triangleCount()), vertices = double(mesh.positions.size());
    constexpr double kFloat = 4, kFlag = 1;
    const double result = samples * kFloat; // the field's values

    if (settings.method == DistanceMethod::Brute) return std::uint64_t(result + triangles * 3 * sizeof(glm::dvec3));

    SignMethod sign = settings.sign;
    if (sign == SignMethod::Default) sign = settings.method == DistanceMethod::Rays ? SignMethod::Rays : SignMethod::Auto;

    // MeshTopology (merged positions and vertex normals, per-triangle corners, face normals, edge
    // neighbours, the sorted edge list and the union-find parents while it is built, the merge map).
    const double topology = vertices * (24 + 24 + 4 + 48) + triangles * (12 + 12 + 12 + 48 + 12);
    // Winding: one crossing (16 bytes) per row the surface crosses, plus each row's vector.
    double projected = 0;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const glm::dvec3 a(mesh.vertex(t, 0)), b(mesh.vertex(t, 1)), c(mesh.vertex(t, 2));
        projected += 0.5 * std::fabs(glm::cross(b - a, c - a).x);
    }
    const double h = grid.voxel / mesh.unit; // the positions above are local
    const double rows = double(grid.dims.y) * double(grid.dims.z);
    const double winding = topology + rows * 24 + 16 * (projected / (h * h) + triangles);
    const double pseudonormal = topology;

    // Per-sample buffers alive at the peak besides the field (see bake.cpp). On the CPU, exact
    // distances go straight into the field, signed there by the pseudonormal or negated in place by
    // the winding sign; the ray method's field is its own result when the rays sign it. Otherwise a
    // sign leaves inside flags (and, from the device, the nearest triangles), or a second, ray field.
    double perSample = 0;
    if (settings.method == DistanceMethod::Exact && sign == SignMethod::Rays) perSample = kFloat; // the ray field
    else if (settings.method == DistanceMethod::Rays && sign != SignMethod::Rays) perSample = kFlag;
    else if (settings.method == DistanceMethod::Exact && settings.device == Device::Gpu) perSample = kFlag + 4; // flags, nearest triangles
    double signBytes = 0;
    if (sign == SignMethod::Winding) signBytes = winding;
    else if (sign == SignMethod::Pseudonormal) signBytes = pseudonormal;
    else if (sign == SignMethod::Auto) signBytes = std::max(winding, pseudonormal);
    return std::uint64_t(std::min(result + samples * perSample + signBytes, 1.8e19));
}

void releaseFreedMemory() {
#ifdef __GLIBC__
    malloc_trim(0);
#endif
}

void checkBakeMemory(const Mesh& mesh, const Grid& grid, const BakeSettings& settings) {
    const double needed = double(estimateBakeBytes(mesh, grid, settings));
    const std::uint64_t available = availableMemoryBytes();
    if (available > 0 && needed > double(available)) {
        const SignMethod sign = settings.sign != SignMethod::Default ? settings.sign
                                : settings.method == DistanceMethod::Rays ? SignMethod::Rays
                                : settings.method == DistanceMethod::Brute ? SignMethod::Winding
                                                                            : SignMethod::Auto;
        throw Error("grid " + std::to_string(grid.dims.x) + "x" + std::to_string(grid.dims.y) + "x" + std::to_string(grid.dims.z) +
                    " (method " + toString(settings.method) + ", sign " + toString(sign) + ") needs about " +
                    mebibytes(needed) + " but only " + mebibytes(double(available)) + " of memory is available");
    }
}

} // namespace sdfgen
