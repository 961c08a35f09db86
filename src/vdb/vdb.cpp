// OpenVDB: a FloatGrid named "surface" (the name Houdini's VDB from Polygons gives) of class level
// set, with a transform that puts index (i, j, k) at sample (i, j, k): voxel size h, translation
// origin + h/2. Dense by default; with a band of V voxels only samples with |d| < V h stay active
// and the rest are inactive +-V h, as OpenVDB level sets are. The grid's sdfgen_* metadata keep
// the exact grid, method and source. A field's channels (sdfgen::Channels) follow as grids of their
// names with the surface grid's transform and active voxels: "gradient" and "closest" Vec3SGrids,
// "triangle" an Int32Grid. Also the iso-surfaces of `sdfgen surface`.
//
// The library the core opens on first use (core/openvdb_plugin.hpp), so that only runs that read
// or write OpenVDB load it.
#include "core/atomic_file.hpp"
#include "core/formats/format.hpp"
#include "core/openvdb_plugin.hpp"
#include "sdfgen/error.hpp"

#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <openvdb/tree/LeafManager.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <tuple>
#include <sys/stat.h>

namespace sdfgen::formats {

namespace {

constexpr const char* kGridName = "surface";

using DenseField = openvdb::tools::Dense<float, openvdb::tools::LayoutXYZ>; // x fastest, like Field::values

openvdb::CoordBBox indexBox(const Grid& grid) {
    return openvdb::CoordBBox(openvdb::Coord(0, 0, 0), openvdb::Coord(grid.dims.x - 1, grid.dims.y - 1, grid.dims.z - 1));
}

// The grid's index-to-world map as voxel size and translation; Error unless it is axis-aligned
// with cubic voxels, which is what a Field can hold.
void linearMap(const openvdb::math::Transform& transform, double& h, openvdb::Vec3d& translation, const std::string& path) {
    if (!transform.isLinear()) throw Error(path + ": the grid's transform is not linear (sdfgen reads axis-aligned grids)");
    const openvdb::Mat4d m = transform.baseMap()->getAffineMap()->getMat4();
    h = m(0, 0);
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
            const double expected = r == c ? h : 0.0;
            if (std::fabs(m(r, c) - expected) > 1e-9 * std::fabs(h)) {
                throw Error(path + ": the grid's transform is rotated or its voxels are not cubes (sdfgen reads axis-aligned grids of cubic voxels)");
            }
        }
    }
    if (!(h > 0) || !std::isfinite(h)) throw Error(path + ": the grid's voxel size is not positive");
    translation = m.getTranslation();
}

// A level-set FloatGrid named "surface" whose index (i, j, k) is at sample (i, j, k) (voxel size
// h, translation origin + h/2). band 0: every sample active; band >= 1: only samples with
// |d| < band * h, the rest inactive +-band * h. Initializes OpenVDB.
openvdb::FloatGrid::Ptr fieldToGrid(const Field& field, double band) {
    openvdb::initialize();
    const Grid& g = field.grid;
    const double h = g.voxel;
    const openvdb::CoordBBox box = indexBox(g);
    openvdb::FloatGrid::Ptr grid;
    if (band == 0) {
        // Every sample active: the background is just beyond the largest distance, so that no
        // sample equals it (copyFromDense makes samples equal to the background inactive).
        float largest = 0.0f;
        for (const float v : field.values) largest = std::max(largest, std::fabs(v));
        grid = openvdb::FloatGrid::create(std::nextafter(largest, std::numeric_limits<float>::infinity()));
        // copyFromDense only reads the dense array; Dense has no const view.
        const DenseField dense(box, const_cast<float*>(field.values.data()));
        openvdb::tools::copyFromDense(dense, *grid, 0.0f);
    } else {
        const float width = float(band * h);
        std::vector<float> clamped(field.values.size());
        std::transform(field.values.begin(), field.values.end(), clamped.begin(),
                       [width](float v) { return std::clamp(v, -width, width); });
        // Samples at +width become inactive background here, those at -width just below, then
        // whole inactive nodes become +-width tiles: the layout of an OpenVDB narrow-band level set.
        grid = openvdb::FloatGrid::create(width);
        const DenseField dense(box, clamped.data());
        openvdb::tools::copyFromDense(dense, *grid, 0.0f);
        for (auto it = grid->beginValueOn(); it; ++it) {
            if (*it <= -width) it.setValueOff();
        }
        openvdb::tools::pruneLevelSet(grid->tree());
    }
    grid->setName(kGridName);
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    openvdb::math::Transform::Ptr transform = openvdb::math::Transform::createLinearTransform(h);
    transform->postTranslate(openvdb::Vec3d(double(g.origin.x) + 0.5 * h, double(g.origin.y) + 0.5 * h, double(g.origin.z) + 0.5 * h));
    grid->setTransform(transform);
    return grid;
}

// A channel as a grid named `name` whose active voxels are the surface grid's (every sample when
// dense, the band's otherwise; the rest hold the background), valued at each voxel (i, j, k) by
// value(grid.index(i, j, k)).
template <class ChannelGrid, class Value>
typename ChannelGrid::Ptr channelGrid(const Field& field, const openvdb::FloatGrid& surface, const char* name,
                                      const typename ChannelGrid::ValueType& background, const Value& value) {
    const typename ChannelGrid::Ptr grid = ChannelGrid::create(background);
    grid->tree().topologyUnion(surface.tree());
    grid->tree().voxelizeActiveTiles();
    openvdb::tree::LeafManager<typename ChannelGrid::TreeType> leaves(grid->tree());
    leaves.foreach([&](typename ChannelGrid::TreeType::LeafNodeType& leaf, std::size_t) {
        for (auto voxel = leaf.beginValueOn(); voxel; ++voxel) {
            const openvdb::Coord c = voxel.getCoord();
            voxel.setValue(value(field.grid.index(c.x(), c.y(), c.z())));
        }
    });
    grid->setName(name);
    grid->setTransform(surface.transform().copy());
    return grid;
}

// The field's channels (sdfgen::Channels) beside the surface grid: "gradient" and "closest" as
// Vec3SGrids, "triangle" as an Int32Grid (background -1: no triangle).
openvdb::GridCPtrVec channelGrids(const Field& field, const openvdb::FloatGrid& surface) {
    openvdb::GridCPtrVec grids;
    const std::size_t n = field.grid.sampleCount();
    for (const auto& [name, planes, type] : {std::tuple{"gradient", &field.gradient, openvdb::VEC_COVARIANT_NORMALIZE},
                                             {"closest", &field.closest, openvdb::VEC_CONTRAVARIANT_ABSOLUTE}}) {
        if (planes->empty()) continue;
        const float* v = planes->data();
        const openvdb::Vec3SGrid::Ptr grid = channelGrid<openvdb::Vec3SGrid>(
            field, surface, name, openvdb::Vec3s(0.0f), [v, n](std::size_t i) { return openvdb::Vec3s(v[i], v[n + i], v[2 * n + i]); });
        grid->setVectorType(type);
        grids.push_back(grid);
    }
    if (!field.triangle.empty()) {
        const std::int32_t* t = field.triangle.data();
        grids.push_back(channelGrid<openvdb::Int32Grid>(field, surface, "triangle", -1, [t](std::size_t i) { return t[i]; }));
    }
    return grids;
}

void saveVdbFile(const Field& field, const std::string& path, const SaveOptions& options) {
    checkField(field, path);
    if (!(options.band == 0 || options.band >= 1) || !std::isfinite(options.band)) {
        throw Error(path + ": band must be 0 (dense) or at least 1 voxel (got " + std::to_string(options.band) + ")");
    }
    const openvdb::FloatGrid::Ptr grid = fieldToGrid(field, options.band);
    const Grid& g = field.grid;
    const double h = g.voxel;
    grid->insertMeta("sdfgen_dims", openvdb::Vec3IMetadata(openvdb::Vec3i(g.dims.x, g.dims.y, g.dims.z)));
    grid->insertMeta("sdfgen_origin", openvdb::Vec3DMetadata(openvdb::Vec3d(double(g.origin.x), double(g.origin.y), double(g.origin.z))));
    grid->insertMeta("sdfgen_voxel", openvdb::DoubleMetadata(h));
    grid->insertMeta("sdfgen_band", openvdb::DoubleMetadata(options.band));
    grid->insertMeta("sdfgen_method", openvdb::StringMetadata(methodLine(field)));
    grid->insertMeta("sdfgen_source", openvdb::StringMetadata(field.source));

    openvdb::GridCPtrVec grids{grid};
    for (const openvdb::GridBase::ConstPtr& channel : channelGrids(field, *grid)) grids.push_back(channel);
    writeFileAtomically(path, [&](std::ostream& out) {
        try {
            openvdb::io::Stream stream(out);
            // Blosc pays off on a narrow band's few leaves; a dense grid of distances hardly
            // compresses (about 20%) and saves three times faster without it.
            stream.setCompression(openvdb::io::COMPRESS_ACTIVE_MASK | (options.band > 0 ? openvdb::io::COMPRESS_BLOSC : 0));
            stream.write(grids);
        } catch (const openvdb::Exception& e) {
            throw Error(path + ": " + e.what());
        }
    });
}

Field loadVdbFile(const std::string& path) {
    struct stat info;
    if (stat(path.c_str(), &info) != 0) throw Error(path + ": cannot open file (" + std::strerror(errno) + ")");
    if (!S_ISREG(info.st_mode)) throw Error(path + ": not a regular file");
    openvdb::initialize();
    openvdb::FloatGrid::Ptr grid;
    try {
        // Read as a stream, not memory-mapped: a truncated file must fail, not fault, and it must
        // end exactly where the last grid does.
        std::ifstream in(path, std::ios::binary);
        if (!in) throw Error(path + ": cannot open file (" + std::strerror(errno) + ")");
        openvdb::io::Stream stream(in, /*delayLoad=*/false);
        const openvdb::GridPtrVecPtr grids = stream.getGrids();
        if (!in || in.tellg() != std::streampos(info.st_size)) {
            throw Error(path + ": not a readable OpenVDB file (truncated, or data after the last grid)");
        }
        // The grid named "surface", else the first float grid.
        for (const bool byName : {true, false}) {
            for (const openvdb::GridBase::Ptr& candidate : *grids) {
                if (!grid && candidate->isType<openvdb::FloatGrid>() && (!byName || candidate->getName() == kGridName)) {
                    grid = openvdb::gridPtrCast<openvdb::FloatGrid>(candidate);
                }
            }
        }
        if (!grid) throw Error(path + ": the file holds no float grid");
    } catch (const openvdb::Exception& e) {
        throw Error(path + ": not a readable OpenVDB file (" + e.what() + ")");
    } catch (const std::bad_alloc&) {
        throw Error(path + ": not a readable OpenVDB file (it declares more data than fits in memory)");
    } catch (const std::ios_base::failure& e) {
        throw Error(path + ": read error (" + e.what() + ")");
    }
    if (grid->getGridClass() == openvdb::GRID_FOG_VOLUME) {
        throw Error(path + ": grid '" + grid->getName() + "' is a fog volume, not a signed distance field");
    }
    double h = 0;
    openvdb::Vec3d translation;
    linearMap(grid->transform(), h, translation, path);

    Field field;
    field.method = "unknown";
    openvdb::CoordBBox box;
    const auto dims = grid->getMetadata<openvdb::Vec3IMetadata>("sdfgen_dims");
    const auto origin = grid->getMetadata<openvdb::Vec3DMetadata>("sdfgen_origin");
    const auto voxel = grid->getMetadata<openvdb::DoubleMetadata>("sdfgen_voxel");
    if (dims && origin && voxel) {
        // Written by sdfgen: the exact grid, which must agree with the transform.
        const std::uint64_t extent[3] = {std::uint64_t(std::max(0, dims->value()[0])), std::uint64_t(std::max(0, dims->value()[1])),
                                         std::uint64_t(std::max(0, dims->value()[2]))};
        checkDimsFit(extent, path);
        for (int a = 0; a < 3; ++a) {
            field.grid.dims[a] = dims->value()[a];
            field.grid.origin[a] = origin->value()[a];
            if (std::fabs(origin->value()[a] + 0.5 * h - translation[a]) > 1e-6 * h) {
                throw Error(path + ": the grid's transform does not match its sdfgen_origin metadata");
            }
        }
        if (std::fabs(voxel->value() - h) > 1e-9 * h) throw Error(path + ": the grid's voxel size does not match its sdfgen_voxel metadata");
        field.grid.voxel = voxel->value();
        box = indexBox(field.grid);
        if (const auto method = grid->getMetadata<openvdb::StringMetadata>("sdfgen_method")) parseMethodLine(method->value(), field, path);
        if (const auto source = grid->getMetadata<openvdb::StringMetadata>("sdfgen_source")) field.source = source->value();
    } else {
        // Another program's grid: the box of its active voxels.
        box = grid->evalActiveVoxelBoundingBox();
        if (box.empty()) throw Error(path + ": grid '" + grid->getName() + "' has no active voxels");
        const std::uint64_t extent[3] = {std::uint64_t(box.dim()[0]), std::uint64_t(box.dim()[1]), std::uint64_t(box.dim()[2])};
        checkDimsFit(extent, path);
        for (int a = 0; a < 3; ++a) {
            field.grid.dims[a] = box.dim()[a];
            field.grid.origin[a] = translation[a] + h * (double(box.min()[a]) - 0.5);
        }
        field.grid.voxel = h;
    }
    field.values.resize(field.grid.sampleCount());
    DenseField dense(box, field.values.data());
    openvdb::tools::copyToDense(*grid, dense);
    checkField(field, path);
    return field;
}

void surfacePolygons(const Field& field, double iso, double adaptivity, std::vector<glm::vec3>& points,
                     std::vector<glm::uvec3>& triangles, std::vector<glm::uvec4>& quads) {
    const openvdb::FloatGrid::Ptr grid = fieldToGrid(field, 0.0);
    std::vector<openvdb::Vec3s> vdbPoints;
    std::vector<openvdb::Vec3I> vdbTriangles;
    std::vector<openvdb::Vec4I> vdbQuads;
    openvdb::tools::volumeToMesh(*grid, vdbPoints, vdbTriangles, vdbQuads, iso, adaptivity);
    points.resize(vdbPoints.size());
    for (std::size_t i = 0; i < vdbPoints.size(); ++i) points[i] = {vdbPoints[i].x(), vdbPoints[i].y(), vdbPoints[i].z()};
    triangles.resize(vdbTriangles.size());
    for (std::size_t i = 0; i < vdbTriangles.size(); ++i) triangles[i] = {vdbTriangles[i][0], vdbTriangles[i][1], vdbTriangles[i][2]};
    quads.resize(vdbQuads.size());
    for (std::size_t i = 0; i < vdbQuads.size(); ++i) quads[i] = {vdbQuads[i][0], vdbQuads[i][1], vdbQuads[i][2], vdbQuads[i][3]};
}

} // namespace

} // namespace sdfgen::formats

extern "C" __attribute__((visibility("default"))) const sdfgen::OpenVdbPlugin* sdfgen_openvdb_plugin() {
    static const sdfgen::OpenVdbPlugin plugin{sdfgen::formats::saveVdbFile, sdfgen::formats::loadVdbFile, sdfgen::formats::surfacePolygons};
    return &plugin;
}
