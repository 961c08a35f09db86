#include "sdfgen/mesh.hpp"
#include "sdfgen/error.hpp"
#include "core/mesh/input_file.hpp"
#include "core/mesh/obj_scan.hpp"

#include <tiny_obj_loader.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <glm/geometric.hpp>
#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <cstdint>
#include <tuple>
#include <utility>
#include <istream>
#include <streambuf>
#include <string_view>
#include <limits>

namespace sdfgen {

namespace {

std::string firstLine(const std::string& text) {
    std::string line = text.substr(0, text.find('\n'));
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    return line;
}

// A read-only stream over text already in memory, so tinyobjloader reads it without a copy.
class TextBuffer : public std::streambuf {
public:
    explicit TextBuffer(std::string_view text) {
        char* begin = const_cast<char*>(text.data()); // never written: this buffer has no put area
        setg(begin, begin, begin + text.size());
    }
};

// The triangles of OBJ text that the scan checked, by tinyobjloader (which triangulates polygons).
std::vector<glm::uvec3> trianglesByTinyobjloader(const std::string& path, std::string_view text, std::size_t faces,
                                                 std::size_t vertexCount) {
    TextBuffer buffer(text);
    std::istream file(&buffer);
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> materials;
    std::string warning, error;
    // No material reader: a missing .mtl must not fail a geometry-only load.
    const bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warning, &error, &file, nullptr,
                                     /*triangulate=*/true);
    if (!ok) throw Error(path + ": " + (error.empty() ? "not a valid OBJ file" : firstLine(error)));
    // tinyobjloader only warns about, and silently skips, polygons with vertex indices out of range.
    if (warning.find("Face with invalid vertex index") != std::string::npos) {
        throw Error(path + ": a face refers to a vertex that does not exist");
    }
    if (attrib.vertices.size() / 3 != vertexCount) {
        throw Error(path + ": tinyobjloader read " + std::to_string(attrib.vertices.size() / 3) +
                    " vertices where the file has " + std::to_string(vertexCount));
    }

    std::vector<glm::uvec3> triangles;
    triangles.reserve(faces); // one per triangle face; polygons add more
    for (const tinyobj::shape_t& shape : shapes) {
        const auto& indices = shape.mesh.indices;
        std::size_t offset = 0;
        for (const unsigned char faceSize : shape.mesh.num_face_vertices) {
            if (faceSize == 3) {
                glm::uvec3 tri;
                for (int c = 0; c < 3; ++c) {
                    const int index = indices[offset + c].vertex_index;
                    if (index < 0 || std::size_t(index) >= vertexCount) {
                        throw Error(path + ": face refers to vertex " + std::to_string(index + 1) +
                                    " but the file has " + std::to_string(vertexCount) + " vertices");
                    }
                    tri[c] = unsigned(index);
                }
                triangles.push_back(tri);
            }
            offset += faceSize;
        }
    }
    return triangles;
}

} // namespace

namespace {

// The power of two nearest above `halfExtent`, so local coordinates lie within about [-1, 1].
double unitFor(double halfExtent) {
    if (!(halfExtent > 0.0)) return 1.0;
    int exponent = 0;
    const double mantissa = std::frexp(halfExtent, &exponent); // halfExtent = m * 2^exponent, m in [0.5, 1)
    return std::ldexp(1.0, mantissa == 0.5 ? exponent - 1 : exponent);
}

} // namespace

namespace {

// Items per parallel chunk: each pass is a few nanoseconds an item, so a mesh of fewer items is
// done on the calling thread alone, sooner than the thread pool would wake (a refit step builds
// one every call).
constexpr std::size_t kGrain = 65536;

// The lowest i in [0, n) for which bad(i) holds, or n: the answer of a serial search, in parallel.
template <class Bad>
std::size_t firstWhere(std::size_t n, const Bad& bad) {
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, n, kGrain), n,
        [&](const tbb::blocked_range<std::size_t>& r, std::size_t found) {
            for (std::size_t i = r.begin(); i < r.end() && i < found; ++i) {
                if (bad(i)) return i;
            }
            return found;
        },
        [](std::size_t a, std::size_t b) { return std::min(a, b); });
}

// The box of the vertices that `triangles` use (min and max are exact, so any order gives it).
template <class Vec>
std::pair<Vec, Vec> usedBox(const std::vector<Vec>& positions, const std::vector<glm::uvec3>& triangles) {
    using Box = std::pair<Vec, Vec>;
    using Scalar = typename Vec::value_type;
    const Box empty{Vec(std::numeric_limits<Scalar>::max()), Vec(-std::numeric_limits<Scalar>::max())};
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, triangles.size(), kGrain), empty,
        [&](const tbb::blocked_range<std::size_t>& r, Box box) {
            for (std::size_t t = r.begin(); t < r.end(); ++t) {
                for (int c = 0; c < 3; ++c) {
                    box.first = glm::min(box.first, positions[triangles[t][c]]);
                    box.second = glm::max(box.second, positions[triangles[t][c]]);
                }
            }
            return box;
        },
        [](Box a, const Box& b) { return Box{glm::min(a.first, b.first), glm::max(a.second, b.second)}; });
}

} // namespace

Mesh buildMesh(std::string source, std::vector<glm::dvec3> positions, std::vector<glm::uvec3> triangles) {
    Mesh mesh;
    mesh.source = std::move(source);
    const std::size_t badVertex = firstWhere(positions.size(), [&](std::size_t i) {
        const glm::dvec3& p = positions[i];
        return !std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z);
    });
    if (badVertex < positions.size()) {
        throw Error(mesh.source + ": vertex " + std::to_string(badVertex + 1) + " has a non-finite coordinate");
    }
    const std::size_t badTriangle = firstWhere(triangles.size(), [&](std::size_t t) {
        return std::max({triangles[t][0], triangles[t][1], triangles[t][2]}) >= positions.size();
    });
    if (badTriangle < triangles.size()) {
        for (int c = 0; c < 3; ++c) {
            const std::size_t index = triangles[badTriangle][c];
            if (index >= positions.size()) {
                throw Error(mesh.source + ": triangle " + std::to_string(badTriangle + 1) + " uses vertex " +
                            std::to_string(index + 1) + " but there are only " + std::to_string(positions.size()) +
                            " vertices");
            }
        }
    }
    // Local frame: the centre of the box of the vertices that the kept triangles use, and a
    // power-of-two unit. Zero-area triangles (and those whose normal overflows) are dropped; they
    // get no normal. Which have zero area is measured on the local float positions, which are what
    // every later step uses; then the frame is taken again from the triangles kept: a dropped one
    // out at a stray vertex would otherwise set a unit so large that the kept ones, far smaller,
    // lose their extent in float (their squared distances underflow, and searches go wrong). A
    // triangle that the new frame leaves with zero area is dropped too; the frame still holds the rest.
    std::vector<glm::vec3> local(positions.size());
    std::vector<glm::uvec3> kept = std::move(triangles);
    std::vector<glm::vec3> normals;
    mesh.droppedDegenerate = 0;
    glm::dvec3 frameLo(0.0), frameHi(0.0);
    for (int pass = 0; pass < 2 && !kept.empty(); ++pass) {
        const auto [lo, hi] = usedBox(positions, kept);
        if (pass > 0 && lo == frameLo && hi == frameHi) break; // the dropped ones lay within the rest's box
        frameLo = lo, frameHi = hi;
        mesh.origin = lo + (hi - lo) * 0.5;
        const glm::dvec3 half = (hi - lo) * 0.5;
        mesh.unit = unitFor(std::max({half.x, half.y, half.z}));
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, positions.size(), kGrain), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i < r.end(); ++i) local[i] = glm::vec3(mesh.toLocal(positions[i]));
        });
        normals.assign(kept.size(), glm::vec3(0.0f));
        std::vector<std::uint8_t> degenerate(kept.size());
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, kept.size(), kGrain), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t t = r.begin(); t < r.end(); ++t) {
                // Double precision so that thin but valid triangles keep an accurate normal.
                const glm::uvec3& tri = kept[t];
                const glm::dvec3 a(local[tri[0]]), b(local[tri[1]]), c(local[tri[2]]);
                const glm::dvec3 n = glm::cross(b - a, c - a);
                const double length = glm::length(n);
                degenerate[t] = !(length > 0.0) || !std::isfinite(length);
                if (!degenerate[t]) normals[t] = glm::vec3(n / length);
            }
        });
        const std::size_t dropped = std::size_t(std::count(degenerate.begin(), degenerate.end(), std::uint8_t(1)));
        if (dropped == 0) break;
        mesh.droppedDegenerate += dropped;
        std::size_t next = 0;
        for (std::size_t t = 0; t < kept.size(); ++t) {
            if (degenerate[t]) continue;
            kept[next] = kept[t];
            normals[next++] = normals[t];
        }
        kept.resize(next);
        normals.resize(next);
    }
    mesh.triangles = std::move(kept);
    mesh.faceNormals = std::move(normals);
    if (mesh.triangles.empty()) {
        throw Error(mesh.source + ": no triangles" +
                    (mesh.droppedDegenerate ? " (all " + std::to_string(mesh.droppedDegenerate) + " have zero area)"
                                            : std::string(" (only points, lines or nothing)")));
    }
    std::tie(mesh.bounds.min, mesh.bounds.max) = usedBox(local, mesh.triangles);
    mesh.positions = std::move(local);
    return mesh;
}

Mesh buildMesh(std::string source, const std::vector<glm::vec3>& positions, std::vector<glm::uvec3> triangles) {
    Mesh mesh = buildMesh(std::move(source), std::vector<glm::dvec3>(positions.begin(), positions.end()), std::move(triangles));
    // Float input resolves about 6e-8 of its distance from the world origin: a mesh whose extent is
    // below ~1e-5 of that distance was already coarsely rounded before sdfgen saw it.
    const WorldBounds box = mesh.worldBounds();
    const glm::dvec3 extent = box.extent();
    const double size = std::max({extent.x, extent.y, extent.z});
    const double distance = std::max({std::fabs(mesh.origin.x), std::fabs(mesh.origin.y), std::fabs(mesh.origin.z)});
    if (size < 1e-5 * distance) {
        char line[256];
        std::snprintf(line, sizeof(line),
                      "%s: the mesh is %.3g across but %.3g from the origin: its single-precision coordinates "
                      "resolve only about %.2g%% of its size",
                      mesh.source.c_str(), size, distance, 100.0 * distance * 6e-8 / size);
        mesh.warnings.push_back(line);
    }
    return mesh;
}

Mesh loadObj(const std::string& path) {
    // One read (pipes and FIFOs work, size bounded, NULs refused), one parallel pass that reads the
    // vertices and triangles and refuses what tinyobjloader would misread; tinyobjloader reads the
    // faces only when the scan cannot (polygons, which it triangulates, or lines it may refuse).
    const std::string content = readInputFile(path, InputKind::Text);
    const std::string_view text = withoutByteOrderMark(content);
    ObjScan scan = scanObj(path, text);
    std::vector<glm::dvec3> positions = std::move(scan.vertices); // correctly rounded doubles
    std::vector<glm::uvec3> triangles =
        scan.trianglesOnly ? std::move(scan.triangles) : trianglesByTinyobjloader(path, text, scan.faces, positions.size());
    return buildMesh(path, std::move(positions), std::move(triangles));
}

} // namespace sdfgen
