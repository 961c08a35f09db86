// `sdfgen bench`: throughput of the whole bake (load, tree, distances, signs, save) on given meshes.
#include "cli/commands.hpp"
#include "sdfgen/model.hpp"
#include "cli/progress.hpp"
#include "sdfgen/field.hpp"
#include "sdfgen/formats.hpp"
#include "sdfgen/mesh.hpp"

#include <tbb/task_arena.h>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <unistd.h>

namespace sdfgen::cli {

namespace {

struct BenchArgs {
    std::vector<std::string> meshes;
    BakeSettings settings = [] {
        BakeSettings s;
        s.res = 128;
        return s;
    }();
    int threads = 0;
    int repeat = 1;
};

struct Timing {
    double load = 0, tree = 0, distance = 0, sign = 0, save = 0;
    double total() const { return load + tree + distance + sign + save; }
};

struct Run {
    Timing timing;
    std::size_t triangles = 0;
    Grid grid;
    std::string sign;
    bool rays = false;
    std::string device; // where it ran and why
};

// `warn`: whether this run prints the mesh's and bake's warnings (the first of a mesh's runs does).
Run runOnce(const std::string& path, const BenchArgs& args, const std::string& scratch, bool warn) {
    Run run;
    RunControl control = commandControl(args.threads);
    if (!warn) control.warn = nullptr;
    Stopwatch watch;
    Mesh loaded = loadMesh(path);
    run.timing.load = watch.seconds();
    watch = Stopwatch();
    const Model model(std::move(loaded), control);
    const Mesh& mesh = model.mesh();
    run.timing.tree = watch.seconds();
    const BakeResult result = model.bake(args.settings, control);
    run.timing.tree += result.setupSeconds; // the wide tree and the topology, built by the first bake
    run.timing.distance = result.distanceSeconds;
    run.timing.sign = result.signSeconds;
    watch = Stopwatch();
    saveField(result.field.dense(), scratch);
    run.timing.save = watch.seconds();
    run.triangles = mesh.triangleCount();
    run.grid = result.field.dense().grid;
    run.sign = result.field.dense().parameter("sign");
    run.rays = !result.field.dense().parameter("rays").empty();
    run.device = result.deviceReason;
    return run;
}

void runBench(const BenchArgs& args) {
    checkBakeSettings(args.settings);
    const std::vector<std::string> meshes = args.meshes.empty() ? std::vector<std::string>{defaultMeshPath()} : args.meshes;
    const int threads = args.threads > 0 ? args.threads : tbb::this_task_arena::max_concurrency();
    const std::string scratch =
        (std::filesystem::temp_directory_path() / ("sdfgen-bench-" + std::to_string(getpid()) + ".sdf")).string();
    std::printf("sdfgen bench: method %s, sign %s, res %d, %d rays, padding %g, %d threads, device %s, best of %d\n",
                toString(args.settings.method), toString(args.settings.sign), args.settings.res, args.settings.rays,
                double(args.settings.padding), threads, args.settings.device.c_str(), args.repeat);
    std::printf("%-22s %9s %13s %-22s %6s %6s %9s %7s %6s %8s %11s %11s %10s\n", "mesh", "triangles", "dims", "sign",
                "load", "tree", "distance", "sign", "save", "total s", "voxels/s", "gen vox/s", "rays/s");
    for (const std::string& path : meshes) {
        Run best;
        for (int r = 0; r < args.repeat; ++r) {
            const Run run = runOnce(path, args, scratch, r == 0);
            if (r == 0 || run.timing.total() < best.timing.total()) best = run;
        }
        std::filesystem::remove(scratch);
        const Timing& t = best.timing;
        const double samples = double(best.grid.sampleCount());
        const std::string dims = std::to_string(best.grid.dims.x) + "x" + std::to_string(best.grid.dims.y) + "x" +
                                 std::to_string(best.grid.dims.z);
        char rays[32] = "-";
        if (best.rays) std::snprintf(rays, sizeof(rays), "%.3g", samples * args.settings.rays / t.distance);
        std::printf("%-22s %9zu %13s %-22s %6.3f %6.3f %9.3f %7.3f %6.3f %8.3f %11.0f %11.0f %10s\n",
                    std::filesystem::path(path).filename().string().c_str(), best.triangles, dims.c_str(), best.sign.c_str(),
                    t.load, t.tree, t.distance, t.sign, t.save, t.total(), samples / t.total(),
                    samples / (t.distance + t.sign), rays);
        if (!best.device.empty()) std::printf("  device: %s\n", best.device.c_str());
    }
    std::puts("Seconds per phase; voxels/s counts the whole process, gen vox/s distances + signs; rays/s (ray method) "
              "counts the rays of the distance phase.");
}

} // namespace

void addBenchCommand(CLI::App& app) {
    auto args = std::make_shared<BenchArgs>();
    CLI::App* bench = app.add_subcommand("bench", "Measure bake throughput (voxels/s, rays/s) on one or more meshes");
    bench->add_option("meshes", args->meshes, "Meshes to bake (default: the bundled bunny)");
    addBakeOptions(*bench, args->settings, args->threads);
    bench->add_option("--repeat", args->repeat, "Runs per mesh; the fastest is reported")->check(CLI::Range(1, 100))->capture_default_str();
    bench->callback([args] { runBench(*args); });
}

} // namespace sdfgen::cli
