#include "core/mesh/vertex_groups.hpp"
#include "core/runtime/parallel.hpp"

#include <tbb/parallel_sort.h>
#include <tbb/task_arena.h>

#include <array>
#include <cstring>
#include <numeric>
#include <tuple>

namespace sdfgen {

namespace {

using PositionBits = std::array<std::uint32_t, 3>;

// The coordinates' bits with -0 made +0: equal for equal finite coordinates, and only for them.
PositionBits bitsOf(const glm::vec3& position) {
    const glm::vec3 p = position + glm::vec3(0.0f);
    PositionBits bits;
    std::memcpy(bits.data(), &p, sizeof(p));
    return bits;
}

// MurmurHash3's 64-bit finaliser over the coordinates: every bit reaches the low ones, which pick
// the slot (grid-like coordinates differ in their high mantissa bits only).
std::uint64_t hashOf(const PositionBits& bits) {
    std::uint64_t h = ((std::uint64_t(bits[0]) << 32) | bits[1]) * 0x9e3779b97f4a7c15ull ^ bits[2];
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdull;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ull;
    return h ^ (h >> 33);
}

} // namespace

VertexGroups::VertexGroups(const std::vector<glm::vec3>& positions, const RunControl& control) {
    // Sorted by (bits, index) in parallel, a total order: each vertex goes to the first of its
    // run, and groups are numbered in the order of their first vertex.
    const std::size_t vertexCount = positions.size();
    std::vector<PositionBits> keys(vertexCount);
    for (std::size_t i = 0; i < vertexCount; ++i) keys[i] = bitsOf(positions[i]);
    std::vector<std::uint32_t> byPosition(vertexCount);
    std::iota(byPosition.begin(), byPosition.end(), 0u);
    tbb::task_arena arena(arenaSize(control));
    arena.execute([&] {
        tbb::parallel_sort(byPosition.begin(), byPosition.end(), [&](std::uint32_t x, std::uint32_t y) {
            return std::tie(keys[x][0], keys[x][1], keys[x][2], x) < std::tie(keys[y][0], keys[y][1], keys[y][2], y);
        });
    });
    groupOf_.resize(vertexCount);
    for (std::size_t k = 0; k < vertexCount; ++k) {
        const std::uint32_t i = byPosition[k];
        groupOf_[i] = k > 0 && keys[byPosition[k - 1]] == keys[i] ? groupOf_[byPosition[k - 1]] : i;
    }
    for (std::size_t i = 0; i < vertexCount; ++i) {
        if (groupOf_[i] == i) {
            groupOf_[i] = std::uint32_t(firstVertex_.size());
            firstVertex_.push_back(std::uint32_t(i));
        } else {
            groupOf_[i] = groupOf_[groupOf_[i]]; // the first of the run, already numbered
        }
    }
}

bool VertexGroups::holdFor(const std::vector<glm::vec3>& positions) const {
    if (positions.size() != groupOf_.size()) return false;
    for (std::size_t i = 0; i < positions.size(); ++i) {
        if (!(positions[i] == positions[firstVertex_[groupOf_[i]]])) return false; // -0 == +0, as the bits above
    }
    // No two groups at one position: each group's position entered in an open-addressing table
    // (at most half full), a repeat found where its probe meets an equal one.
    std::size_t slots = 16;
    while (slots < 2 * firstVertex_.size()) slots *= 2;
    constexpr std::uint32_t kFree = 0xffffffffu;
    std::vector<std::uint32_t> table(slots, kFree); // a group's first vertex
    for (const std::uint32_t vertex : firstVertex_) {
        const PositionBits bits = bitsOf(positions[vertex]);
        for (std::size_t slot = hashOf(bits) & (slots - 1);; slot = (slot + 1) & (slots - 1)) {
            if (table[slot] == kFree) {
                table[slot] = vertex;
                break;
            }
            if (bitsOf(positions[table[slot]]) == bits) return false;
        }
    }
    return true;
}

} // namespace sdfgen
