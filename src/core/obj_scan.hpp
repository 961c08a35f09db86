#pragma once
#include <glm/vec3.hpp>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace sdfgen {

// What one pass over an OBJ file's text found, before tinyobjloader reads it.
struct ObjScan {
    std::vector<glm::dvec3> vertices; // every `v` line's coordinates, as written (double)
    std::size_t faces = 0;            // `f` lines
};

// Checks the vertex and face lines of OBJ text (without a byte-order mark) for everything
// tinyobjloader would misread silently: coordinates that are not finite decimal numbers within
// float range (nan, inf, hex floats, overflow, junk), fewer than 3 coordinates, face indices that
// are not whole numbers, are 0, overflow or refer past the vertices, and faces with fewer than 3
// vertices. Lines end in \n, \r\n or a lone \r, as tinyobjloader reads them. Throws
// Error("PATH:LINE: problem").
ObjScan scanObj(const std::string& path, std::string_view text);

// `text` without a leading UTF-8 byte-order mark.
std::string_view withoutByteOrderMark(std::string_view text);

} // namespace sdfgen
