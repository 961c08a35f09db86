// The ray method's distance error against the analytic distance of a sphere, per ray count: the
// table in docs/how-it-works.md ("Distances") (bench/accuracy.sh --rays-table runs it).
//
//   bench_ray_error [--res 24] [--levels 4] [--rays 16,64,256,1024]
//
// The mesh is the icosphere of radius 1 subdivided --levels times (its vertices on the sphere), baked
// with --method rays at --res; each sample's error is (|field| - |sphere distance|) / voxel, which
// is positive but for the icosphere's sag (the ray distance is a real ray's length). Prints mean,
// median, 99th percentile and max over all samples, in voxels.
#include "sdfgen/error.hpp"
#include "core/bake/bake.hpp"
#include "core/accel/bvh.hpp"
#include "support/shapes.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

int main(int argc, char** argv) {
    CLI::App app{"Ray-method distance error against a sphere's analytic distance"};
    int res = 24, levels = 4;
    std::vector<int> rayCounts = {16, 64, 256, 1024};
    app.add_option("--res", res, "Voxels along the longest side")->check(CLI::Range(2, 512))->capture_default_str();
    app.add_option("--levels", levels, "Icosphere subdivision levels")->check(CLI::Range(0, 7))->capture_default_str();
    app.add_option("--rays", rayCounts, "Ray counts, comma-separated")->delimiter(',')->check(CLI::Range(1, 1 << 16));
    CLI11_PARSE(app, argc, argv);
    try {
        const sdfgen::Mesh sphere = sdfgen::test::icosphere(1.0f, levels);
        const sdfgen::Bvh tree(sphere);
        std::printf("sphere of radius 1 (icosphere, %d levels, %zu triangles, sag %.2g), res %d, --method rays; "
                    "error = (|ray distance| - |true distance|) / voxel over all samples\n\n",
                    levels, sphere.triangleCount(), double(sdfgen::test::icosphereSag(1.0f, levels)), res);
        std::printf("| rays | mean error | median | 99th percentile | max |\n|---:|---:|---:|---:|---:|\n");
        for (int rays : rayCounts) {
            sdfgen::BakeSettings settings;
            settings.res = res;
            settings.rays = rays;
            settings.method = sdfgen::DistanceMethod::Rays;
            const sdfgen::Field field = sdfgen::bake(sphere, tree, settings, sdfgen::RunControl{}).field.dense();
            const sdfgen::Grid& g = field.grid;
            std::vector<double> errors;
            errors.reserve(field.values.size());
            for (int k = 0; k < g.dims.z; ++k)
                for (int j = 0; j < g.dims.y; ++j)
                    for (int i = 0; i < g.dims.x; ++i) {
                        const double truth = sdfgen::test::sphereDistance(glm::vec3(g.position(i, j, k)), 1.0f);
                        errors.push_back((std::fabs(double(field.at(i, j, k))) - std::fabs(truth)) / g.voxel);
                    }
            std::sort(errors.begin(), errors.end());
            double mean = 0;
            for (double e : errors) mean += e;
            mean /= double(errors.size());
            std::printf("| %d | %.3g | %.3g | %.3g | %.3g |\n", rays, mean, errors[errors.size() / 2],
                        errors[errors.size() * 99 / 100], errors.back());
        }
    } catch (const sdfgen::Error& e) {
        std::fprintf(stderr, "bench_ray_error: %s\n", e.what());
        return 1;
    }
    return 0;
}
