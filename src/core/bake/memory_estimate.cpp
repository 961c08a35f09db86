#include "core/bake/memory_estimate.hpp"
#include "core/method/methods.hpp"
#include "core/runtime/memory.hpp"
#include "core/runtime/parallel.hpp"
#include "sdfgen/error.hpp"

#include <glm/geometric.hpp>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace sdfgen {

std::uint64_t estimateBakeBytes(const Mesh& mesh, const Grid& grid, const BakeSettings& settings, bool onDevice, const Bvh* tree,
                                const RunControl& control) {
    const double samples = double(grid.dims.x) * double(grid.dims.y) * double(grid.dims.z);
    const double triangles = double(mesh.triangleCount()), vertices = double(mesh.positions.size());
    constexpr double kFloat = 4, kFlag = 1;
    // The field's values and the channels asked for (4-byte values, width of them per sample).
    double fieldSample = kFloat;
    for (std::size_t c = 0; c < channelInfos().size(); ++c) {
        if (settings.channels.has(c)) fieldSample += channelInfos()[c].width * kFloat;
    }
    const double result = samples * fieldSample;
    MemoryTerms terms;
    terms.samples = samples;
    terms.triangles = triangles;

    const DistanceMethodPlugin& method = distanceMethod(settings.method);
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
        const SignMethodPlugin& info = signMethod(sign);
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
