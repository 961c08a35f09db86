// Point queries alone: Model::query's signed distances (winding sign) against its unsigned ones on
// the same points, after the model's tree, topology and fans are built (one untimed call of each
// first), on --near N points drawn near the surface (a random point of a random triangle moved
// along its normal by up to 1% of the mesh's diagonal).
// Prints the best of --repeat wall and CPU seconds of each and their ratios, and a checksum of the signs.
#include "sdfgen/error.hpp"
#include "sdfgen/mesh.hpp"
#include "sdfgen/model.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <random>
#include <vector>

int main(int argc, char** argv) {
    CLI::App app{"Time signed against unsigned point queries (sdfgen's query benchmark)"};
    std::string input;
    std::size_t near = 1000000;
    int repeat = 3, threads = 0;
    app.add_option("mesh", input, "A mesh file")->required();
    app.add_option("--near", near, "Points drawn near the surface")->capture_default_str();
    app.add_option("--repeat", repeat, "Runs; the best is printed")->check(CLI::Range(1, 100))->capture_default_str();
    app.add_option("--threads", threads, "Worker threads, 0 for all cores")->capture_default_str();
    CLI11_PARSE(app, argc, argv);
    try {
        using namespace sdfgen;
        using Clock = std::chrono::steady_clock;
        RunControl control;
        control.threads = threads;
        const Model model(loadMesh(input), control);
        const Mesh& mesh = model.mesh();
        std::vector<double> points;
        {
            std::mt19937_64 rng(7);
            std::uniform_real_distribution<double> unit(0.0, 1.0), offset(-1.0, 1.0);
            const std::vector<glm::dvec3> positions = mesh.worldPositions();
            const double diagonal = glm::length(glm::dvec3(mesh.worldBounds().max - mesh.worldBounds().min));
            for (std::size_t n = 0; n < near; ++n) {
                const glm::uvec3& t = mesh.triangles[std::size_t(unit(rng) * double(mesh.triangleCount())) % mesh.triangleCount()];
                double u = unit(rng), v = unit(rng);
                if (u + v > 1.0) u = 1.0 - u, v = 1.0 - v;
                const glm::dvec3 a = positions[t.x], b = positions[t.y], c = positions[t.z];
                const glm::dvec3 normal = glm::cross(b - a, c - a);
                const double length = glm::length(normal);
                const glm::dvec3 p = a + u * (b - a) + v * (c - a) + (length > 0.0 ? normal / length : glm::dvec3(0.0)) * offset(rng) * 0.01 * diagonal;
                points.insert(points.end(), {p.x, p.y, p.z});
            }
        }
        const std::size_t count = points.size() / 3;
        std::vector<float> distances(count);
        auto time = [&](bool sign) {
            PointQueryOutputs out;
            (sign ? out.signedDistance : out.unsignedDistance) = distances.data();
            std::pair<double, double> best{1e30, 1e30}; // wall, CPU (all threads: steadier on a busy machine)
            for (int run = 0; run <= repeat; ++run) { // run 0 builds what the query needs, untimed
                const auto start = Clock::now();
                const std::clock_t cpuStart = std::clock();
                model.query(points.data(), count, out, SignMethod::Winding, control);
                if (run == 0) continue;
                best.first = std::min(best.first, std::chrono::duration<double>(Clock::now() - start).count());
                best.second = std::min(best.second, double(std::clock() - cpuStart) / CLOCKS_PER_SEC);
            }
            return best;
        };
        const auto [unsignedWall, unsignedCpu] = time(false);
        const auto [signedWall, signedCpu] = time(true);
        std::uint64_t checksum = 1469598103934665603ull;
        std::size_t inside = 0;
        for (float d : distances) {
            checksum = (checksum ^ std::uint64_t(d < 0.0f)) * 1099511628211ull;
            inside += d < 0.0f;
        }
        std::printf("%s: %zu triangles, %zu points, best of %d: unsigned %.3f s wall %.3f s CPU, signed (winding) %.3f s wall %.3f s CPU, "
                    "ratio %.2f wall %.2f CPU; %zu inside, checksum %016llx\n",
                    input.c_str(), mesh.triangleCount(), count, repeat, unsignedWall, unsignedCpu, signedWall, signedCpu,
                    signedWall / unsignedWall, signedCpu / unsignedCpu, inside, (unsigned long long)checksum);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_query: %s\n", e.what());
        return 1;
    }
}
