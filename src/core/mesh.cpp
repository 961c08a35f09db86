#include "sdfgen/mesh.hpp"
#include "sdfgen/error.hpp"
#include "core/input_file.hpp"
#include "core/obj_scan.hpp"

#include <tiny_obj_loader.h>

#include <glm/geometric.hpp>
#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cmath>
#include <cstdlib>
#include <cstring>
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

Mesh buildMesh(std::string source, std::vector<glm::dvec3> positions, std::vector<glm::uvec3> triangles) {
    Mesh mesh;
    mesh.source = std::move(source);
    for (std::size_t i = 0; i < positions.size(); ++i) {
        const glm::dvec3& p = positions[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            throw Error(mesh.source + ": vertex " + std::to_string(i + 1) + " has a non-finite coordinate");
        }
    }
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const glm::uvec3& tri = triangles[t];
        for (int c = 0; c < 3; ++c) {
            if (tri[c] >= positions.size()) {
                throw Error(mesh.source + ": triangle " + std::to_string(t + 1) + " uses vertex " +
                            std::to_string(std::size_t(tri[c]) + 1) + " but there are only " +
                            std::to_string(positions.size()) + " vertices");
            }
        }
    }
    // Local frame: the centre of the box of the vertices that triangles use, and a power-of-two unit.
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const glm::uvec3& tri : triangles) {
        for (int c = 0; c < 3; ++c) {
            lo = glm::min(lo, positions[tri[c]]);
            hi = glm::max(hi, positions[tri[c]]);
        }
    }
    if (!triangles.empty()) {
        mesh.origin = lo + (hi - lo) * 0.5;
        const glm::dvec3 half = (hi - lo) * 0.5;
        mesh.unit = unitFor(std::max({half.x, half.y, half.z}));
    }
    std::vector<glm::vec3> local(positions.size());
    for (std::size_t i = 0; i < positions.size(); ++i) local[i] = glm::vec3(mesh.toLocal(positions[i]));

    mesh.triangles.reserve(triangles.size());
    mesh.faceNormals.reserve(triangles.size());
    for (const glm::uvec3& tri : triangles) {
        // Double precision so that thin but valid triangles keep an accurate normal; measured on the
        // local float positions, which are what every later step uses.
        const glm::dvec3 a(local[tri[0]]), b(local[tri[1]]), c(local[tri[2]]);
        const glm::dvec3 n = glm::cross(b - a, c - a);
        const double length = glm::length(n);
        if (!(length > 0.0) || !std::isfinite(length)) {
            ++mesh.droppedDegenerate;
            continue;
        }
        mesh.triangles.push_back(tri);
        mesh.faceNormals.push_back(glm::vec3(n / length));
    }
    if (mesh.triangles.empty()) {
        throw Error(mesh.source + ": no triangles" +
                    (mesh.droppedDegenerate ? " (all " + std::to_string(mesh.droppedDegenerate) + " have zero area)"
                                            : std::string(" (only points, lines or nothing)")));
    }
    mesh.bounds.min = glm::vec3(std::numeric_limits<float>::max());
    mesh.bounds.max = glm::vec3(-std::numeric_limits<float>::max());
    for (const glm::uvec3& tri : mesh.triangles) {
        for (int c = 0; c < 3; ++c) {
            mesh.bounds.min = glm::min(mesh.bounds.min, local[tri[c]]);
            mesh.bounds.max = glm::max(mesh.bounds.max, local[tri[c]]);
        }
    }
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
    // One read (pipes and FIFOs work, size bounded, NULs refused), one pass that refuses what
    // tinyobjloader would misread, then tinyobjloader for the faces and their triangulation.
    const std::string content = readInputFile(path, InputKind::Text);
    const std::string_view text = withoutByteOrderMark(content);
    ObjScan scan = scanObj(path, text);
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

    const std::size_t vertexCount = attrib.vertices.size() / 3;
    if (vertexCount != scan.vertices.size()) {
        throw Error(path + ": tinyobjloader read " + std::to_string(vertexCount) + " vertices where the file has " +
                    std::to_string(scan.vertices.size()));
    }
    // The scan's correctly rounded doubles, not tinyobjloader's own float parsing.
    std::vector<glm::dvec3> positions = std::move(scan.vertices);

    std::vector<glm::uvec3> triangles;
    triangles.reserve(scan.faces); // one per triangle face; polygons add more
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
    return buildMesh(path, std::move(positions), std::move(triangles));
}

} // namespace sdfgen
