// The winding sign alone (core/sign/winding_sign.cpp): loads a mesh, builds its topology once, then runs
// insideByWinding --repeat times on the grid of `sdfgen bake --res N`. Prints the best wall seconds
// and CPU seconds of the process (all threads; steadier than wall time on a busy machine), the
// caps and fan evaluations, and a checksum of the inside flags (equal checksums: identical signs,
// e.g. across thread counts or versions).
#include "core/runtime/parallel.hpp"
#include "core/sign/winding_sign.hpp"
#include "core/accel/topology.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/grid.hpp"
#include "sdfgen/mesh.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <thread>
#include <vector>

int main(int argc, char** argv) {
    CLI::App app{"Time the winding sign alone (sdfgen's sign benchmark)"};
    std::string input;
    int res = 128, repeat = 1, threads = 0;
    double padding = 0.1;
    app.add_option("mesh", input, "A mesh file")->required();
    app.add_option("--res", res, "Voxels along the longest side")->check(CLI::Range(1, 4096))->capture_default_str();
    app.add_option("--padding", padding, "Margin as a fraction of the longest side")->capture_default_str();
    app.add_option("--threads", threads, "Worker threads, 0 for all cores")->capture_default_str();
    app.add_option("--repeat", repeat, "Runs; the best is printed")->check(CLI::Range(1, 100))->capture_default_str();
    CLI11_PARSE(app, argc, argv);
    try {
        using namespace sdfgen;
        using Clock = std::chrono::steady_clock;
        const Mesh mesh = loadMesh(input);
        RunControl control;
        control.threads = threads;
        const MeshTopology topology(mesh, control);
        const Grid grid = makeGrid(mesh.worldBounds(), res, padding);
        std::vector<std::uint8_t> inside;
        WindingStats stats;
        double wall = 1e30, cpu = 1e30;
        for (int run = 0; run < repeat; ++run) {
            const auto start = Clock::now();
            const std::clock_t cpuStart = std::clock();
            stats = {};
            inside = insideByWinding(mesh, topology, grid, control, &stats);
            wall = std::min(wall, std::chrono::duration<double>(Clock::now() - start).count());
            cpu = std::min(cpu, double(std::clock() - cpuStart) / CLOCKS_PER_SEC);
        }
        std::uint64_t checksum = 1469598103934665603ull; // FNV-1a over the flags
        std::size_t insideCount = 0;
        for (std::uint8_t flag : inside) {
            checksum = (checksum ^ flag) * 1099511628211ull;
            insideCount += flag;
        }
        std::printf("%s: %zu triangles, %dx%dx%d samples, %d threads, best of %d: sign %.3f s wall, %.3f s CPU; %zu caps, %zu fan "
                    "evaluations, %zu inside, checksum %016llx\n",
                    input.c_str(), mesh.triangleCount(), grid.dims.x, grid.dims.y, grid.dims.z,
                    threads > 0 ? threads : int(std::thread::hardware_concurrency()), repeat, wall, cpu, stats.caps, stats.fanEvaluations,
                    insideCount, (unsigned long long)checksum);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_sign: %s\n", e.what());
        return 1;
    }
}
