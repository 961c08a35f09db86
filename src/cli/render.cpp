// `sdfgen render`: a PNG of any combination of views, drawn headless (EGL, else OSMesa) with the
// same renderers as the viewer window.
#include "cli/commands.hpp"
#include "cli/progress.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/field.hpp"
#include "core/bvh.hpp"
#include "sdfgen/mesh.hpp"
#include "render/image.hpp"
#include "render/egl_context.hpp"
#include "render/scene.hpp"

#include <cstdio>
#include <memory>
#include <sstream>

namespace sdfgen::cli {

namespace {

struct RenderArgs {
    std::string mesh;
    std::string sdf;
    std::string output;
    std::string views = "grid,mesh";
    std::string camera = "30,20,1";
    std::string size = "800x600";
    std::string sliceAxis = "z";
    float slicePosition = 0.5f;
    std::string background;
    bool noShadows = false;
    int repeat = 0;
    BakeSettings settings;
    int threads = 0;
};

std::vector<float> parseNumbers(const std::string& text, char separator, std::size_t count, const std::string& what) {
    std::vector<float> out;
    std::stringstream in(text);
    std::string item;
    while (std::getline(in, item, separator)) {
        try {
            std::size_t used = 0;
            out.push_back(std::stof(item, &used));
            if (used != item.size()) throw std::invalid_argument(item);
        } catch (const std::exception&) {
            throw Error(what + " '" + text + "' is not valid");
        }
    }
    if (out.size() != count) throw Error(what + " '" + text + "' is not valid");
    return out;
}

void runRender(const RenderArgs& args) {
    const std::vector<float> camera = parseNumbers(args.camera, ',', 3, "--camera (yaw,pitch,zoom)");
    const std::vector<float> size = parseNumbers(args.size, 'x', 2, "--size (WIDTHxHEIGHT)");
    if (camera[2] <= 0.0f) throw Error("--camera zoom must be positive");
    render::Views views = render::Views::parse(args.views);
    const int axis = args.sliceAxis == "x" ? 0 : args.sliceAxis == "y" ? 1 : args.sliceAxis == "z" ? 2 : -1;
    if (axis < 0) throw Error("--slice-axis must be x, y or z");

    const glm::ivec2 pixels{int(size[0]), int(size[1])};
    if (float(pixels.x) != size[0] || float(pixels.y) != size[1] || pixels.x < 1 || pixels.y < 1) {
        throw Error("--size '" + args.size + "' must be two positive whole numbers");
    }

    const Mesh mesh = loadObj(args.mesh);
    Field field;
    const bool needField = views.volume || views.raymarch || views.slice;
    if (!args.sdf.empty()) {
        field = loadFieldText(args.sdf);
    } else if (needField) {
        const Bvh tree(mesh);
        RunControl control;
        control.threads = args.threads;
        ProgressBar bar;
        control.progress = bar.callback();
        field = bake(mesh, tree, args.settings, control).field;
    }

    std::unique_ptr<render::GlContext> context = render::createHeadlessContext(pixels);
    render::Scene scene;
    scene.views = views;
    scene.sliceAxis = axis;
    scene.slicePosition = args.slicePosition;
    scene.shadows = !args.noShadows;
    if (!args.background.empty()) {
        const std::vector<float> rgb = parseNumbers(args.background, ',', 3, "--background (r,g,b in 0..1)");
        scene.background = glm::vec3(rgb[0], rgb[1], rgb[2]);
    }
    scene.setMesh(mesh);
    if (!field.values.empty()) scene.setField(field);

    render::OrbitCamera orbit;
    orbit.yaw = camera[0];
    orbit.pitch = camera[1];
    orbit.frame(mesh.bounds, camera[2]);
    scene.draw(orbit, pixels);
    context->present();
    if (args.repeat > 0) {
        Stopwatch watch;
        for (int i = 0; i < args.repeat; ++i) {
            scene.draw(orbit, pixels);
            context->present();
        }
        std::printf("%s: %dx%d, views %s: %.1f ms per frame (mean of %d)\n", args.output.c_str(), pixels.x, pixels.y,
                    args.views.c_str(), 1000.0 * watch.seconds() / args.repeat, args.repeat);
    }
    render::savePng(render::readFramebuffer(pixels.x, pixels.y), args.output);
}

} // namespace

void addRenderCommand(CLI::App& app) {
    auto args = std::make_shared<RenderArgs>();
    CLI::App* render = app.add_subcommand("render", "Render views of a mesh and its field to a PNG, headless (EGL or OSMesa, no display needed)");
    render->add_option("mesh", args->mesh, "Input mesh (Wavefront OBJ)")->required();
    render->add_option("-o,--output", args->output, "Output PNG file")->required();
    render->add_option("--sdf", args->sdf, "Field file to show (default: bake one from the mesh when a view needs it)");
    render->add_option("--view", args->views, "Comma-separated views: grid, mesh, wire, volume, raymarch, slice (or all, none)")
        ->capture_default_str();
    render->add_option("--camera", args->camera, "Orbit camera: yaw,pitch in degrees and zoom (1 frames the mesh; 2 is twice as far)")
        ->capture_default_str();
    render->add_option("--size", args->size, "Image size in pixels, WIDTHxHEIGHT")->capture_default_str();
    render->add_option("--slice-axis", args->sliceAxis, "Axis the slice view cuts across: x, y or z")->capture_default_str();
    render->add_option("--slice-pos", args->slicePosition, "Slice position across the field's box, 0 to 1")
        ->check(CLI::Range(0.0f, 1.0f))
        ->capture_default_str();
    render->add_option("--background", args->background, "Background colour r,g,b in 0..1 (default: dark grey)");
    render->add_flag("--no-shadows", args->noShadows, "Ray-marched view without soft shadows and ambient occlusion");
    render->add_option("--repeat", args->repeat, "Draw the frame N more times and print the mean frame time")
        ->check(CLI::Range(0, 100000));
    addBakeOptions(*render, args->settings, args->threads);
    render->callback([args] { runRender(*args); });
}

} // namespace sdfgen::cli
