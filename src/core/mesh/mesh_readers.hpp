#pragma once
// The mesh formats sdfgen reads with its own readers, and what they share. A reader is one file
// (ply_reader.cpp, off_reader.cpp, stl_reader.cpp, OBJ in mesh.cpp) plus one line in the table in
// mesh_formats.cpp; every other extension goes to Assimp (core/mesh/assimp_reader.hpp).
//
// Each reader checks what a file declares (counts, sizes) against the file's size before it
// allocates anything, refuses indices out of range, and reports in Mesh::warnings what it read
// but could not use (faces of fewer than 3 vertices, data after the declared elements).
#include "core/runtime/printable.hpp"
#include "sdfgen/mesh.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace sdfgen {

Mesh loadPly(const std::string& path);
Mesh loadOff(const std::string& path);
Mesh loadStl(const std::string& path);

// Throws Error when `count` items of at least `bytesEach` bytes do not fit into `available` bytes:
// "PATH: the header declares COUNT WHAT (at least N bytes) but only AVAILABLE bytes follow it".
void checkDeclaredCount(const std::string& path, std::uint64_t count, const char* what, std::uint64_t bytesEach,
                        std::uint64_t available);

// Error("WHERE refers to vertex INDEX but the file has COUNT vertices (counted from 0)").
[[noreturn]] void badVertexIndex(const std::string& where, std::int64_t index, std::uint64_t vertexCount);

// Appends a polygon's triangles as a fan around its first corner, after checking every index
// against `vertexCount` (else badVertexIndex with where(), e.g. "PATH:12: face"). A polygon of
// fewer than 3 corners adds nothing and returns false (the caller counts it for its warning).
template <class Where>
bool addPolygon(const std::vector<std::int64_t>& corners, std::uint64_t vertexCount, const Where& where,
                std::vector<glm::uvec3>& triangles) {
    for (const std::int64_t index : corners) {
        if (index < 0 || std::uint64_t(index) >= vertexCount) badVertexIndex(where(), index, vertexCount);
    }
    if (corners.size() < 3) return false;
    for (std::size_t c = 1; c + 1 < corners.size(); ++c) {
        triangles.emplace_back(unsigned(corners[0]), unsigned(corners[c]), unsigned(corners[c + 1]));
    }
    return true;
}

// "" when a vertex coordinate read as `value` (from the text `token`, or written from the value
// when empty) fits single precision, as meshes are stored (OBJ's scan refuses the same); else the
// problem, for the reader to report where it read it: "vertex coordinate '1e300' is beyond
// single precision's range (3.4e+38)".
inline std::string coordinateProblem(double value, std::string_view token = {}) {
    if (std::fabs(value) <= double(std::numeric_limits<float>::max())) return "";
    std::string text(token);
    if (text.empty()) {
        char buffer[32];
        text.assign(buffer, std::to_chars(buffer, buffer + sizeof buffer, value).ptr);
    }
    return "vertex coordinate '" + printable(text, 40) + "' is " +
           (std::isfinite(value) ? "beyond single precision's range (3.4e+38)" : "not a finite number");
}

// Warning text for `count` faces of fewer than 3 vertices that were skipped (empty when none).
std::string skippedFacesWarning(const std::string& path, std::uint64_t count);

} // namespace sdfgen
