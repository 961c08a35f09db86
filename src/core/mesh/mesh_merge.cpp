// mergeMeshes: a scene of placed meshes as one triangle soup (see mesh.hpp).
#include "sdfgen/error.hpp"
#include "sdfgen/mesh.hpp"

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <cmath>

namespace sdfgen {

Mesh mergeMeshes(const std::vector<MeshInstance>& parts, std::string source) {
    if (parts.empty()) throw Error(source + ": a scene needs at least one mesh");
    std::vector<glm::dvec3> positions; // world, in double
    std::vector<glm::uvec3> triangles;
    for (const MeshInstance& part : parts) {
        const glm::dmat4& m = part.transform;
        for (int c = 0; c < 4; ++c) {
            for (int r = 0; r < 4; ++r) {
                if (!std::isfinite(m[c][r])) throw Error(part.mesh->source + ": the transform has a non-finite entry");
            }
        }
        const bool mirrored = glm::determinant(glm::dmat3(m)) < 0.0;
        const std::size_t base = positions.size();
        if (base + part.mesh->positions.size() > 0xffffffffu) throw Error(source + ": the scene has too many vertices");
        for (const glm::dvec3& p : part.mesh->worldPositions()) positions.push_back(glm::dvec3(m * glm::dvec4(p, 1.0)));
        for (const glm::uvec3& t : part.mesh->triangles) {
            const glm::uvec3 shifted = t + glm::uvec3(std::uint32_t(base));
            triangles.push_back(mirrored ? glm::uvec3(shifted.x, shifted.z, shifted.y) : shifted);
        }
    }
    Mesh merged = buildMesh(std::move(source), std::move(positions), std::move(triangles));
    // What the parts' loads dropped or warned about still holds for the scene.
    std::vector<std::string> warnings;
    for (const MeshInstance& part : parts) {
        merged.droppedDegenerate += part.mesh->droppedDegenerate;
        warnings.insert(warnings.end(), part.mesh->warnings.begin(), part.mesh->warnings.end());
    }
    merged.warnings.insert(merged.warnings.begin(), warnings.begin(), warnings.end());
    return merged;
}

} // namespace sdfgen
