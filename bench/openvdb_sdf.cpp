// peer_openvdb: the same mesh and grid as `sdfgen bake`, but the field made by OpenVDB's
// tools::meshToSignedDistanceField, for side-by-side timing and comparison.
//
//   peer_openvdb MESH.obj --res N [--padding 0.1] -o OUT.sdf
//
// The OpenVDB grid's transform has voxel size grid.voxel and is shifted by half a voxel, so that
// OpenVDB voxel (i, j, k) has its centre exactly at sdfgen's sample (i, j, k), origin + (i+1/2)h:
// every sample is a direct voxel lookup, no interpolation. The narrow band is made wide enough that
// every sample of the grid is an active voxel with a real distance rather than the background value:
// the interior band is half the mesh's smallest extent (no point inside a closed surface is farther
// from it than that), the exterior band starts at the farthest grid corner's distance to the nearest
// mesh vertex and is doubled, and the conversion run again, while any sample still falls outside it.
// OpenVDB decides inside and outside itself (it does not use the triangles' winding).
//
// Prints `openvdb: <s> s (convert <s>, sample <s>)`: the whole process from the start of loading to
// the end of saving, the conversion (including any retry) and the sampling.
#include "peer_common.hpp"

#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <glm/geometric.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace {

using namespace sdfgen;

// Farthest corner of the grid's box from the mesh's nearest vertex, in voxels: a first guess at the
// exterior band (not a bound: a sample inside a concavity can be farther from the surface).
float cornerDistanceVoxels(const std::vector<glm::dvec3>& world, const Grid& grid) {
    double farthest = 0.0;
    for (int c = 0; c < 8; ++c) {
        const glm::dvec3 corner = grid.origin + glm::dvec3(c & 1 ? grid.dims.x : 0, c & 2 ? grid.dims.y : 0,
                                                           c & 4 ? grid.dims.z : 0) * grid.voxel;
        double nearest = INFINITY;
        for (const glm::dvec3& p : world) nearest = std::min(nearest, glm::distance(corner, p));
        farthest = std::max(farthest, nearest);
    }
    return float(farthest / grid.voxel);
}

int run(const peer::Options& options) {
    peer::Stopwatch clock;
    const Mesh mesh = loadMesh(options.mesh);
    const Grid grid = makeGrid(mesh.worldBounds(), options.res, options.padding);

    openvdb::initialize();
    // OpenVDB takes world positions (the transform below is the grid's, in world units).
    const std::vector<glm::dvec3> world = mesh.worldPositions();
    std::vector<openvdb::Vec3s> points;
    points.reserve(world.size());
    for (const glm::dvec3& p : world) points.emplace_back(float(p.x), float(p.y), float(p.z));
    std::vector<openvdb::Vec3I> triangles;
    triangles.reserve(mesh.triangles.size());
    for (const glm::uvec3& t : mesh.triangles) triangles.emplace_back(t.x, t.y, t.z);
    const std::vector<openvdb::Vec4I> quads;

    const double h = grid.voxel;
    openvdb::math::Transform::Ptr transform = openvdb::math::Transform::createLinearTransform(h);
    transform->postTranslate(openvdb::Vec3d(grid.origin.x + 0.5 * h, grid.origin.y + 0.5 * h, grid.origin.z + 0.5 * h));

    const glm::dvec3 extent = glm::dvec3(mesh.bounds.extent()) * mesh.unit;
    const double smallest = std::min(extent.x, std::min(extent.y, extent.z));
    const float interiorBand = float(std::ceil(0.5 * smallest / grid.voxel) + 2.0);
    float exteriorBand = std::ceil(cornerDistanceVoxels(world, grid)) + 2.0f;
    const float largestBand = 4.0f * std::ceil(glm::length(glm::vec3(grid.dims))) + 4.0f;

    clock.lap();
    double convertSeconds = 0.0;
    double sampleSeconds = 0.0;
    Field field;
    field.source = options.mesh;
    field.method = "openvdb";
    field.parameters = {{"res", std::to_string(options.res)}, {"padding", peer::numberText(options.padding)}};
    field.grid = grid;
    field.values.assign(grid.sampleCount(), 0.0f);
    for (;;) {
        const openvdb::FloatGrid::Ptr sdf = openvdb::tools::meshToSignedDistanceField<openvdb::FloatGrid>(
            *transform, points, triangles, quads, exteriorBand, interiorBand);
        convertSeconds += clock.lap();

        // One z-slice per task; each task has its own accessor (they cache tree nodes).
        const std::size_t outsideBand = tbb::parallel_reduce(
            tbb::blocked_range<int>(0, grid.dims.z, 1), std::size_t(0),
            [&](const tbb::blocked_range<int>& slices, std::size_t count) {
                openvdb::FloatGrid::ConstAccessor accessor = sdf->getConstAccessor();
                for (int k = slices.begin(); k != slices.end(); ++k) {
                    for (int j = 0; j < grid.dims.y; ++j) {
                        for (int i = 0; i < grid.dims.x; ++i) {
                            const openvdb::Coord ijk(i, j, k);
                            field.values[grid.index(i, j, k)] = accessor.getValue(ijk);
                            count += accessor.isValueOn(ijk) ? 0 : 1;
                        }
                    }
                }
                return count;
            },
            [](std::size_t a, std::size_t b) { return a + b; });
        sampleSeconds += clock.lap();
        if (outsideBand == 0) break;
        if (exteriorBand >= largestBand) {
            std::fprintf(stderr, "peer_openvdb: warning: %zu samples still outside a %g-voxel band keep the background value\n",
                         outsideBand, double(exteriorBand));
            break;
        }
        std::fprintf(stderr, "peer_openvdb: %zu samples outside the %g-voxel exterior band; converting again with %g\n",
                     outsideBand, double(exteriorBand), double(std::min(2.0f * exteriorBand, largestBand)));
        exteriorBand = std::min(2.0f * exteriorBand, largestBand);
    }

    saveField(field, options.output);
    std::printf("openvdb: %.3f s (convert %.3f, sample %.3f)\n", clock.seconds(), convertSeconds, sampleSeconds);
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"peer_openvdb: sdfgen's grid, filled by OpenVDB's meshToSignedDistanceField"};
    sdfgen::peer::Options options;
    if (const int code = sdfgen::peer::parseOptions(app, options, false, argc, argv); code >= 0) return code;
    try {
        return run(options);
    } catch (const sdfgen::Error& e) {
        std::fprintf(stderr, "peer_openvdb: %s\n", e.what());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "peer_openvdb: %s: %s\n", options.mesh.c_str(), e.what());
    }
    return 1;
}
