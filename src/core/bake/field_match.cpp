#include "sdfgen/field_match.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <filesystem>

namespace sdfgen {

std::string fieldMismatch(const FieldHeader& field, const Mesh& mesh) {
    namespace fs = std::filesystem;
    const std::string fieldSource = fs::path(field.source).filename().string();
    const std::string meshSource = fs::path(mesh.source).filename().string();
    // Covering: the mesh's box inside the grid's box, up to a millionth of the mesh's size.
    const glm::dvec3 gridMin(field.grid.origin);
    const glm::dvec3 gridMax = gridMin + glm::dvec3(field.grid.dims) * double(field.grid.voxel);
    const glm::dvec3 meshMin = mesh.worldBounds().min, meshMax = mesh.worldBounds().max;
    const double slack = 1e-6 * std::max(glm::length(meshMax - meshMin), 1e-30);
    const bool covers = !glm::any(glm::lessThan(meshMin, gridMin - slack)) && !glm::any(glm::greaterThan(meshMax, gridMax + slack));
    // Both when both: a field of another name may still cover the model (a copy), or not.
    if (!fieldSource.empty() && fieldSource != meshSource) {
        return "the field was made from " + field.source + ", not from " + meshSource + (covers ? "" : ", and its grid does not cover the model");
    }
    if (!covers) return "the field's grid does not cover the model (made from another mesh, or the model was moved)";
    return "";
}

} // namespace sdfgen
