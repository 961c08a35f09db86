#include "gpu/flat_bvh.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <algorithm>
#include <cmath>
#include <cstring>

namespace sdfgen::gpu {

namespace {

float uintBits(std::uint32_t value) {
    float f;
    std::memcpy(&f, &value, sizeof(f));
    return f;
}

struct Builder {
    const Mesh& mesh;
    std::vector<std::uint32_t> order;   // triangle indices, partitioned as the tree is built
    std::vector<glm::vec3> centroids;
    std::vector<FlatBvh::Node>& nodes;

    void build(std::uint32_t nodeIndex, std::uint32_t first, std::uint32_t count, int depth) {
        glm::vec3 lo(INFINITY), hi(-INFINITY), clo(INFINITY), chi(-INFINITY);
        for (std::uint32_t i = first; i < first + count; ++i) {
            const std::uint32_t t = order[i];
            for (int c = 0; c < 3; ++c) {
                lo = glm::min(lo, mesh.vertex(t, c));
                hi = glm::max(hi, mesh.vertex(t, c));
            }
            clo = glm::min(clo, centroids[t]);
            chi = glm::max(chi, centroids[t]);
        }
        if (count <= std::uint32_t(FlatBvh::kLeafSize) || depth >= FlatBvh::kMaxDepth) {
            nodes[nodeIndex] = {glm::vec4(lo, uintBits(first)), glm::vec4(hi, uintBits(count))};
            return;
        }
        const glm::vec3 extent = chi - clo;
        const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
        const std::uint32_t half = count / 2;
        // Ties broken by index, so that the tree does not depend on the library's nth_element.
        std::nth_element(order.begin() + first, order.begin() + first + half, order.begin() + first + count,
                         [&](std::uint32_t l, std::uint32_t r) {
                             return centroids[l][axis] < centroids[r][axis] || (centroids[l][axis] == centroids[r][axis] && l < r);
                         });
        const std::uint32_t left = std::uint32_t(nodes.size());
        nodes.resize(nodes.size() + 2);
        nodes[nodeIndex] = {glm::vec4(lo, uintBits(left)), glm::vec4(hi, uintBits(0))};
        build(left, first, half, depth + 1);
        build(left + 1, first + half, count - half, depth + 1);
    }
};

} // namespace

FlatBvh::FlatBvh(const Mesh& mesh) {
    const std::uint32_t count = std::uint32_t(mesh.triangleCount());
    Builder builder{mesh, std::vector<std::uint32_t>(count), std::vector<glm::vec3>(count), nodes};
    for (std::uint32_t t = 0; t < count; ++t) {
        builder.order[t] = t;
        builder.centroids[t] = (mesh.vertex(t, 0) + mesh.vertex(t, 1) + mesh.vertex(t, 2)) / 3.0f;
    }
    nodes.resize(1);
    nodes.reserve(2 * (count / kLeafSize + 1));
    builder.build(0, 0, count, 0);
    triangles.reserve(count);
    auto inverse = [](const glm::vec3& e) {
        const float length2 = glm::dot(e, e);
        return length2 > 0.0f ? 1.0f / length2 : 0.0f;
    };
    for (std::uint32_t t : builder.order) {
        const glm::vec3 a = mesh.vertex(t, 0), b = mesh.vertex(t, 1), c = mesh.vertex(t, 2);
        const glm::vec3 ab = b - a, ac = c - a, bc = c - b, ca = a - c;
        const glm::vec3 normal = mesh.faceNormals[t];
        triangles.push_back({glm::vec4(a, inverse(ab)), glm::vec4(ab, inverse(bc)), glm::vec4(ac, inverse(ca)),
                             glm::vec4(normal, uintBits(t)), glm::vec4(glm::cross(normal, ab), 0.0f),
                             glm::vec4(glm::cross(normal, bc), 0.0f), glm::vec4(glm::cross(normal, ca), 0.0f),
                             glm::vec4(b, 0.0f), glm::vec4(c, 0.0f)});
    }
}

} // namespace sdfgen::gpu
