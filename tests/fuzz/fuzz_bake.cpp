// Fuzzes load -> tree -> bake: the first byte picks the method and sign from the registries, the
// second the grid resolution (1-8) and ray count (1-16); the rest is an OBJ file. Any input either
// gives a field of finite values on the grid or an Error. Exact distances equal brute force's. For
// exact distances with the winding sign, the band bake of the same mesh and grid must match that field (the dense values in the
// band, their sides beyond), and so must point queries at its samples (whose counts of crossings
// may run on the other side of a row).
#include "fuzz_input.hpp"
#include "core/bake/bake.hpp"
#include "core/accel/bvh.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/mesh.hpp"
#include "sdfgen/model.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 2) return 0;
    sdfgen::BakeSettings settings;
    // Every method and sign the registries list, the unsupported pairs included (they must be refused).
    static const auto methods = sdfgen::distanceMethodChoices();
    static const auto signs = sdfgen::signMethodChoices();
    settings.method = methods[data[0] % methods.size()].id;
    settings.sign = signs[data[0] / methods.size() % signs.size()].id;
    settings.res = 1 + data[1] % 8;
    settings.rays = 1 + data[1] / 8 % 16;
    const std::string& path = sdfgen::fuzz::writeInput(data + 2, size - 2, ".obj");
    try {
        const sdfgen::Mesh mesh = sdfgen::loadObj(path);
        if (mesh.triangleCount() > 2000) return 0; // brute force is O(samples x triangles)
        const sdfgen::Bvh tree(mesh);
        sdfgen::RunControl control;
        control.threads = 1;
        const sdfgen::BakeResult result = sdfgen::bake(mesh, tree, settings, control);
        const sdfgen::Field& field = result.field.dense();
        if (field.values.size() != field.grid.sampleCount()) std::abort();
        for (float v : field.values) {
            if (!std::isfinite(v)) {
                std::fprintf(stderr, "non-finite value in the field\n");
                std::abort();
            }
        }
        if (settings.method != sdfgen::DistanceMethod::Exact) return 0;
        const sdfgen::Grid& grid = field.grid;
        // Exact distances are brute force's, to the rounding of a float search over local coordinates.
        sdfgen::BakeSettings bruteSettings = settings;
        bruteSettings.method = sdfgen::DistanceMethod::Brute;
        bruteSettings.sign = sdfgen::SignMethod::Winding;
        const sdfgen::Field brute = sdfgen::bake(mesh, tree, bruteSettings, control).field.dense();
        const double extent = std::max({grid.dims.x, grid.dims.y, grid.dims.z}) * grid.voxel;
        for (std::size_t n = 0; n < brute.values.size(); ++n) {
            const double exact = std::fabs(field.values[n]), reference = std::fabs(brute.values[n]);
            if (std::fabs(exact - reference) > 1e-5 * (extent + reference)) {
                std::fprintf(stderr, "sample %zu: exact distance %.9g, brute force's %.9g\n", n, exact, reference);
                std::abort();
            }
        }
        if (settings.sign != sdfgen::SignMethod::Winding) return 0;
        // The band bake: the dense field's values in the band, its sides beyond.
        settings.band = 2;
        const sdfgen::BakeResult baked = sdfgen::bake(mesh, tree, settings, control);
        const sdfgen::SparseField& band = baked.field.band();
        const float background = band.background();
        for (int k = 0; k < grid.dims.z; ++k)
            for (int j = 0; j < grid.dims.y; ++j)
                for (int i = 0; i < grid.dims.x; ++i) {
                    const float dense = field.at(i, j, k), sparse = band.at(i, j, k);
                    const float expected = std::fabs(dense) < background ? dense : std::copysign(background, dense);
                    if (sparse != expected) {
                        std::fprintf(stderr, "band sample (%d, %d, %d): %g, the dense bake's %g\n", i, j, k, sparse, dense);
                        std::abort();
                    }
                }
        // Point queries at the samples (world positions, as Model::query takes them).
        std::vector<double> xyz;
        for (int k = 0; k < grid.dims.z; ++k)
            for (int j = 0; j < grid.dims.y; ++j)
                for (int i = 0; i < grid.dims.x; ++i) {
                    const glm::dvec3 p = grid.position(i, j, k);
                    xyz.insert(xyz.end(), {p.x, p.y, p.z});
                }
        std::vector<float> queried(grid.sampleCount());
        sdfgen::PointQueryOutputs out;
        out.signedDistance = queried.data();
        const sdfgen::Model model(mesh, control);
        model.query(xyz.data(), grid.sampleCount(), out, sdfgen::SignMethod::Winding, control);
        for (std::size_t n = 0; n < queried.size(); ++n) {
            if (queried[n] != field.values[n]) {
                std::fprintf(stderr, "query at sample %zu: %g, the dense bake's %g\n", n, queried[n], field.values[n]);
                std::abort();
            }
        }
    } catch (const sdfgen::Error&) {
    }
    return 0;
}
