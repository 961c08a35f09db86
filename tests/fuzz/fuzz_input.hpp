#pragma once
// The loaders read files by path, so each fuzz input is written to one scratch file per process.
#include "sdfgen/mesh.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <unistd.h>

namespace sdfgen::fuzz {

// Writes the input to a scratch file with the given extension and returns its path.
inline const std::string& writeInput(const std::uint8_t* data, std::size_t size, const std::string& extension) {
    static std::string folder = [] {
        std::string dir = (std::getenv("TMPDIR") ? std::string(std::getenv("TMPDIR")) : std::string("/tmp")) +
                          "/sdfgen-fuzz-XXXXXX";
        if (!mkdtemp(dir.data())) std::abort();
        return dir;
    }();
    static std::string path;
    path = folder + "/input" + extension;
    std::FILE* file = std::fopen(path.c_str(), "wb");
    if (!file || std::fwrite(data, 1, size, file) != size || std::fclose(file) != 0) std::abort();
    return path;
}

// Aborts unless `mesh` is what every loader promises: triangles, one normal each, indices in
// range, finite positions.
inline void checkMesh(const Mesh& mesh) {
    if (mesh.triangles.empty() || mesh.triangles.size() != mesh.faceNormals.size()) std::abort();
    for (const glm::uvec3& t : mesh.triangles) {
        for (int c = 0; c < 3; ++c) {
            if (t[c] >= mesh.positions.size()) std::abort();
            const glm::vec3 p = mesh.positions[t[c]];
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) std::abort();
        }
    }
}

} // namespace sdfgen::fuzz
