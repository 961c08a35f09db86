#include "core/duplicates.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <numeric>

namespace sdfgen {

TriangleCopies findTriangleCopies(const Mesh& mesh) {
    const std::size_t n = mesh.triangleCount();
    // Each triangle's corners as bit patterns (+0 for -0), rotated so the smallest comes first:
    // equal keys are equal oriented triangles whatever corner the file starts with.
    using Key = std::array<std::uint32_t, 9>;
    std::vector<Key> keys(n);
    for (std::size_t t = 0; t < n; ++t) {
        std::array<std::array<std::uint32_t, 3>, 3> corner;
        for (int c = 0; c < 3; ++c) {
            const glm::vec3 p = mesh.vertex(t, c) + glm::vec3(0.0f);
            std::memcpy(corner[std::size_t(c)].data(), &p, sizeof(p));
        }
        const std::size_t start = std::size_t(std::min_element(corner.begin(), corner.end()) - corner.begin());
        for (std::size_t c = 0; c < 3; ++c) {
            const auto& from = corner[(start + c) % 3];
            std::copy(from.begin(), from.end(), keys[t].begin() + std::ptrdiff_t(3 * c));
        }
    }
    // Sorted by a hash first (cheap to compare), the full key on ties, then by index so the first
    // copy leads its run.
    std::vector<std::uint64_t> hash(n);
    for (std::size_t t = 0; t < n; ++t) {
        std::uint64_t h = 0x9e3779b97f4a7c15ull;
        for (std::uint32_t word : keys[t]) h = (h ^ word) * 0x100000001b3ull;
        hash[t] = h ^ (h >> 29);
    }
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
        if (hash[a] != hash[b]) return hash[a] < hash[b];
        if (keys[a] != keys[b]) return keys[a] < keys[b];
        return a < b;
    });

    TriangleCopies copies;
    copies.first.resize(n);
    for (std::size_t begin = 0; begin < n;) {
        std::size_t end = begin + 1;
        while (end < n && keys[order[end]] == keys[order[begin]]) ++end;
        for (std::size_t i = begin; i < end; ++i) copies.first[order[i]] = order[begin];
        begin = end;
    }
    std::vector<std::uint32_t> countOf(n, 0);
    for (std::size_t t = 0; t < n; ++t) ++countOf[copies.first[t]];
    for (std::uint32_t t = 0; t < n; ++t) {
        if (copies.first[t] != t) continue;
        copies.unique.push_back(t);
        copies.count.push_back(countOf[t]);
    }
    return copies;
}

} // namespace sdfgen
