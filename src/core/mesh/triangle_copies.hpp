#pragma once
#include "sdfgen/mesh.hpp"

#include <cstdint>
#include <vector>

namespace sdfgen {

// Triangles that repeat an earlier triangle exactly: the same corner positions in the same cyclic
// order (so the same plane and orientation; a flipped copy is a different triangle). Meshes made
// by concatenating parts, or written twice, hold many; every pass that pairs or stacks triangles
// works on one copy and its count instead, so copies cost linear time, not quadratic.
struct TriangleCopies {
    std::vector<std::uint32_t> unique; // the first copy of each distinct triangle, ascending
    std::vector<std::uint32_t> count;  // how many times unique[i] occurs in the mesh
    std::vector<std::uint32_t> first;  // per mesh triangle: the index (into the mesh) of its first copy

    bool none() const { return unique.size() == first.size(); }
};

TriangleCopies findTriangleCopies(const Mesh& mesh);

} // namespace sdfgen
