#pragma once
#include "sdfgen/run_control.hpp"

#include <glm/vec3.hpp>
#include <cstdint>
#include <vector>

namespace sdfgen {

// A mesh's vertices grouped by position: vertices at the same coordinates (-0 and +0 alike; OBJ
// files often repeat positions) form one group, the topology's merged vertex. Groups are numbered
// in the order of their first vertex. Kept by a model whose vertices move (Model::refit): while
// they group the same way, the connectivity, the triangles' exact copies and so the trees' and
// the topology's shapes stand.
class VertexGroups {
public:
    // Sorted by position on control.threads threads; the same groups for any count. Positions are
    // finite (Mesh), so equal coordinates have equal bits once -0 is made +0.
    explicit VertexGroups(const std::vector<glm::vec3>& positions, const RunControl& control = {});

    std::size_t count() const { return firstVertex_.size(); }
    std::size_t vertexCount() const { return groupOf_.size(); }
    std::uint32_t groupOf(std::size_t vertex) const { return groupOf_[vertex]; }
    std::uint32_t firstVertex(std::size_t group) const { return firstVertex_[group]; }

    // Whether `positions`, these vertices moved, group the same way: every group still at one
    // position and no two groups at the same one. Linear time (the groups' positions hashed), where
    // grouping them again sorts.
    bool holdFor(const std::vector<glm::vec3>& positions) const;

private:
    std::vector<std::uint32_t> groupOf_;     // per vertex
    std::vector<std::uint32_t> firstVertex_; // per group, ascending
};

} // namespace sdfgen
