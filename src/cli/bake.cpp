// `sdfgen bake`: mesh in, field file out.
#include "cli/commands.hpp"
#include "sdfgen/model.hpp"
#include "cli/progress.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/field.hpp"
#include "sdfgen/formats.hpp"
#include "sdfgen/mesh.hpp"
#include "core/runtime/file_extension.hpp"

#include <tbb/task_arena.h>
#include <cstdio>
#include <filesystem>
#include <memory>

namespace sdfgen::cli {

namespace {

struct BakeArgs {
    std::vector<std::string> meshes;
    std::string output;
    BakeSettings settings;
    SaveOptions save;
    std::string channels = "sdf";
    int threads = 0;
};

void runBake(BakeArgs args) {
    Stopwatch total;
    args.settings.channels = parseChannels(args.channels);
    if (args.settings.band > 0 && args.settings.channels.any()) {
        // Channels come from the dense bake: its .vdb keeps the band's voxels (and theirs) only.
        if (lowerExtension(args.output) != ".vdb") throw Error("--band with --channels applies to .vdb output only (" + args.output + ")");
        args.save.band = args.settings.band;
        args.settings.band = 0;
    }
    checkBakeSettings(args.settings);
    refuseOverwritingInput(args.output, args.meshes);
    if (args.settings.channels.any()) checkFormatHoldsChannels(args.output, args.settings.channels); // before the bake, not after
    RunControl control = commandControl(args.threads);
    const Model model(loadScene(args.meshes), control);
    const Mesh& mesh = model.mesh();
    BakeResult result;
    {
        ProgressBar bar;
        control.progress = bar.callback();
        result = model.bake(args.settings, control);
    }
    const FieldHeader field = result.field.header(); // kept: saving a band field gives it up
    std::string bandLine;                            // the band's figures, taken before the save
    if (result.field.isBand()) {
        const SparseField& band = result.field.band();
        char line[512];
        std::snprintf(line, sizeof line,
                      "band: %g voxels each side (background %g): %zu bricks of 8^3, %zu samples in the band, %zu inside boxes; "
                      "tree and topology %.2f s, distances %.2f s, bricks and sides %.2f s (the search for the bricks %.2f s)\n",
                      args.settings.band, double(band.background()), band.bricks().size(), band.activeCount(), band.insideBoxes().size(),
                      result.setupSeconds, result.distanceSeconds, result.signSeconds, result.searchSeconds);
        bandLine = line;
    }
    saveAnyField(std::move(result.field), args.output, args.save);
    const double seconds = total.seconds();
    const int threads = args.threads > 0 ? args.threads : tbb::this_task_arena::max_concurrency();
    const Grid& g = field.grid;
    std::printf("%s -> %s: %zu triangles, %dx%dx%d voxels, method %s, sign %s, %d threads, %.3f s, %.0f voxels/s\n",
                mesh.source.c_str(), args.output.c_str(), mesh.triangleCount(), g.dims.x, g.dims.y, g.dims.z,
                (field.method + (field.parameter("rays").empty() ? "" : " (" + field.parameter("rays") + " rays)")).c_str(),
                field.parameter("sign").c_str(), threads, seconds, double(g.sampleCount()) / seconds);
    if (args.settings.channels.any()) std::printf("channels: %s\n", toString(args.settings.channels).c_str());
    std::fputs(bandLine.c_str(), stdout);
    if (result.checked) std::printf("mesh check: %s\nsign: auto chose %s\n", result.check.describe().c_str(), result.signReason.c_str());
    if (!result.deviceReason.empty()) std::printf("device: %s\n", result.deviceReason.c_str());
}

} // namespace

void addBakeCommand(CLI::App& app) {
    auto args = std::make_shared<BakeArgs>();
    CLI::App* bake = app.add_subcommand("bake", "Generate a signed distance field from a mesh and save it (format from the extension)");
    bake->add_option("mesh", args->meshes, "Input mesh (" + meshFormatList() + ", ...); several give the field of their union")->required();
    bake->add_option("-o,--output", args->output, "Output field file: " + fieldFormatList() + " (docs/field-format.md)")->required();
    bake->add_option("--band", args->settings.band,
                     "Narrow band: exact distances only within this many voxels of the surface (at least 1), the rest only "
                     "its side; sparse in .vdb and .npz, never a dense grid in memory (0 = the dense field). With --channels: "
                     "the dense bake, of which the .vdb keeps the band")
        ->capture_default_str();
    bake->add_option("--channels", args->channels,
                     "What each sample holds, comma-separated: sdf (the signed distance, always), " + describeChannels() + "; for " +
                         channelFormatList() + ", --method exact")
        ->capture_default_str();
    addBakeOptions(*bake, args->settings, args->threads);
    std::string formats = "Field formats (from the output's extension):";
    for (const FieldFormatInfo& format : knownFieldFormats()) formats += std::string("\n  ") + format.extension + "  " + format.description;
    bake->footer(formats + "\nThe summary line counts the whole process: load, tree, generation and save."
                           "\nA glTF's external buffers and images are read only from its folder and subfolders; "
                           "SDFGEN_GLTF_FOLDERS=DIR[:DIR...] allows more folders.");
    bake->callback([args] { runBake(*args); });
}

} // namespace sdfgen::cli
