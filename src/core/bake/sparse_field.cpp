#include "sdfgen/sparse_field.hpp"
#include "sdfgen/error.hpp"
#include "core/runtime/memory.hpp"
#include "core/runtime/parallel.hpp"

#include <glm/common.hpp>
#include <algorithm>
#include <atomic>
#include <functional>
#include <cmath>
#include <tuple>

namespace sdfgen {

namespace {

// Bricks and boxes are ordered by z, then y, then x.
bool before(const glm::ivec3& a, const glm::ivec3& b) { return std::tie(a.z, a.y, a.x) < std::tie(b.z, b.y, b.x); }

// Runs body(chunk, first, last) over the bricks [0, count) in chunks of kChunk, on every thread
// (a band's values are hundreds of megabytes).
constexpr std::size_t kChunk = 4096; // bricks (8 MB of values)
void forEachChunk(std::size_t count, const std::function<void(std::size_t, std::size_t, std::size_t)>& body) {
    parallelFor((count + kChunk - 1) / kChunk, RunControl{}, [&](std::size_t chunk) {
        body(chunk, chunk * kChunk, std::min(count, (chunk + 1) * kChunk));
    });
}

} // namespace

SparseField::SparseField(const FieldHeader& header, Storage storage, const std::string& where)
    : FieldHeader(header), storage_(std::move(storage)) {
    check(where);
}

SparseField::Storage SparseField::release() {
    Storage taken = std::move(storage_);
    storage_ = {};
    return taken;
}

float SparseField::at(int i, int j, int k) const {
    const glm::ivec3 brick(i / kBrick, j / kBrick, k / kBrick);
    const auto found = std::lower_bound(bricks().begin(), bricks().end(), brick, before);
    if (found != bricks().end() && *found == brick) {
        const std::size_t b = std::size_t(found - bricks().begin());
        return values()[b * kBrickSamples + std::size_t(((k % kBrick) * kBrick + j % kBrick) * kBrick + i % kBrick)];
    }
    // The last box of the sample's brick row that starts at or before it.
    const glm::ivec3 key(i, brick.y * kBrick, brick.z * kBrick);
    const auto box = std::upper_bound(insideBoxes().begin(), insideBoxes().end(), key, [](const glm::ivec3& p, const std::array<int, 6>& b) {
        return std::tie(p.z, p.y, p.x) < std::tie(b[2], b[1], b[0]);
    });
    if (box != insideBoxes().begin()) {
        const auto& b = *std::prev(box);
        if (b[2] == key.z && b[1] == key.y && i < b[3]) return -background();
    }
    return background();
}

bool SparseField::inBand(int i, int j, int k) const { return std::fabs(at(i, j, k)) < background(); }

float SparseField::sample(const glm::dvec3& position) const {
    const glm::dvec3 g = glm::clamp((position - grid().origin) / grid().voxel - 0.5, glm::dvec3(0.0), glm::dvec3(grid().dims - 1));
    const glm::ivec3 lo = glm::min(glm::ivec3(glm::floor(g)), glm::max(grid().dims - 2, 0));
    const glm::dvec3 t = g - glm::dvec3(lo);
    double sum = 0.0;
    for (int c = 0; c < 8; ++c) {
        const glm::ivec3 o(c & 1, c >> 1 & 1, c >> 2 & 1);
        const glm::ivec3 s = glm::min(lo + o, grid().dims - 1);
        const double w = (o.x ? t.x : 1.0 - t.x) * (o.y ? t.y : 1.0 - t.y) * (o.z ? t.z : 1.0 - t.z);
        if (w != 0.0) sum += w * double(at(s.x, s.y, s.z));
    }
    return float(sum);
}

std::size_t SparseField::activeCount() const {
    std::vector<std::size_t> counts((bricks().size() + kChunk - 1) / kChunk);
    forEachChunk(bricks().size(), [&](std::size_t chunk, std::size_t first, std::size_t last) {
        std::size_t count = 0;
        for (std::size_t b = first; b < last; ++b) {
            const glm::ivec3 lo = bricks()[b] * kBrick, hi = glm::min(lo + kBrick, grid().dims);
            for (int k = lo.z; k < hi.z; ++k)
                for (int j = lo.y; j < hi.y; ++j)
                    for (int i = lo.x; i < hi.x; ++i) {
                        const float v = values()[b * kBrickSamples + std::size_t(((k - lo.z) * kBrick + (j - lo.y)) * kBrick + (i - lo.x))];
                        count += std::fabs(v) < background();
                    }
        }
        counts[chunk] = count;
    });
    std::size_t count = 0;
    for (const std::size_t c : counts) count += c;
    return count;
}

Field SparseField::toDense() const {
    const std::uint64_t samples = Grid::checkedSampleCount(grid().dims);
    if (samples == 0) {
        throw Error("this " + std::to_string(grid().dims.x) + "x" + std::to_string(grid().dims.y) + "x" + std::to_string(grid().dims.z) +
                    " band field has no dense form: its grid has no samples or more than 2^58");
    }
    const double bytes = double(samples) * sizeof(float);
    const std::uint64_t available = availableMemoryBytes();
    if (available > 0 && bytes > double(available)) {
        throw Error("the dense form of this " + std::to_string(grid().dims.x) + "x" + std::to_string(grid().dims.y) + "x" +
                    std::to_string(grid().dims.z) + " band field needs " + mebibytes(bytes) + " but only " +
                    mebibytes(double(available)) + " of memory is available; keep it sparse (.vdb or .npz)");
    }
    Field field;
    static_cast<FieldHeader&>(field) = *this;
    field.values.assign(grid().sampleCount(), background());
    for (const auto& box : insideBoxes()) {
        for (int k = box[2]; k < box[5]; ++k)
            for (int j = box[1]; j < box[4]; ++j)
                std::fill_n(field.values.begin() + std::ptrdiff_t(grid().index(box[0], j, k)), box[3] - box[0], -background());
    }
    for (std::size_t b = 0; b < bricks().size(); ++b) {
        const glm::ivec3 lo = bricks()[b] * kBrick, hi = glm::min(lo + kBrick, grid().dims);
        for (int k = lo.z; k < hi.z; ++k)
            for (int j = lo.y; j < hi.y; ++j) {
                const float* row = &values()[b * kBrickSamples + std::size_t(((k - lo.z) * kBrick + (j - lo.y)) * kBrick)];
                std::copy(row, row + (hi.x - lo.x), field.values.begin() + std::ptrdiff_t(grid().index(lo.x, j, k)));
            }
    }
    return field;
}

std::string FieldHeader::parameter(const std::string& key) const {
    for (const auto& [name, value] : parameters) {
        if (name == key) return value;
    }
    return "";
}

std::array<int, 6> SparseField::insideBox(const glm::ivec3& dims, int x0, int x1, int y, int z) {
    return {x0 * kBrick, y * kBrick, z * kBrick, std::min(x1 * kBrick, dims.x), std::min(y * kBrick + kBrick, dims.y), std::min(z * kBrick + kBrick, dims.z)};
}

void SparseField::check(const std::string& path) const {
    auto fail = [&](const std::string& problem) { throw Error(path + ": " + problem); };
    if (!(background() > 0.0f) || !std::isfinite(background())) fail("the band's background is not a positive finite number");
    if (grid().dims.x < 1 || grid().dims.y < 1 || grid().dims.z < 1) fail("the grid has no samples");
    if (Grid::checkedSampleCount(grid().dims) == 0) {
        fail("the grid " + std::to_string(grid().dims.x) + "x" + std::to_string(grid().dims.y) + "x" + std::to_string(grid().dims.z) +
             " has more than 2^58 samples");
    }
    const glm::ivec3 brickDims = (grid().dims + (kBrick - 1)) / kBrick;
    if (values().size() / kBrickSamples != bricks().size() || values().size() % kBrickSamples != 0) {
        fail("the brick values do not match the bricks (" + std::to_string(values().size()) + " values for " +
             std::to_string(bricks().size()) + " bricks of 512)");
    }
    for (std::size_t b = 0; b < bricks().size(); ++b) {
        const glm::ivec3& brick = bricks()[b];
        if (glm::any(glm::lessThan(brick, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(brick, brickDims))) {
            fail("brick " + std::to_string(b) + " lies outside the grid");
        }
        if (b > 0 && !before(bricks()[b - 1], brick)) fail("the bricks are not in z, y, x order or repeat one");
    }
    std::atomic<bool> bad{false};
    forEachChunk(bricks().size(), [&](std::size_t, std::size_t first, std::size_t last) {
        bool chunkBad = false; // no early exit: the loop vectorizes (NaN fails the comparison)
        for (std::size_t n = first * kBrickSamples; n < last * kBrickSamples; ++n) chunkBad |= !(std::fabs(values()[n]) <= background());
        if (chunkBad) bad = true;
    });
    if (bad) fail("a brick value is not finite or exceeds the background");
    for (std::size_t n = 0; n < insideBoxes().size(); ++n) {
        const auto& box = insideBoxes()[n];
        for (int a = 0; a < 3; ++a) {
            if (box[a] < 0 || box[a] >= box[a + 3] || box[a + 3] > grid().dims[a]) fail("inside box " + std::to_string(n) + " is empty or leaves the grid");
        }
        for (int a = 1; a < 3; ++a) {
            if (box[a] % kBrick != 0 || box[a + 3] != std::min(box[a] + kBrick, grid().dims[a])) fail("inside box " + std::to_string(n) + " is not one row of bricks");
        }
        if (box[0] % kBrick != 0 || (box[3] % kBrick != 0 && box[3] != grid().dims.x)) fail("inside box " + std::to_string(n) + " does not hold whole bricks");
        if (n > 0) {
            const auto& last = insideBoxes()[n - 1];
            if (std::tie(last[2], last[1], last[0]) >= std::tie(box[2], box[1], box[0])) fail("the inside boxes are not in z, y, x order");
            // at() looks in the last box of the row starting at or before a sample: boxes that
            // overlap would make it disagree with toDense().
            if (last[2] == box[2] && last[1] == box[1] && last[3] > box[0]) {
                fail("inside boxes " + std::to_string(n - 1) + " and " + std::to_string(n) + " overlap");
            }
        }
        // Boxes hold no stored brick of their own field (what compareSparseFields counts on).
        const glm::ivec3 first(box[0] / kBrick, box[1] / kBrick, box[2] / kBrick);
        const auto brick = std::lower_bound(bricks().begin(), bricks().end(), first, before);
        if (brick != bricks().end() && brick->z == first.z && brick->y == first.y && brick->x * kBrick < box[3]) {
            fail("inside box " + std::to_string(n) + " holds stored brick " + std::to_string(brick - bricks().begin()));
        }
    }
}

} // namespace sdfgen
