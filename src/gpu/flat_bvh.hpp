#pragma once
#include "sdfgen/mesh.hpp"

#include <glm/vec4.hpp>
#include <cstdint>
#include <vector>

namespace sdfgen::gpu {

// A binary bounding volume hierarchy over a mesh's triangles, flattened into the arrays
// shaders/nearest.glsl reads from SSBOs (std430). Built here rather than taken from the CPU's
// tree so that the GPU's layout is its own.
struct FlatBvh {
    struct Node {
        glm::vec4 lo; // box minimum; w: first child (interior: children are adjacent) or first triangle (leaf), as uint bits
        glm::vec4 hi; // box maximum; w: triangle count, 0 for interior nodes, as uint bits
    };
    // Set up for the shader's float distance (shaders/nearest.glsl, triangleDistance2), with the
    // corners for the double re-measure.
    struct Triangle {
        glm::vec4 a;      // w: 1 / |b - a|²
        glm::vec4 ab;     // b - a; w: 1 / |c - b|²
        glm::vec4 ac;     // c - a; w: 1 / |a - c|²
        glm::vec4 normal; // the mesh's face normal; w: the mesh's triangle index, as uint bits
        glm::vec4 inAB;   // normal x edge: the edges' in-plane normals, pointing inwards
        glm::vec4 inBC;
        glm::vec4 inCA;
        glm::vec4 b;
        glm::vec4 c;
    };
    std::vector<Node> nodes;         // root first
    std::vector<Triangle> triangles; // in leaf order

    static constexpr int kMaxDepth = 30;  // the shader's stack holds 32 entries
    static constexpr int kLeafSize = 4;

    // Splits at the centroid median of the longest axis of the centroids' box: balanced, so the
    // depth stays under kMaxDepth for any mesh that fits in memory.
    explicit FlatBvh(const Mesh& mesh);
};

} // namespace sdfgen::gpu
