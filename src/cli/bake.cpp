// `sdfgen bake`: mesh in, field file out.
#include "cli/commands.hpp"
#include "sdfgen/model.hpp"
#include "cli/progress.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/field.hpp"
#include "sdfgen/formats.hpp"
#include "sdfgen/mesh.hpp"

#include <tbb/task_arena.h>
#include <cctype>
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
    std::string extension = std::filesystem::path(args.output).extension().string();
    for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (args.save.band > 0 && extension != ".vdb") {
        throw Error("--band applies to .vdb output only (" + args.output + ")");
    }
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
    saveField(result.field, args.output, args.save);
    const double seconds = total.seconds();
    const int threads = args.threads > 0 ? args.threads : tbb::this_task_arena::max_concurrency();
    const Grid& g = result.field.grid;
    std::printf("%s -> %s: %zu triangles, %dx%dx%d voxels, method %s, sign %s, %d threads, %.3f s, %.0f voxels/s\n",
                mesh.source.c_str(), args.output.c_str(), mesh.triangleCount(), g.dims.x, g.dims.y, g.dims.z,
                (result.field.method + (result.field.parameter("rays").empty() ? "" : " (" + result.field.parameter("rays") + " rays)")).c_str(),
                result.field.parameter("sign").c_str(), threads, seconds, double(g.sampleCount()) / seconds);
    if (args.settings.channels.any()) std::printf("channels: %s\n", toString(args.settings.channels).c_str());
    if (result.checked) std::printf("mesh check: %s\nsign: auto chose %s\n", result.check.describe().c_str(), result.signReason.c_str());
    if (!result.deviceReason.empty()) std::printf("device: %s\n", result.deviceReason.c_str());
}

} // namespace

void addBakeCommand(CLI::App& app) {
    auto args = std::make_shared<BakeArgs>();
    CLI::App* bake = app.add_subcommand("bake", "Generate a signed distance field from a mesh and save it (format from the extension)");
    bake->add_option("mesh", args->meshes, "Input mesh (" + meshFormatList() + ", ...); several give the field of their union")->required();
    bake->add_option("-o,--output", args->output, "Output field file: " + fieldFormatList() + " (docs/field-format.md)")->required();
    bake->add_option("--band", args->save.band, "For .vdb: keep only voxels within this many voxels of the surface (0 = dense)")
        ->check(finiteRange(0.0, 1e9))
        ->capture_default_str();
    bake->add_option("--channels", args->channels,
                     "What each sample holds, comma-separated: sdf (the signed distance, always), gradient (its unit gradient), "
                     "closest (the nearest surface point), triangle (the nearest triangle's index); for " + channelFormatList() +
                         ", --method exact")
        ->capture_default_str();
    addBakeOptions(*bake, args->settings, args->threads);
    std::string formats = "Field formats (from the output's extension):";
    for (const FieldFormatInfo& format : knownFieldFormats()) formats += std::string("\n  ") + format.extension + "  " + format.description;
    bake->footer(formats + "\nThe summary line counts the whole process: load, tree, generation and save.");
    bake->callback([args] { runBake(*args); });
}

} // namespace sdfgen::cli
