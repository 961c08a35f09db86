#include "support/shapes.hpp"

#include <glm/geometric.hpp>
#include <cmath>
#include <algorithm>
#include <map>
#include <utility>
#include <vector>

namespace sdfgen::test {

Mesh icosphere(float radius, int levels) {
    const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
    std::vector<glm::vec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    std::vector<glm::uvec3> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},   {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                                 {3, 8, 9},   {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (glm::vec3& p : v) p = glm::normalize(p);
    for (int level = 0; level < levels; ++level) {
        std::map<std::pair<unsigned, unsigned>, unsigned> midpoints;
        auto midpoint = [&](unsigned a, unsigned b) {
            const auto key = std::minmax(a, b);
            auto it = midpoints.find(key);
            if (it != midpoints.end()) return it->second;
            v.push_back(glm::normalize(v[a] + v[b]));
            return midpoints[key] = unsigned(v.size() - 1);
        };
        std::vector<glm::uvec3> next;
        for (const glm::uvec3& tri : f) {
            const unsigned ab = midpoint(tri[0], tri[1]);
            const unsigned bc = midpoint(tri[1], tri[2]);
            const unsigned ca = midpoint(tri[2], tri[0]);
            next.insert(next.end(), {glm::uvec3(tri[0], ab, ca), glm::uvec3(tri[1], bc, ab), glm::uvec3(tri[2], ca, bc),
                                    glm::uvec3(ab, bc, ca)});
        }
        f = std::move(next);
    }
    for (glm::vec3& p : v) p *= radius;
    return buildMesh("icosphere", std::move(v), std::move(f));
}

float icosphereSag(float radius, int levels) {
    // Faces shrink by about half per level; the worst face centre lies deepest. Measured directly.
    const Mesh mesh = icosphere(radius, levels);
    float sag = 0.0f;
    for (std::size_t i = 0; i < mesh.triangleCount(); ++i) {
        const glm::vec3 n = mesh.faceNormals[i];
        sag = std::max(sag, radius - float(glm::dot(glm::dvec3(n), mesh.toWorld(glm::dvec3(mesh.vertex(i, 0))))));
    }
    return sag;
}

float sphereDistance(const glm::vec3& p, float radius) { return glm::length(p) - radius; }

Mesh box(const glm::vec3& h) {
    std::vector<glm::vec3> v;
    for (int i = 0; i < 8; ++i) v.emplace_back(i & 1 ? h.x : -h.x, i & 2 ? h.y : -h.y, i & 4 ? h.z : -h.z);
    std::vector<glm::uvec3> f = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                                 {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
    return buildMesh("box", std::move(v), std::move(f));
}

float boxDistance(const glm::vec3& p, const glm::vec3& h) {
    const glm::vec3 q = glm::abs(p) - h;
    return glm::length(glm::max(q, glm::vec3(0.0f))) + std::min(std::max(q.x, std::max(q.y, q.z)), 0.0f);
}

Mesh torus(float major, float minor, int ringSegments, int tubeSegments) {
    std::vector<glm::vec3> v;
    std::vector<glm::uvec3> f;
    for (int i = 0; i < ringSegments; ++i) {
        const float u = 2.0f * float(M_PI) * float(i) / float(ringSegments);
        for (int j = 0; j < tubeSegments; ++j) {
            const float w = 2.0f * float(M_PI) * float(j) / float(tubeSegments);
            const float r = major + minor * std::cos(w);
            v.emplace_back(r * std::cos(u), minor * std::sin(w), r * std::sin(u));
        }
    }
    auto at = [&](int i, int j) { return unsigned((i % ringSegments) * tubeSegments + (j % tubeSegments)); };
    for (int i = 0; i < ringSegments; ++i) {
        for (int j = 0; j < tubeSegments; ++j) {
            // Wound so that normals point away from the tube's centre line.
            f.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
            f.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
        }
    }
    return buildMesh("torus", std::move(v), std::move(f));
}

float torusDistance(const glm::vec3& p, float major, float minor) {
    const float ring = std::sqrt(p.x * p.x + p.z * p.z) - major;
    return std::sqrt(ring * ring + p.y * p.y) - minor;
}

float torusSag(float major, float minor, int ringSegments, int tubeSegments) {
    // Chord sag of each circle the quads span: (radius)(1 - cos(half the angle)); the outer ring is widest.
    const float ring = (major + minor) * (1.0f - std::cos(float(M_PI) / float(ringSegments)));
    const float tube = minor * (1.0f - std::cos(float(M_PI) / float(tubeSegments)));
    return ring + tube;
}

const char* bundledBunnyPath() { return SDFGEN_SOURCE_DIR "/assets/bunny.obj"; }

} // namespace sdfgen::test
