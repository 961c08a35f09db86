// The exact distance kernel alone (core/distance/exact_kernel.inc): loads a mesh, builds both trees once,
// then runs the unsigned exact field (computeExactField) --repeat times on the grid of
// `sdfgen bake --res N`. Prints the best wall seconds and CPU seconds of the process (all threads;
// steadier than wall time on a busy machine), samples per CPU second, the SIMD path the kernel ran
// (SDFGEN_SIMD picks one), and a checksum of the field's bits (equal checksums: bit-identical
// fields, e.g. across paths, thread counts or versions).
#include "core/accel/bvh.hpp"
#include "core/distance/exact.hpp"
#include "core/distance/kernel.hpp"
#include "core/runtime/parallel.hpp"
#include "core/accel/wide_bvh.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/grid.hpp"
#include "sdfgen/mesh.hpp"

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <thread>
#include <vector>

int main(int argc, char** argv) {
    CLI::App app{"Time the exact distance kernel alone (sdfgen's kernel benchmark)"};
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
        const Bvh binary(mesh);
        const WideBvh tree(mesh, binary);
        const Grid grid = makeGrid(mesh.worldBounds(), res, padding);
        RunControl control;
        control.threads = threads;
        std::vector<float> values(grid.sampleCount());
        double wall = 1e30, cpu = 1e30;
        for (int run = 0; run < repeat; ++run) {
            const auto start = Clock::now();
            const std::clock_t cpuStart = std::clock();
            computeExactField(mesh, tree, grid, nullptr, false, values.data(), control);
            wall = std::min(wall, std::chrono::duration<double>(Clock::now() - start).count());
            cpu = std::min(cpu, double(std::clock() - cpuStart) / CLOCKS_PER_SEC);
        }
        std::uint64_t checksum = 1469598103934665603ull; // FNV-1a over the field's bytes
        const auto* bytes = reinterpret_cast<const unsigned char*>(values.data());
        for (std::size_t i = 0; i < values.size() * sizeof(float); ++i) checksum = (checksum ^ bytes[i]) * 1099511628211ull;
        std::printf("%s: %zu triangles, %dx%dx%d samples, %s path, %d threads, best of %d: distance %.3f s wall, %.3f s CPU, %.0f samples/CPU s, "
                    "checksum %016llx\n",
                    input.c_str(), mesh.triangleCount(), grid.dims.x, grid.dims.y, grid.dims.z, toString(simdPath()), threads > 0 ? threads : int(std::thread::hardware_concurrency()), repeat, wall, cpu,
                    double(grid.sampleCount()) / cpu, (unsigned long long)checksum);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_kernel: %s\n", e.what());
        return 1;
    }
}
