#include "support/broken_meshes.hpp"
#include "support/shapes.hpp"

#include <glm/geometric.hpp>
#include <cmath>
#include <utility>

namespace sdfgen::test {

constexpr double kPi = 3.14159265358979323846;

Mesh translated(const Mesh& mesh, const glm::vec3& offset, bool flip) {
    std::vector<glm::dvec3> positions = mesh.worldPositions();
    for (glm::dvec3& p : positions) p += glm::dvec3(offset);
    std::vector<glm::uvec3> triangles = mesh.triangles;
    if (flip) {
        for (glm::uvec3& t : triangles) std::swap(t[1], t[2]);
    }
    return buildMesh(mesh.source, std::move(positions), std::move(triangles));
}

Mesh combined(const std::string& name, const Mesh& a, const Mesh& b) {
    std::vector<glm::dvec3> positions = a.worldPositions();
    const std::vector<glm::dvec3> more = b.worldPositions();
    positions.insert(positions.end(), more.begin(), more.end());
    std::vector<glm::uvec3> triangles = a.triangles;
    const unsigned shift = unsigned(a.positions.size());
    for (const glm::uvec3& t : b.triangles) triangles.push_back(t + glm::uvec3(shift));
    return buildMesh(name, std::move(positions), std::move(triangles));
}

Mesh holedSphere(float r) {
    const Mesh sphere = test::icosphere(r, 2);
    std::vector<glm::uvec3> kept;
    for (std::size_t t = 0; t < sphere.triangleCount(); ++t) {
        const glm::vec3 centroid = (sphere.vertex(t, 0) + sphere.vertex(t, 1) + sphere.vertex(t, 2)) / 3.0f;
        if (centroid.y <= 0.8f * r) kept.push_back(sphere.triangles[t]);
    }
    return buildMesh("holed sphere", sphere.worldPositions(), std::move(kept));
}

Mesh twoShells(bool flipSecond) {
    const Mesh sphere = test::icosphere(1.0f, 2);
    return combined(flipSecond ? "two shells, one flipped" : "two shells", translated(sphere, {-0.5f, 0, 0}, false),
                    translated(sphere, {0.5f, 0, 0}, flipSecond));
}

Mesh fan(const std::string& name, glm::vec3 centre, glm::vec3 apex, glm::vec3 u, glm::vec3 v, float R, int n, bool flip) {
    std::vector<glm::vec3> positions = {apex};
    std::vector<glm::uvec3> triangles;
    for (int k = 0; k < n; ++k) {
        const float angle = 2.0f * float(kPi) * float(k) / float(n);
        positions.push_back(centre + R * (std::cos(angle) * u + std::sin(angle) * v));
        const unsigned b = unsigned(1 + k), c = unsigned(1 + (k + 1) % n);
        triangles.push_back(flip ? glm::uvec3(0, c, b) : glm::uvec3(0, b, c));
    }
    return buildMesh(name, std::move(positions), std::move(triangles));
}

void tiltedFrame(glm::vec3& u, glm::vec3& v) {
    u = glm::normalize(glm::vec3(0.8f, 0.3f, -0.5f));
    v = glm::normalize(glm::cross(glm::vec3(0.2f, 1.0f, 0.1f), u));
}

Mesh flatDisk() {
    glm::vec3 u, v;
    tiltedFrame(u, v);
    return fan("disk", {0.1f, 0.05f, -0.02f}, {0.1f, 0.05f, -0.02f}, u, v, 1.0f, 16, false);
}

Mesh cup(bool flip) {
    glm::vec3 u, v;
    tiltedFrame(u, v);
    const glm::vec3 centre(0.1f, 0.05f, -0.02f);
    const glm::vec3 axis = glm::normalize(glm::cross(u, v));
    return fan(flip ? "cup, flipped" : "cup", centre, centre + 1.5f * axis, u, v, 1.0f, 16, flip);
}

void addTetrahedron(std::vector<glm::vec3>& positions, std::vector<glm::uvec3>& triangles, glm::vec3 o, float s) {
    const unsigned base = unsigned(positions.size());
    positions.insert(positions.end(), {o, o + glm::vec3(s, 0, 0), o + glm::vec3(0, s, 0), o + glm::vec3(0, 0, s)});
    std::vector<glm::uvec3> faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    for (glm::uvec3 f : faces) {
        if (s < 0) std::swap(f[1], f[2]); // a mirror image reverses the orientation
        triangles.push_back(f + glm::uvec3(base));
    }
}

Mesh unshared(const Mesh& mesh) {
    std::vector<glm::dvec3> positions;
    std::vector<glm::uvec3> triangles;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const unsigned base = unsigned(positions.size());
        for (int c = 0; c < 3; ++c) positions.push_back(mesh.toWorld(glm::dvec3(mesh.vertex(t, c))));
        triangles.emplace_back(base, base + 1, base + 2);
    }
    return buildMesh(mesh.source + " (unshared)", std::move(positions), std::move(triangles));
}

double signedVolume(const Mesh& mesh) {
    double volume = 0;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        volume += glm::dot(glm::dvec3(mesh.vertex(t, 0)), glm::cross(glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2))));
    }
    return volume / 6.0;
}

std::vector<Shape> closedShapes() {
    return {{"icosphere", test::icosphere(1.0f, 2), 24},
            {"box", test::box({1.0f, 0.6f, 0.4f}), 24},
            {"torus", test::torus(1.0f, 0.3f, 24, 12), 24},
            {"bunny", loadMesh(test::bundledBunnyPath()), 16}};
}

std::vector<Shape> openShapes() {
    return {{"holed sphere", holedSphere(1.0f), 24}, {"two shells", twoShells(false), 24},
            {"two shells, one flipped", twoShells(true), 24}, {"disk", flatDisk(), 24},
            {"cup", cup(false), 24}, {"cup, flipped", cup(true), 24}};
}

} // namespace sdfgen::test
