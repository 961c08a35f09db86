#include "core/mesh/triangle_copies.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <utility>

namespace sdfgen {

namespace {

// A triangle's corners as bit patterns (+0 for -0), in the rotation that is lexicographically
// smallest: equal keys are equal oriented triangles whatever corner the file starts with
// (degenerate ones with repeated corners included).
using Key = std::array<std::uint32_t, 9>;

Key keyOf(const Mesh& mesh, std::size_t t) {
    std::array<std::array<std::uint32_t, 3>, 3> corner;
    for (int c = 0; c < 3; ++c) {
        const glm::vec3 p = mesh.vertex(t, c) + glm::vec3(0.0f);
        std::memcpy(corner[std::size_t(c)].data(), &p, sizeof(p));
    }
    auto rotation = [&](std::size_t start) {
        Key key;
        for (std::size_t c = 0; c < 3; ++c) {
            const auto& from = corner[(start + c) % 3];
            std::copy(from.begin(), from.end(), key.begin() + std::ptrdiff_t(3 * c));
        }
        return key;
    };
    return std::min({rotation(0), rotation(1), rotation(2)});
}

} // namespace

TriangleCopies findTriangleCopies(const Mesh& mesh) {
    const std::size_t n = mesh.triangleCount();
    // Sorted by a hash of the key (cheap to keep and compare), then by index so that the first copy
    // leads its run. A run of equal hashes is almost always one key; only when it is not (a hash
    // collision) is it sorted by the key itself.
    // In parallel (in the caller's task arena): the order is total, so the result is the same for
    // any thread count. The (hash, index) pairs are sorted themselves: no indirection in the
    // comparisons.
    std::vector<std::pair<std::uint64_t, std::uint32_t>> sorted(n);
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t t) {
        std::uint64_t h = 0x9e3779b97f4a7c15ull;
        for (std::uint32_t word : keyOf(mesh, t)) h = (h ^ word) * 0x100000001b3ull;
        sorted[t] = {h ^ (h >> 29), std::uint32_t(t)};
    });
    tbb::parallel_sort(sorted.begin(), sorted.end());
    std::vector<std::uint32_t> order(n);
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) { order[i] = sorted[i].second; });

    TriangleCopies copies;
    copies.first.resize(n);
    for (std::size_t begin = 0; begin < n;) {
        std::size_t end = begin + 1;
        while (end < n && sorted[end].first == sorted[begin].first) ++end;
        if (end == begin + 1) { // a hash of its own: a triangle without copies
            copies.first[order[begin]] = order[begin];
            begin = end;
            continue;
        }
        const Key key = keyOf(mesh, order[begin]);
        bool oneKey = true;
        for (std::size_t i = begin + 1; i < end && oneKey; ++i) oneKey = keyOf(mesh, order[i]) == key;
        if (!oneKey) {
            std::sort(order.begin() + std::ptrdiff_t(begin), order.begin() + std::ptrdiff_t(end), [&](std::uint32_t a, std::uint32_t b) {
                const Key ka = keyOf(mesh, a), kb = keyOf(mesh, b);
                return ka != kb ? ka < kb : a < b;
            });
        }
        for (std::size_t i = begin; i < end;) {
            const Key first = keyOf(mesh, order[i]);
            std::size_t last = i + 1;
            while (last < end && (oneKey || keyOf(mesh, order[last]) == first)) ++last;
            for (std::size_t c = i; c < last; ++c) copies.first[order[c]] = order[i];
            i = last;
        }
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
