#include "sdfgen/surface.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/formats/format.hpp"
#include "core/io/openvdb_plugin.hpp"
#include "sdfgen/error.hpp"
#include "core/runtime/file_extension.hpp"

#include <glm/geometric.hpp>
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace sdfgen {

namespace {

// The first sample on the grid's boundary at or below `iso`, if any.
bool boundaryReaches(const Field& field, double iso, glm::ivec3& where) {
    const glm::ivec3 n = field.grid.dims;
    for (int k = 0; k < n.z; ++k) {
        for (int j = 0; j < n.y; ++j) {
            const bool faceRow = k == 0 || k == n.z - 1 || j == 0 || j == n.y - 1;
            for (int i = 0; i < n.x; i += faceRow ? 1 : std::max(1, n.x - 1)) {
                if (double(field.at(i, j, k)) <= iso) {
                    where = {i, j, k};
                    return true;
                }
            }
        }
    }
    return false;
}

// The same for a band field: its bricks' samples on the boundary, and any inside box that touches
// it (every other sample is +background, above an iso within the band).
bool boundaryReaches(const SparseField& field, double iso, glm::ivec3& where) {
    constexpr int B = SparseField::kBrick;
    const glm::ivec3 n = field.grid().dims;
    auto onBoundary = [&](const glm::ivec3& p) { return glm::any(glm::equal(p, glm::ivec3(0))) || glm::any(glm::equal(p, n - 1)); };
    for (std::size_t b = 0; b < field.bricks().size(); ++b) {
        const glm::ivec3 lo = field.bricks()[b] * B, hi = glm::min(lo + B, n);
        if (!onBoundary(lo) && !glm::any(glm::equal(hi, n))) continue;
        for (int k = lo.z; k < hi.z; ++k)
            for (int j = lo.y; j < hi.y; ++j)
                for (int i = lo.x; i < hi.x; ++i) {
                    const glm::ivec3 p(i, j, k);
                    if (onBoundary(p) && double(field.values()[b * SparseField::kBrickSamples + std::size_t(((k - lo.z) * B + (j - lo.y)) * B + (i - lo.x))]) <= iso) {
                        where = p;
                        return true;
                    }
                }
    }
    for (const auto& box : field.insideBoxes()) {
        const glm::ivec3 lo(box[0], box[1], box[2]), hi(box[3], box[4], box[5]);
        for (int a = 0; a < 3; ++a) {
            if (lo[a] == 0 || hi[a] == n[a]) {
                where = lo;
                where[a] = lo[a] == 0 ? 0 : n[a] - 1;
                return true;
            }
        }
    }
    return false;
}

void appendNumber(std::string& out, float v) {
    char text[32];
    const auto result = std::to_chars(text, text + sizeof text, v); // shortest exact float
    out.append(text, result.ptr);
}

std::string objText(const SurfaceMesh& mesh) {
    std::string text = "# sdfgen surface: " + std::to_string(mesh.positions.size()) + " vertices, " +
                       std::to_string(mesh.triangles.size()) + " triangles\n";
    text.reserve(mesh.positions.size() * 40 + mesh.triangles.size() * 24);
    for (const glm::vec3& p : mesh.positions) {
        text += "v ";
        appendNumber(text, p.x);
        text += ' ';
        appendNumber(text, p.y);
        text += ' ';
        appendNumber(text, p.z);
        text += '\n';
    }
    for (const glm::uvec3& t : mesh.triangles) {
        text += "f " + std::to_string(t.x + 1) + ' ' + std::to_string(t.y + 1) + ' ' + std::to_string(t.z + 1) + '\n';
    }
    return text;
}

std::string plyBytes(const SurfaceMesh& mesh) {
    std::string bytes = "ply\nformat binary_little_endian 1.0\ncomment sdfgen surface\nelement vertex " +
                        std::to_string(mesh.positions.size()) +
                        "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                        std::to_string(mesh.triangles.size()) + "\nproperty list uchar uint vertex_indices\nend_header\n";
    bytes.append(reinterpret_cast<const char*>(mesh.positions.data()), mesh.positions.size() * sizeof(glm::vec3));
    for (const glm::uvec3& t : mesh.triangles) {
        bytes += char(3);
        bytes.append(reinterpret_cast<const char*>(&t), sizeof t);
    }
    return bytes;
}

// The checks before meshing: iso and adaptivity, and a surface that stays inside the grid.
template <class AnyField>
void checkSurfaceCanClose(const AnyField& field, double iso, double adaptivity) {
    if (!std::isfinite(iso)) throw Error("iso must be a finite number");
    if (!(adaptivity >= 0.0 && adaptivity <= 1.0)) throw Error("adaptivity must be between 0 and 1");
    glm::ivec3 where;
    if (boundaryReaches(field, iso, where)) {
        throw Error("the surface at iso " + std::to_string(iso) + " reaches the grid's boundary (sample " + std::to_string(where.x) +
                    "," + std::to_string(where.y) + "," + std::to_string(where.z) + " is " +
                    std::to_string(field.at(where.x, where.y, where.z)) +
                    "), so it would be cut open: bake with more padding");
    }
}

// volumeToMesh's polygons as a mesh: triangles wound counter-clockwise seen from outside.
SurfaceMesh surfaceMesh(std::vector<glm::vec3>&& positions, const std::vector<glm::uvec3>& triangles, const std::vector<glm::uvec4>& quads,
                        const Grid& grid, double iso) {
    SurfaceMesh mesh;
    mesh.positions = std::move(positions);
    // volumeToMesh winds its polygons clockwise seen from outside (where d > iso); reversed here.
    mesh.triangles.reserve(triangles.size() + 2 * quads.size());
    for (const glm::uvec3& t : triangles) mesh.triangles.emplace_back(t[2], t[1], t[0]);
    for (const glm::uvec4& q : quads) {
        // Split along the shorter diagonal; both halves keep the quad's orientation.
        const glm::vec3 &a = mesh.positions[q[0]], &b = mesh.positions[q[1]], &c = mesh.positions[q[2]], &d = mesh.positions[q[3]];
        if (glm::distance(a, c) <= glm::distance(b, d)) {
            mesh.triangles.emplace_back(q[2], q[1], q[0]);
            mesh.triangles.emplace_back(q[3], q[2], q[0]);
        } else {
            mesh.triangles.emplace_back(q[3], q[1], q[0]);
            mesh.triangles.emplace_back(q[3], q[2], q[1]);
        }
    }
    if (mesh.triangles.empty()) throw Error("the field has no surface at iso " + std::to_string(iso));
    // Never a file of "v inf inf inf": a grid far beyond single precision (a voxel of 1e300, an
    // origin near the double limit) has no float positions.
    const auto bad = std::find_if(mesh.positions.begin(), mesh.positions.end(),
                                  [](const glm::vec3& p) { return !std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z); });
    if (bad != mesh.positions.end()) {
        char message[256];
        std::snprintf(message, sizeof(message),
                      "the surface's vertices are beyond single precision (grid origin %.3g %.3g %.3g, voxel size %.3g): "
                      "no mesh file can hold them",
                      grid.origin.x, grid.origin.y, grid.origin.z, grid.voxel);
        throw Error(message);
    }
    return mesh;
}

// The plugin's polygons of `field` (its polygons or polygonsSparse) on `grid` as a checked surface mesh.
template <class DenseOrBand, class Polygons>
SurfaceMesh polygonize(const DenseOrBand& field, const Grid& grid, double iso, double adaptivity, Polygons polygons) {
    checkSurfaceCanClose(field, iso, adaptivity);
    std::vector<glm::vec3> positions;
    std::vector<glm::uvec3> triangles;
    std::vector<glm::uvec4> quads;
    polygons(field, iso, adaptivity, positions, triangles, quads);
    return surfaceMesh(std::move(positions), triangles, quads, grid, iso);
}

} // namespace

SurfaceMesh extractSurface(const Field& field, double iso, double adaptivity) {
    return polygonize(field, field.grid, iso, adaptivity, openVdbPlugin().polygons);
}

SurfaceMesh extractSurface(const SparseField& field, double iso, double adaptivity) {
    if (std::isfinite(iso) && !(std::fabs(iso) < double(field.background()))) {
        char message[160];
        std::snprintf(message, sizeof message, "iso %g lies outside the band field's band (|d| < %g), where it holds only the side of the surface",
                      iso, double(field.background()));
        throw Error(message);
    }
    return polygonize(field, field.grid(), iso, adaptivity, openVdbPlugin().polygonsSparse);
}

void saveSurface(const SurfaceMesh& mesh, const std::string& path) {
    const std::string extension = lowerExtension(path);
    std::string bytes;
    if (extension == ".obj") {
        bytes = objText(mesh);
    } else if (extension == ".ply") {
        bytes = plyBytes(mesh);
    } else {
        throw Error(path + ": unknown surface format " + (extension.empty() ? "(no extension)" : "'" + extension + "'") + "; known: .obj, .ply");
    }
    writeFileAtomically(path, [&](std::ostream& out) { out.write(bytes.data(), std::streamsize(bytes.size())); });
}

} // namespace sdfgen
