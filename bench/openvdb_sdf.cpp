// peer_openvdb: the same mesh and grid as `sdfgen bake`, but the field made by OpenVDB's
// tools::meshToSignedDistanceField, for side-by-side timing and comparison.
//
//   peer_openvdb MESH.obj --res N [--padding 0.1] -o OUT.sdf
//   peer_openvdb MESH.obj --res N --band V -o OUT.vdb [--signs-against DENSE.npy]
//
// With --band: OpenVDB's own narrow-band path, tools::meshToLevelSet with V voxels each side,
// written as a .vdb level set (what `sdfgen bake --band V -o F.vdb` is measured against); with
// --signs-against, the count of the grid's samples whose side differs from a dense field's (an
// sdfgen bake of the same mesh and grid; its .npy) is printed too.
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
#include "core/mesh/sample_positions.hpp"

#include <openvdb/openvdb.h>
#include <openvdb/io/File.h>
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
// exterior band (not a bound: a sample inside a concavity can be farther from the surface). In the
// mesh's local coordinates, with `origin` and `voxel` the grid's in local units.
float cornerDistanceVoxels(const Mesh& mesh, const Grid& grid, const glm::vec3& origin, float voxel) {
    float farthest = 0.0f;
    for (int c = 0; c < 8; ++c) {
        const glm::vec3 corner = origin + glm::vec3(c & 1 ? grid.dims.x : 0, c & 2 ? grid.dims.y : 0,
                                                    c & 4 ? grid.dims.z : 0) * voxel;
        float nearest = INFINITY;
        for (const glm::vec3& p : mesh.positions) nearest = std::min(nearest, glm::distance(corner, p));
        farthest = std::max(farthest, nearest);
    }
    return farthest / voxel;
}

// The mesh in OpenVDB's types, in its local coordinates as sdfgen measures it (distances scaled by
// mesh.unit when stored), and the transform whose voxel (i, j, k) has its centre at the grid's
// sample (i, j, k): voxel size h (the grid's voxel in local units), shifted by half a voxel.
struct OpenVdbMesh {
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    double h;
    glm::dvec3 origin; // the grid's, in local units
    openvdb::math::Transform::Ptr transform;
};
OpenVdbMesh toOpenVdb(const Mesh& mesh, const Grid& grid) {
    openvdb::initialize();
    OpenVdbMesh out;
    out.points.reserve(mesh.positions.size());
    for (const glm::vec3& p : mesh.positions) out.points.emplace_back(p.x, p.y, p.z);
    out.triangles.reserve(mesh.triangles.size());
    for (const glm::uvec3& t : mesh.triangles) out.triangles.emplace_back(t.x, t.y, t.z);
    out.h = grid.voxel / mesh.unit;
    out.origin = mesh.toLocal(grid.origin);
    out.transform = openvdb::math::Transform::createLinearTransform(out.h);
    out.transform->postTranslate(openvdb::Vec3d(out.origin.x + 0.5 * out.h, out.origin.y + 0.5 * out.h, out.origin.z + 0.5 * out.h));
    return out;
}

// The band mode: the level set alone, on sdfgen's grid (gridAround: makeGrid without its check
// that a dense grid fits, since none is made).
int runBand(const peer::Options& options, float band, const std::string& signsAgainst) {
    peer::Stopwatch clock;
    const Mesh mesh = loadMesh(options.mesh);
    const OpenVdbMesh vdb = toOpenVdb(mesh, gridAround(mesh.worldBounds(), options.res, options.padding));
    clock.lap();
    const openvdb::FloatGrid::Ptr levelSet = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*vdb.transform, vdb.points, vdb.triangles, band);
    const double convertSeconds = clock.lap();
    levelSet->setName("sdf");
    openvdb::io::File(options.output).write({levelSet});
    std::printf("openvdb: %.3f s (meshToLevelSet %.3f), %zu active voxels\n", clock.seconds(), convertSeconds,
                std::size_t(levelSet->activeVoxelCount()));
    if (!signsAgainst.empty()) {
        const Field dense = loadField(signsAgainst);
        std::size_t wrong = 0;
        openvdb::FloatGrid::ConstAccessor accessor = levelSet->getConstAccessor();
        for (int k = 0; k < dense.grid.dims.z; ++k)
            for (int j = 0; j < dense.grid.dims.y; ++j)
                for (int i = 0; i < dense.grid.dims.x; ++i) {
                    wrong += (accessor.getValue(openvdb::Coord(i, j, k)) < 0.0f) != (dense.at(i, j, k) < 0.0f);
                }
        std::printf("openvdb wrong signs: %zu of %zu samples (%.2f%%)\n", wrong, dense.grid.sampleCount(),
                    100.0 * double(wrong) / double(dense.grid.sampleCount()));
    }
    return 0;
}

int run(const peer::Options& options) {
    peer::Stopwatch clock;
    const Mesh mesh = loadMesh(options.mesh);
    const Grid grid = makeGrid(mesh.worldBounds(), options.res, options.padding);
    const OpenVdbMesh vdb = toOpenVdb(mesh, grid);
    const std::vector<openvdb::Vec4I> quads;
    const double h = vdb.h;

    const glm::vec3 extent = mesh.bounds.extent();
    const float smallest = std::min(extent.x, std::min(extent.y, extent.z));
    const float interiorBand = std::ceil(0.5f * smallest / float(h)) + 2.0f;
    float exteriorBand = std::ceil(cornerDistanceVoxels(mesh, grid, glm::vec3(vdb.origin), float(h))) + 2.0f;
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
            *vdb.transform, vdb.points, vdb.triangles, quads, exteriorBand, interiorBand);
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
                            field.values[grid.index(i, j, k)] = float(double(accessor.getValue(ijk)) * mesh.unit);
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
    float band = 0.0f;
    std::string signsAgainst;
    app.add_option("--band", band, "OpenVDB's narrow band (meshToLevelSet) of this many voxels each side, written as .vdb")
        ->check(CLI::PositiveNumber);
    app.add_option("--signs-against", signsAgainst, "with --band: count the samples whose side differs from this dense field's");
    if (const int code = sdfgen::peer::parseOptions(app, options, false, argc, argv); code >= 0) return code;
    try {
        return band > 0.0f ? runBand(options, band, signsAgainst) : run(options);
    } catch (const sdfgen::Error& e) {
        std::fprintf(stderr, "peer_openvdb: %s\n", e.what());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "peer_openvdb: %s: %s\n", options.mesh.c_str(), e.what());
    }
    return 1;
}
