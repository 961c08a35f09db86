// compareFields: identical, negated, banded and mismatched fields.
#include "sdfgen/compare.hpp"
#include "sdfgen/error.hpp"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <vector>

namespace sdfgen {
namespace {

Field rampField(glm::ivec3 dims) {
    Field f;
    f.grid.origin = {-1, -1, -1};
    f.grid.voxel = 0.25f;
    f.grid.dims = dims;
    f.values.resize(f.grid.sampleCount());
    for (int k = 0; k < dims.z; ++k)
        for (int j = 0; j < dims.y; ++j)
            for (int i = 0; i < dims.x; ++i) f.values[f.grid.index(i, j, k)] = glm::length(glm::vec3(f.grid.position(i, j, k))) - 0.6f;
    return f;
}

TEST(CompareFields, IdenticalNegatedBandAndMismatch) {
    const Field a = rampField({8, 8, 8});
    FieldDifference d = compareFields(a, a, 0.0);
    EXPECT_EQ(d.maxAbs, 0.0);
    EXPECT_EQ(d.meanAbs, 0.0);
    EXPECT_EQ(d.rmsAbs, 0.0);
    EXPECT_EQ(d.signDifferences, 0u);
    EXPECT_EQ(d.compared, a.grid.sampleCount());
    EXPECT_EQ(d.voxel, double(a.grid.voxel));
    EXPECT_EQ(d.signFraction(), 0.0);

    // One far sample negated: one sign difference, the max twice its magnitude.
    Field b = a;
    const std::size_t far = a.grid.index(0, 0, 0);
    b.values[far] = -b.values[far];
    d = compareFields(a, b, 0.0);
    EXPECT_EQ(d.signDifferences, 1u);
    EXPECT_DOUBLE_EQ(d.maxAbs, 2.0 * std::fabs(double(a.values[far])));
    EXPECT_DOUBLE_EQ(d.meanAbs, 2.0 * std::fabs(double(a.values[far])) / double(a.grid.sampleCount()));
    EXPECT_DOUBLE_EQ(d.signFraction(), 1.0 / double(a.grid.sampleCount()));
    EXPECT_EQ(compareFields(b, a, 0.0).signDifferences, 1u); // symmetric

    // A near-surface sample negated is excluded by a band wider than its distance.
    Field c = a;
    std::size_t nearest = 0;
    for (std::size_t i = 0; i < a.values.size(); ++i) {
        if (std::fabs(a.values[i]) < std::fabs(a.values[nearest])) nearest = i;
    }
    const double nearVoxels = std::fabs(a.values[nearest]) / a.grid.voxel;
    ASSERT_LT(nearVoxels, 1.0);
    c.values[nearest] = -c.values[nearest];
    EXPECT_EQ(compareFields(a, c, 0.0).signDifferences, 1u);
    d = compareFields(a, c, 1.0);
    EXPECT_EQ(d.signDifferences, 0u);
    EXPECT_EQ(d.maxAbs, 0.0);
    std::size_t inBand = 0;
    for (float v : a.values) inBand += std::fabs(v) < a.grid.voxel;
    EXPECT_EQ(d.compared, a.grid.sampleCount() - inBand);
    // The band is on either field: a sample moved into the band in one field is skipped too.
    Field e = a;
    e.values[far] = 0.0f;
    d = compareFields(a, e, 1.0);
    EXPECT_EQ(d.maxAbs, 0.0);
    EXPECT_EQ(d.compared, a.grid.sampleCount() - inBand - 1);

    // Different grids throw.
    EXPECT_THROW(compareFields(a, rampField({8, 8, 7}), 0.0), Error);
    Field moved = a;
    moved.grid.origin.x += 0.1f;
    EXPECT_THROW(compareFields(a, moved, 0.0), Error);
    Field scaled = a;
    scaled.grid.voxel *= 1.5f;
    EXPECT_THROW(compareFields(a, scaled, 0.0), Error);
}

TEST(CompareFields, ListsWhereTheSignsDiffer) {
    const Field a = rampField({8, 8, 8});
    Field b = a;
    const std::vector<std::size_t> flipped = {3, 70, 300, 511};
    for (const std::size_t i : flipped) b.values[i] = -b.values[i];
    std::vector<std::size_t> where = {42}; // replaced, not appended to
    const FieldDifference d = compareFields(a, b, 0.0, &where);
    EXPECT_EQ(where, flipped);
    EXPECT_EQ(d.signDifferences, where.size());
    // Within a band, as counted: the samples the band skips are not listed.
    const FieldDifference banded = compareFields(a, b, 100.0, &where);
    EXPECT_EQ(banded.signDifferences, 0u);
    EXPECT_TRUE(where.empty());
}

// Progress runs up to 1 in steps of at most a million samples, and a cancel raised from it stops
// the comparison with Cancelled; the result does not depend on the control.
TEST(CompareFields, ReportsProgressAndHonoursCancel) {
    const Field a = rampField({128, 128, 160}); // 2.6 million samples: three blocks
    Field b = a;
    for (std::size_t i = 0; i < b.values.size(); i += 1000) b.values[i] = -b.values[i];
    std::vector<double> reports;
    RunControl control;
    control.progress = [&](double fraction) { reports.push_back(fraction); };
    std::vector<std::size_t> where, plainWhere;
    const FieldDifference d = compareFields(a, b, 0.0, &where, control);
    const FieldDifference plain = compareFields(a, b, 0.0, &plainWhere);
    EXPECT_EQ(d.signDifferences, plain.signDifferences);
    EXPECT_EQ(d.maxAbs, plain.maxAbs);
    EXPECT_EQ(d.meanAbs, plain.meanAbs);
    EXPECT_EQ(where, plainWhere);
    ASSERT_GE(reports.size(), 3u);
    EXPECT_TRUE(std::is_sorted(reports.begin(), reports.end()));
    EXPECT_EQ(reports.back(), 1.0);

    std::atomic<bool> cancel{false};
    control.cancel = &cancel;
    control.progress = [&](double fraction) {
        if (fraction < 1.0) cancel = true;
    };
    EXPECT_THROW(compareFields(a, b, 0.0, &where, control), Cancelled);
}

} // namespace
} // namespace sdfgen
