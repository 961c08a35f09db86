// `sdfgen compare`: how far two fields on the same grid are apart.
#include "cli/commands.hpp"
#include "sdfgen/compare.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/field.hpp"
#include "sdfgen/formats.hpp"
#include "sdfgen/any_field.hpp"

#include <cstdio>
#include <memory>
#include <string>

namespace sdfgen::cli {

namespace {

struct CompareArgs {
    std::string first, second;
    double band = 0.0;
};

void runCompare(const CompareArgs& args) {
    // Both grids are checked before anything is made dense: band fields are compared sparse, and
    // one is made dense only beside a dense field of the same grid, which its file holds whole.
    AnyField a = loadAnyField(args.first);
    AnyField b = loadAnyField(args.second);
    FieldDifference d;
    try {
        checkSameGrid(a.header().grid, b.header().grid);
        if (a.isBand() && b.isBand()) {
            d = compareSparseFields(a.band(), b.band(), args.band);
        } else {
            for (AnyField* field : {&a, &b}) {
                if (field->isBand()) *field = field->band().toDense();
            }
            d = compareFields(a.dense(), b.dense(), args.band);
        }
    } catch (const Error& e) {
        throw Error(args.first + " vs " + args.second + ": " + e.what());
    }
    const double h = d.voxel;
    std::printf("%s vs %s: %zu of %zu samples compared (band %g voxels)\n", args.first.c_str(), args.second.c_str(),
                d.compared, a.header().grid.sampleCount(), args.band);
    std::string bands; // the band fields among the two: compared by value in their band, by sign outside
    for (const auto& [name, field] : {std::pair{&args.first, &a}, {&args.second, &b}}) {
        if (const float background = field->header().background; background > 0) {
            char band[64];
            std::snprintf(band, sizeof band, " (|d| < %g, %.4g voxels)", double(background), double(background) / h);
            bands += (bands.empty() ? "" : ", ") + *name + band;
        }
    }
    if (!bands.empty()) {
        std::printf("band fields %s: values compared where |d| is below the band, %zu samples outside it compared by sign only\n",
                    bands.c_str(), d.signOnly);
    }
    std::printf("abs difference: max %.6g (%.4g voxels), mean %.6g (%.4g voxels), rms %.6g (%.4g voxels)\n", d.maxAbs,
                d.maxAbs / h, d.meanAbs, d.meanAbs / h, d.rmsAbs, d.rmsAbs / h);
    std::printf("signs differ: %zu samples (%.4f%%)\n", d.signDifferences, 100.0 * d.signFraction());
}

} // namespace

void addCompareCommand(CLI::App& app) {
    auto args = std::make_shared<CompareArgs>();
    CLI::App* compare = app.add_subcommand("compare", "Compare two fields on the same grid: distance error and sign disagreements");
    compare->add_option("first", args->first, "A field file (e.g. the reference): " + fieldFormatList())->required();
    compare->add_option("second", args->second, "A field file on the same grid")->required();
    compare->add_option("--band", args->band, "Ignore samples within this many voxels of the surface in either field")
        ->check(finiteRange(0.0, 1e9))
        ->capture_default_str();
    compare->callback([args] { runCompare(*args); });
}

} // namespace sdfgen::cli
