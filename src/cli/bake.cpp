// `sdfgen bake`: mesh in, field file out.
#include "cli/commands.hpp"
#include "cli/progress.hpp"
#include "sdfgen/field.hpp"
#include "core/bvh.hpp"
#include "sdfgen/mesh.hpp"

#include <tbb/task_arena.h>
#include <cstdio>
#include <memory>

namespace sdfgen::cli {

namespace {

struct BakeArgs {
    std::string mesh;
    std::string output;
    BakeSettings settings;
    int threads = 0;
};

void runBake(const BakeArgs& args) {
    Stopwatch total;
    const Mesh mesh = loadObj(args.mesh);
    if (mesh.droppedDegenerate > 0) {
        std::fprintf(stderr, "sdfgen: warning: %s: dropped %zu zero-area triangles\n", args.mesh.c_str(), mesh.droppedDegenerate);
    }
    const Bvh tree(mesh);
    RunControl control;
    control.threads = args.threads;
    BakeResult result;
    {
        ProgressBar bar;
        control.progress = bar.callback();
        result = bake(mesh, tree, args.settings, control);
    }
    saveFieldText(result.field, args.output);
    const double seconds = total.seconds();
    const int threads = args.threads > 0 ? args.threads : tbb::this_task_arena::max_concurrency();
    const Grid& g = result.field.grid;
    std::printf("%s -> %s: %zu triangles, %dx%dx%d voxels, method %s, sign %s, %d threads, %.3f s, %.0f voxels/s\n",
                args.mesh.c_str(), args.output.c_str(), mesh.triangleCount(), g.dims.x, g.dims.y, g.dims.z,
                (result.field.method + (result.field.parameter("rays").empty() ? "" : " (" + result.field.parameter("rays") + " rays)")).c_str(),
                result.field.parameter("sign").c_str(), threads, seconds, double(g.sampleCount()) / seconds);
    if (result.checked) std::printf("mesh check: %s\nsign: auto chose %s\n", result.check.describe().c_str(), result.signReason.c_str());
    if (!result.deviceReason.empty()) std::printf("device: %s\n", result.deviceReason.c_str());
}

} // namespace

void addBakeCommand(CLI::App& app) {
    auto args = std::make_shared<BakeArgs>();
    CLI::App* bake = app.add_subcommand("bake", "Generate a signed distance field from an OBJ mesh and save it as text");
    bake->add_option("mesh", args->mesh, "Input mesh (Wavefront OBJ)")->required();
    bake->add_option("-o,--output", args->output, "Output field file (sdfgen-text, see docs/field-format.md)")->required();
    addBakeOptions(*bake, args->settings, args->threads);
    bake->footer("The summary line counts the whole process: load, tree, generation and save.");
    bake->callback([args] { runBake(*args); });
}

} // namespace sdfgen::cli
