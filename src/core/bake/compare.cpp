#include "sdfgen/compare.hpp"
#include "core/runtime/parallel.hpp"
#include "sdfgen/error.hpp"

#include <glm/common.hpp>
#include <algorithm>
#include <cmath>
#include <tuple>

namespace sdfgen {

namespace {

// The one rule for a pair of samples, dense or sparse: skipped within `band` of the surface in
// either field; by sign only outside a band field's band; by value elsewhere.
class Tally {
public:
    Tally(double band, float backgroundA, float backgroundB) : band_(band), backgroundA_(backgroundA), backgroundB_(backgroundB) {}

    // Returns whether the pair counts as a sign difference.
    bool add(double va, double vb) {
        if (std::min(std::fabs(va), std::fabs(vb)) < band_) return false;
        const bool differ = (va < 0) != (vb < 0);
        d_.signDifferences += differ;
        if ((backgroundA_ > 0 && std::fabs(va) >= backgroundA_) || (backgroundB_ > 0 && std::fabs(vb) >= backgroundB_)) {
            ++d_.signOnly;
            return differ;
        }
        const double diff = std::fabs(va - vb);
        d_.maxAbs = std::max(d_.maxAbs, diff);
        sum_ += diff;
        sumSquares_ += diff * diff;
        ++d_.compared;
        return differ;
    }

    // `count` samples outside both band fields' bricks (each +-background), `differ` of them on
    // different sides: what add() would make of them one by one.
    void addOutsideBricks(std::uint64_t count, std::uint64_t differ) {
        if (std::min(backgroundA_, backgroundB_) < band_) return;
        d_.signOnly += count;
        d_.signDifferences += differ;
    }

    FieldDifference result(double voxel) {
        d_.voxel = voxel;
        if (d_.compared) {
            d_.meanAbs = sum_ / double(d_.compared);
            d_.rmsAbs = std::sqrt(sumSquares_ / double(d_.compared));
        }
        return d_;
    }

private:
    double band_;
    float backgroundA_, backgroundB_;
    FieldDifference d_;
    double sum_ = 0, sumSquares_ = 0;
};

bool before(const glm::ivec3& a, const glm::ivec3& b) { return std::tie(a.z, a.y, a.x) < std::tie(b.z, b.y, b.x); }

std::uint64_t samplesIn(const std::array<int, 6>& box) {
    return std::uint64_t(box[3] - box[0]) * std::uint64_t(box[4] - box[1]) * std::uint64_t(box[5] - box[2]);
}

// The samples two fields' inside boxes share (each field's boxes disjoint and in z, y, x order).
std::uint64_t sharedInsideSamples(const std::vector<std::array<int, 6>>& a, const std::vector<std::array<int, 6>>& b) {
    std::uint64_t shared = 0;
    for (std::size_t i = 0, j = 0; i < a.size() && j < b.size();) {
        const auto rowA = std::tie(a[i][2], a[i][1]), rowB = std::tie(b[j][2], b[j][1]);
        if (rowA < rowB) {
            ++i;
        } else if (rowB < rowA) {
            ++j;
        } else {
            const int overlap = std::min(a[i][3], b[j][3]) - std::max(a[i][0], b[j][0]);
            if (overlap > 0) shared += std::uint64_t(overlap) * std::uint64_t(a[i][4] - a[i][1]) * std::uint64_t(a[i][5] - a[i][2]);
            (a[i][3] < b[j][3] ? i : j)++;
        }
    }
    return shared;
}

} // namespace

void checkSameGrid(const Grid& ga, const Grid& gb) {
    if (ga.dims != gb.dims) {
        throw Error("the fields have different grids: " + std::to_string(ga.dims.x) + "x" + std::to_string(ga.dims.y) + "x" +
                    std::to_string(ga.dims.z) + " and " + std::to_string(gb.dims.x) + "x" + std::to_string(gb.dims.y) + "x" +
                    std::to_string(gb.dims.z));
    }
    // Same sample positions to within a thousandth of a voxel (text round trips are exact anyway).
    const double tolerance = 1e-3 * ga.voxel;
    const glm::dvec3 offset = glm::abs(ga.origin - gb.origin);
    if (std::max({offset.x, offset.y, offset.z}) > tolerance || std::fabs(ga.voxel - gb.voxel) > tolerance) {
        throw Error("the fields' grids have the same dimensions but different origins or voxel sizes");
    }
}

FieldDifference compareFields(const Field& a, const Field& b, double bandVoxels, std::vector<std::size_t>* signDifferences,
                              const RunControl& control) {
    throwIfCancelled(control);
    checkSameGrid(a.grid, b.grid);
    Tally tally(bandVoxels * a.grid.voxel, a.background, b.background);
    if (signDifferences) signDifferences->clear();
    constexpr std::size_t kChunk = std::size_t(1) << 20;
    const std::size_t count = a.values.size();
    ProgressCounter progress(control, count);
    for (std::size_t start = 0; start < count; start += kChunk) {
        const std::size_t end = std::min(count, start + kChunk);
        for (std::size_t i = start; i < end; ++i) {
            if (tally.add(a.values[i], b.values[i]) && signDifferences) signDifferences->push_back(i);
        }
        progress.add(end - start);
    }
    progress.finish();
    return tally.result(a.grid.voxel);
}

FieldDifference compareSparseFields(const SparseField& a, const SparseField& b, double bandVoxels) {
    checkSameGrid(a.grid(), b.grid());
    constexpr int B = SparseField::kBrick;
    const glm::ivec3 dims = a.grid().dims;
    Tally tally(bandVoxels * a.grid().voxel, a.background(), b.background());
    // Sample by sample in the bricks either field stores, walking both brick lists in their order;
    // a field without the brick holds one value there (+-background, from its inside boxes).
    std::uint64_t brickSamples = 0;
    std::uint64_t insideA = 0, insideB = 0; // samples of each's inside boxes, less those in the other's bricks
    for (const auto& box : a.insideBoxes()) insideA += samplesIn(box);
    for (const auto& box : b.insideBoxes()) insideB += samplesIn(box);
    for (std::size_t ia = 0, ib = 0; ia < a.bricks().size() || ib < b.bricks().size();) {
        const bool inA = ib == b.bricks().size() || (ia < a.bricks().size() && !before(b.bricks()[ib], a.bricks()[ia]));
        const bool inB = ia == a.bricks().size() || (ib < b.bricks().size() && !before(a.bricks()[ia], b.bricks()[ib]));
        const glm::ivec3 lo = (inA ? a.bricks()[ia] : b.bricks()[ib]) * B, hi = glm::min(lo + B, dims);
        const std::uint64_t samples = std::uint64_t(hi.x - lo.x) * std::uint64_t(hi.y - lo.y) * std::uint64_t(hi.z - lo.z);
        const float* valuesA = inA ? &a.values()[ia * SparseField::kBrickSamples] : nullptr;
        const float* valuesB = inB ? &b.values()[ib * SparseField::kBrickSamples] : nullptr;
        const float sideA = inA ? 0.0f : a.at(lo.x, lo.y, lo.z), sideB = inB ? 0.0f : b.at(lo.x, lo.y, lo.z);
        if (!inA && sideA < 0) insideA -= samples;
        if (!inB && sideB < 0) insideB -= samples;
        for (int k = lo.z; k < hi.z; ++k)
            for (int j = lo.y; j < hi.y; ++j)
                for (int i = lo.x; i < hi.x; ++i) {
                    const int n = ((k - lo.z) * B + (j - lo.y)) * B + (i - lo.x);
                    tally.add(valuesA ? valuesA[n] : sideA, valuesB ? valuesB[n] : sideB);
                }
        brickSamples += samples;
        ia += inA;
        ib += inB;
    }
    // The rest: both at +-background, on different sides where exactly one is inside (inside
    // boxes never hold their own field's bricks, so the shared ones hold no brick at all).
    const std::uint64_t rest = Grid::checkedSampleCount(dims) - brickSamples;
    tally.addOutsideBricks(rest, insideA + insideB - 2 * sharedInsideSamples(a.insideBoxes(), b.insideBoxes()));
    return tally.result(a.grid().voxel);
}

} // namespace sdfgen
