#pragma once
#include <glm/vec3.hpp>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace sdfgen {

// What one pass over an OBJ file's text found.
struct ObjScan {
    std::vector<glm::dvec3> vertices; // every `v` line's coordinates, as written (double)
    std::size_t faces = 0;            // `f` lines
    // Set when every face is a triangle whose corners are written v, v/vt, v//vn or v/vt/vn with
    // whole nonzero indices, and no `l`, `p` or `vw` line (which tinyobjloader may refuse) is there:
    // `triangles` then holds exactly what tinyobjloader would read (each face, in file order, its
    // corners counted from 0), and the file needs no other reader. Otherwise `triangles` is empty
    // and tinyobjloader reads the faces (it triangulates polygons by its own float coordinates).
    bool trianglesOnly = true;
    std::vector<glm::uvec3> triangles;
};

// Checks the vertex and face lines of OBJ text (without a byte-order mark) for everything
// tinyobjloader would misread silently: coordinates that are not finite decimal numbers within
// float range (nan, inf, hex floats, overflow, junk), fewer than 3 coordinates, face indices that
// are not whole numbers, are 0, overflow or refer past the vertices, and faces with fewer than 3
// vertices. Lines end in \n, \r\n or a lone \r, as tinyobjloader reads them. Throws
// Error("PATH:LINE: problem") for the first problem in the file. The text is read in pieces of
// about `chunkBytes` (split after a \n) in parallel; the result does not depend on the size.
ObjScan scanObj(const std::string& path, std::string_view text, std::size_t chunkBytes = std::size_t(1) << 20);

} // namespace sdfgen
