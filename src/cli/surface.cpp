// `sdfgen surface`: a closed, manifold triangle mesh from a mesh (baked with exact distances and
// the automatic sign, so holes and self-intersections do not leak) or from a saved field.
#include "cli/commands.hpp"
#include "cli/progress.hpp"
#include "sdfgen/surface.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/formats.hpp"
#include "sdfgen/mesh.hpp"
#include "core/runtime/file_extension.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <memory>

namespace sdfgen::cli {

namespace {

struct SurfaceArgs {
    std::string input;
    std::string output;
    BakeSettings settings;
    int threads = 0;
    double iso = 0.0;
    double adaptivity = 0.0;
};

bool isFieldFile(const std::string& path) {
    const std::string extension = lowerExtension(path);
    const std::vector<std::string> fields = fieldFormatExtensions();
    return std::find(fields.begin(), fields.end(), extension) != fields.end();
}

void runSurface(const SurfaceArgs& args) {
    Stopwatch total;
    refuseOverwritingInput(args.output, {args.input});
    // A band field (a band bake, or a sparse .vdb or .npz) is meshed as it is, never made dense.
    AnyField field;
    if (isFieldFile(args.input)) {
        field = loadAnyField(args.input);
    } else {
        checkBakeSettings(args.settings);
        if (!(args.settings.padding > 0.0)) throw Error("--padding must be above 0: the surface must stay inside the grid to be closed");
        RunControl control = commandControl(args.threads);
        const Model model = Model::load(args.input, control);
        ProgressBar bar;
        control.progress = bar.callback();
        field = model.bake(args.settings, control).field;
    }
    SurfaceMesh surface;
    try {
        surface = field.visit([&](const auto& f) { return extractSurface(f, args.iso, args.adaptivity); });
    } catch (const Error& e) {
        throw Error(args.input + ": " + e.what());
    }
    // Checked before the old output is replaced: a surface that is no valid mesh is never saved.
    const MeshCheck check = Model(buildMesh(args.output, surface.positions, surface.triangles)).check();
    saveSurface(surface, args.output);
    const double seconds = total.seconds();
    const Grid& g = field.header().grid;
    std::printf("%s -> %s: %zu vertices, %zu triangles, iso %g, adaptivity %g, grid %dx%dx%d%s, %.3f s\n", args.input.c_str(),
                args.output.c_str(), surface.positions.size(), surface.triangles.size(), args.iso, args.adaptivity, g.dims.x,
                g.dims.y, g.dims.z, field.isBand() ? (" (band field, " + std::to_string(field.band().bricks().size()) + " bricks)").c_str() : "", seconds);
    std::printf("mesh check of the output: %s\n", check.describe().c_str());
}

} // namespace

void addSurfaceCommand(CLI::App& app) {
    auto args = std::make_shared<SurfaceArgs>();
    CLI::App* surface = app.add_subcommand("surface", "Extract a closed, manifold iso-surface (OBJ or PLY) from a mesh or a field");
    surface->add_option("input", args->input, "A mesh (baked first: exact distances, automatic sign) or a field file (" + fieldFormatList() + ")")
        ->required();
    surface->add_option("-o,--output", args->output, "Output mesh: .obj or .ply (binary)")->required();
    surface->add_option("--iso", args->iso, "Distance of the surface: 0 is the mesh's surface, > 0 an offset outwards")
        ->check(finiteRange(-1e30, 1e30))->capture_default_str();
    surface->add_option("--adaptivity", args->adaptivity, "0 (uniform triangles) to 1 (fewer, larger triangles where the surface is flat)")
        ->check(finiteRange(0.0, 1.0))
        ->capture_default_str();
    surface->add_option("--res", args->settings.res, "For a mesh: voxels along the longest side of the padded bounding box (1 to " + std::to_string(kMaxRes) + ")")
        ->capture_default_str();
    surface->add_option("--padding", args->settings.padding, "For a mesh: margin around it, as a fraction of its longest side (above 0, at most 100)")
        ->capture_default_str();
    surface->add_option("--band", args->settings.band,
                        "For a mesh: bake only this many voxels each side of the surface, in bricks (memory grows with the surface, "
                        "not the volume: for high --res); 0 bakes the whole grid")
        ->capture_default_str();
    addThreadsOption(*surface, args->threads);
    surface->footer("The surface is OpenVDB's volumeToMesh of the field; it is closed when it stays inside the grid.");
    surface->callback([args] { runSurface(*args); });
}

} // namespace sdfgen::cli
