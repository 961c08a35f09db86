// `sdfgen render`: a PNG of any combination of views, drawn headless (EGL, else OSMesa) with the same
// renderers as the viewer window.
#include "cli/commands.hpp"
#include "sdfgen/model.hpp"
#include "cli/progress.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/field.hpp"
#include "sdfgen/formats.hpp"
#include "sdfgen/field_match.hpp"
#include "sdfgen/any_field.hpp"
#include "sdfgen/mesh.hpp"
#include "render/image.hpp"
#include "render/band_display.hpp"
#include "render/egl_context.hpp"
#include "render/scene.hpp"
#include "render/views.hpp"

#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>

namespace sdfgen::cli {

namespace {

struct RenderArgs {
    std::vector<std::string> meshes;
    std::string sdf;
    std::string output;
    std::string views = "grid,mesh";
    std::string camera = "30,20,1";
    std::string size = "800x600";
    std::string sliceAxis = "z";
    std::string sliceNormal;
    float slicePosition = 0.5f;
    float iso = 0.0f;
    std::string colormap = "diverging";
    float colourRange = 0.0f;
    bool noColourBar = false;
    bool cutAway = false;
    bool orthographic = false;
    bool wireSeeThrough = false;
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
        if (!std::isfinite(out.back())) throw Error(what + " '" + text + "' is not valid: '" + item + "' is not a finite number");
    }
    if (out.size() != count) throw Error(what + " '" + text + "' is not valid");
    return out;
}

void runRender(const RenderArgs& args) {
    const std::vector<float> camera = parseNumbers(args.camera, ',', 3, "--camera (yaw,pitch,zoom)");
    const std::vector<float> size = parseNumbers(args.size, 'x', 2, "--size (WIDTHxHEIGHT)");
    if (!(camera[2] > 0.0f)) throw Error("--camera zoom must be positive");
    checkBakeSettings(args.settings);
    std::vector<std::string> inputs = args.meshes;
    inputs.push_back(args.sdf);
    refuseOverwritingInput(args.output, inputs);
    const std::vector<bool> views = render::parseViewList(args.views);
    const int axis = args.sliceAxis == "x" ? 0 : args.sliceAxis == "y" ? 1 : args.sliceAxis == "z" ? 2 : -1;
    if (axis < 0) throw Error("--slice-axis must be x, y or z");
    glm::vec3 sliceNormal = render::axisNormal(axis);
    if (!args.sliceNormal.empty()) {
        const std::vector<float> n = parseNumbers(args.sliceNormal, ',', 3, "--slice-normal (x,y,z)");
        sliceNormal = glm::vec3(n[0], n[1], n[2]);
        if (!(glm::length(sliceNormal) > 0.0f)) throw Error("--slice-normal must not be zero");
        sliceNormal = glm::normalize(sliceNormal);
    }
    const int colormap = args.colormap == "diverging" ? 0 : args.colormap == "viridis" ? 1 : args.colormap == "grey" ? 2 : -1;
    if (colormap < 0) throw Error("--colormap must be diverging, viridis or grey");

    constexpr float kMaxSide = 16384.0f; // OSMesa's largest framebuffer
    if (!(size[0] >= 1.0f && size[0] <= kMaxSide && size[1] >= 1.0f && size[1] <= kMaxSide) ||
        std::floor(size[0]) != size[0] || std::floor(size[1]) != size[1]) {
        throw Error("--size '" + args.size + "' must be two whole numbers from 1 to 16384");
    }
    const glm::ivec2 pixels{int(size[0]), int(size[1])};

    const RunControl control = commandControl(args.threads);
    // A scene's meshes are drawn one by one, each in its own colour (render::meshColour, as in the
    // viewer); the field is their union's.
    std::vector<Mesh> meshes;
    for (const std::string& path : args.meshes) meshes.push_back(loadMesh(path));
    const Model model(meshes.size() == 1 ? std::move(meshes[0]) : mergeScene(meshes, args.meshes), control);
    const Mesh& mesh = model.mesh();
    AnyField field; // a band field is shown through render::bandDisplay once there is a context
    bool needField = false;
    for (std::size_t i = 0; i < views.size(); ++i) needField |= views[i] && render::viewTypes()[i].needsField;
    if (!args.sdf.empty()) {
        field = loadAnyField(args.sdf);
        if (const std::string mismatch = fieldMismatch(field.header(), mesh); !mismatch.empty()) {
            control.warn(args.sdf + ": " + mismatch);
        }
    } else if (needField) {
        ProgressBar bar;
        RunControl baking = control; // the bar's callback lives only as long as the bar
        baking.progress = bar.callback();
        field = model.bake(args.settings, baking).field;
    }

    std::unique_ptr<render::GlContext> context = render::createHeadlessContext(pixels);
    render::Scene scene;
    scene.showOnly(views);
    scene.sliceNormal = sliceNormal;
    scene.slicePosition = args.slicePosition;
    scene.view<render::RaymarchView>().shadows = !args.noShadows;
    scene.view<render::RaymarchView>().iso = args.iso;
    scene.colormap = colormap;
    if (args.colourRange > 0.0f) scene.view<render::SliceView>().range = scene.view<render::VolumeView>().range = glm::vec2(-args.colourRange, args.colourRange);
    scene.sliceCut = args.cutAway ? 1 : 0;
    scene.colourBar = !args.noColourBar;
    scene.view<render::WireView>().seeThrough = args.wireSeeThrough;
    if (!args.background.empty()) {
        const std::vector<float> rgb = parseNumbers(args.background, ',', 3, "--background (r,g,b in 0..1)");
        for (float channel : rgb) {
            if (channel < 0.0f || channel > 1.0f) throw Error("--background '" + args.background + "': each channel must be in 0..1");
        }
        scene.background = glm::vec3(rgb[0], rgb[1], rgb[2]);
    }
    if (meshes.size() == 1) {
        scene.setMesh(mesh);
    } else {
        std::vector<MeshInstance> parts;
        for (const Mesh& part : meshes) parts.push_back({&part, glm::dmat4(1.0)});
        scene.setMeshes(parts);
    }
    if (field.isBand()) {
        render::BandDisplay shown = render::bandDisplay(field.band(), render::textureLimit3D(), control);
        std::printf("%s: %s\n", args.sdf.c_str(), shown.line.c_str());
        field = std::move(shown.field);
    }
    if (!field.dense().values.empty()) scene.setField(field.dense());

    render::OrbitCamera orbit;
    orbit.yaw = camera[0];
    orbit.pitch = camera[1];
    orbit.orthographic = args.orthographic;
    orbit.frame(mesh.worldBounds(), camera[2], float(pixels.x) / float(pixels.y)); // fits a narrow image too
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
    render->add_option("mesh", args->meshes, "Input mesh (" + meshFormatList() + ", ...); several make one scene")->required();
    render->add_option("-o,--output", args->output, "Output PNG file")->required();
    render->add_option("--sdf", args->sdf, "Field file to show (default: bake one from the mesh when a view needs it)");
    render->add_option("--view", args->views, "Comma-separated views: " + render::viewNames() + " (or all, none)")
        ->capture_default_str();
    render->add_option("--camera", args->camera, "Orbit camera: yaw,pitch in degrees and zoom (1 frames the mesh; 2 is twice as far)")
        ->capture_default_str();
    render->add_option("--size", args->size, "Image size in pixels, WIDTHxHEIGHT")->capture_default_str();
    render->add_option("--slice-axis", args->sliceAxis, "Axis the slice view cuts across: x, y or z")->capture_default_str();
    render->add_option("--slice-normal", args->sliceNormal, "Slice plane at any orientation: its normal x,y,z (instead of --slice-axis)");
    render->add_option("--slice-pos", args->slicePosition, "Slice position across the field's box along its normal, 0 to 1")
        ->check(finiteRange(0.0, 1.0))
        ->capture_default_str();
    render->add_option("--iso", args->iso, "Level set the raymarch view shows (0: the surface; > 0 outwards, < 0 inwards)")
        ->check(finiteRange(-1e30, 1e30))
        ->capture_default_str();
    render->add_option("--colormap", args->colormap, "Colour map of the slice, volume and colour bar: diverging, viridis or grey")
        ->capture_default_str();
    render->add_option("--range", args->colourRange, "Distance at which the colour map saturates (0: a quarter of the field's box)")
        ->check(finiteRange(0.0, 1e30))
        ->capture_default_str();
    render->add_flag("--no-colour-bar", args->noColourBar, "No colour bar beside the slice and volume views");
    render->add_flag("--cut-away", args->cutAway,
                     "The slice's plane (see --slice-axis, --slice-normal, --slice-pos) cuts away the mesh, wire and ray-marched surface on the side its normal points to");
    render->add_flag("--ortho", args->orthographic, "Orthographic camera instead of perspective");
    render->add_flag("--see-through", args->wireSeeThrough, "The wire view shows hidden edges too");
    render->add_option("--background", args->background, "Background colour r,g,b in 0..1 (default: dark grey)");
    render->add_flag("--no-shadows", args->noShadows, "Ray-marched view without soft shadows and ambient occlusion");
    render->add_option("--repeat", args->repeat, "Draw the frame N more times and print the mean frame time")
        ->check(CLI::Range(0, 100000));
    addBakeOptions(*render, args->settings, args->threads);
    render->callback([args] { runRender(*args); });
}

} // namespace sdfgen::cli
