// Render tests under OSMesa, or the context SDFGEN_HEADLESS names (ctest render-egl: EGL, as
// `sdfgen render` draws; Mesa llvmpipe either way, no display): screenshots of every view compared with
// reference images, checks that need no reference (not blank, toggling a view changes the image),
// and the ray-marched silhouette against the rasterised one.
//
// Reference images: tests/render/reference/<model>_<view>.png. To (re)create them after an
// intended change in how a view looks, run
//     SDFGEN_UPDATE_REFERENCES=1 build/tests/sdfgen_render_tests
// and look at the images before committing them. A failing comparison writes the image it got
// beside the test binary (render-actual/), to compare by eye.
#include "sdfgen/error.hpp"
#include "core/bake/bake.hpp"
#include "core/accel/bvh.hpp"
#include "sdfgen/mesh.hpp"
#include "render/band_display.hpp"
#include "render/image.hpp"
#include "render/egl_context.hpp"
#include "render/osmesa_context.hpp"
#include "render/scene.hpp"
#include "render/views.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>
#include <algorithm>
#include <functional>
#include <glm/gtc/matrix_transform.hpp>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <string>

namespace sdfgen::render {
namespace {

namespace fs = std::filesystem;

// Small images keep the suite fast on llvmpipe with two cores.
constexpr glm::ivec2 kSize{256, 192};

// One context, scene and set of baked models for the whole suite.
struct Model {
    Mesh mesh;
    Field field;
};

// The sign errors view's crosses: nine along a diagonal of the box's top, above the model (crosses
// are depth-tested), each a tenth of the box across (the viewer's come from a comparison).
std::vector<glm::vec3> crossesAlongDiagonal(const Grid& grid) {
    const glm::vec3 lo(grid.origin), size = glm::vec3(grid.dims) * float(grid.voxel);
    std::vector<glm::vec3> segments;
    for (int n = 1; n <= 9; ++n) {
        const glm::vec3 at = lo + size * glm::vec3(float(n) / 10.0f, 0.95f, float(n) / 10.0f);
        for (int a = 0; a < 3; ++a) {
            glm::vec3 d(0.0f);
            d[a] = 0.05f * size[a];
            segments.push_back(at - d);
            segments.push_back(at + d);
        }
    }
    return segments;
}

class RenderTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        context_ = (std::getenv("SDFGEN_HEADLESS") ? createHeadlessContext(kSize) : createOsMesaContext(kSize)).release();
        scene_ = new Scene();
        models_ = new std::map<std::string, Model>();
        // The generated torus at res 64; the bundled bunny at res 128, as in the silhouette test.
        addModel("torus", test::torus(1.0f, 0.4f, 48, 24), 64);
        addModel("bunny", loadMesh(test::bundledBunnyPath()), 128);
        // A scene of two meshes (mergeMeshes): the bunny and a torus three times as large beside it.
        const Mesh& bunny = models_->at("bunny").mesh;
        ring_ = new Mesh(test::torus(1.0f, 0.4f, 48, 24));
        ringPlace_ = glm::scale(glm::translate(glm::dmat4(1.0), glm::dvec3(bunny.worldBounds().max.x + 3.0, 4.0, 0.0)), glm::dvec3(3.0));
        addModel("scene", mergeMeshes({{&bunny, glm::dmat4(1.0)}, {ring_, ringPlace_}}, "bunny+torus"), 96);
        // The bunny as a band field of one voxel each side at res 512, shown under a texture limit
        // of 128: resampled 4x coarser, where the band is a quarter of a shown voxel wide.
        BakeSettings settings;
        settings.res = 512;
        settings.band = 1;
        band_ = new SparseField(bake(bunny, Bvh(bunny), settings, RunControl{}).field.band());
        bandShown_ = new BandDisplay(bandDisplay(*band_, 128));
        (*models_)["bunny band"] = Model{bunny, bandShown_->field};
    }
    static void TearDownTestSuite() {
        delete models_;
        delete bandShown_;
        delete band_;
        delete ring_;
        delete scene_;
        delete context_;
    }
    static void addModel(const std::string& name, Mesh mesh, int res) {
        const Bvh tree(mesh);
        BakeSettings settings;
        settings.res = res;
        Field field = bake(mesh, tree, settings, RunControl{}).field.dense();
        (*models_)[name] = Model{std::move(mesh), std::move(field)};
    }

    // Draws `views` of a model with a fixed camera and background; `tweak` changes the scene's
    // settings from their defaults.
    static Image draw(const std::string& model, const std::vector<bool>& views, float yaw = 30.0f, float pitch = 20.0f,
                      glm::vec3 background = glm::vec3(0.16f, 0.17f, 0.19f), bool shadows = true,
                      const std::function<void(Scene&)>& tweak = {}) {
        const Model& m = models_->at(model);
        scene_->setMesh(m.mesh);
        scene_->setField(m.field);
        scene_->showOnly(views);
        scene_->background = background;
        scene_->view<RaymarchView>().shadows = shadows;
        scene_->sliceNormal = axisNormal(2);
        scene_->slicePosition = 0.5f;
        scene_->view<RaymarchView>().iso = 0.0f;
        scene_->view<WireView>().seeThrough = false;
        scene_->colourBar = true;
        scene_->colormap = 0;
        scene_->view<SliceView>().range = scene_->view<VolumeView>().range = glm::vec2(0.0f);
        scene_->sliceCut = 0;
        scene_->view<SignErrorsView>().crosses = crossesAlongDiagonal(m.field.grid);
        if (tweak) tweak(*scene_);
        OrbitCamera camera;
        camera.yaw = yaw;
        camera.pitch = pitch;
        camera.frame(m.mesh.worldBounds());
        scene_->draw(camera, kSize);
        context_->present();
        return readFramebuffer(kSize.x, kSize.y);
    }

    static GlContext* context_;
    static Scene* scene_;
    static std::map<std::string, Model>* models_;

    static SparseField* band_;
    static BandDisplay* bandShown_;

public:
    static Mesh* ring_;
    static glm::dmat4 ringPlace_;
};
GlContext* RenderTest::context_ = nullptr;
Scene* RenderTest::scene_ = nullptr;
std::map<std::string, Model>* RenderTest::models_ = nullptr;
Mesh* RenderTest::ring_ = nullptr;
SparseField* RenderTest::band_ = nullptr;
BandDisplay* RenderTest::bandShown_ = nullptr;
glm::dmat4 RenderTest::ringPlace_{1.0};

std::vector<bool> only(const std::string& list) { return parseViewList(list); }

// Pixels whose largest channel difference exceeds `threshold`.
std::size_t differingPixels(const Image& a, const Image& b, int threshold, int* largest = nullptr) {
    std::size_t count = 0;
    int maxDiff = 0;
    for (std::size_t i = 0; i < a.rgba.size(); i += 4) {
        int d = 0;
        for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(int(a.rgba[i + c]) - int(b.rgba[i + c])));
        maxDiff = std::max(maxDiff, d);
        if (d > threshold) ++count;
    }
    if (largest) *largest = maxDiff;
    return count;
}

std::size_t pixelCount(const Image& image) { return std::size_t(image.width) * std::size_t(image.height); }

// Pixels that differ from the background colour at all.
std::vector<bool> coverage(const Image& image) {
    std::vector<bool> mask(pixelCount(image));
    for (std::size_t i = 0; i < mask.size(); ++i) {
        const std::uint8_t* p = &image.rgba[i * 4];
        mask[i] = p[0] != 0 || p[1] != 0 || p[2] != 0;
    }
    return mask;
}

// ---------------------------------------------------------------------------------------------
// Screenshots against references.

struct Shot {
    std::string model;
    std::string view;
    std::string variant; // a named change of the scene's settings (see tweakFor), or ""
};
std::string fileName(const Shot& shot) {
    std::string name = shot.model + "_" + shot.view + (shot.variant.empty() ? "" : "_" + shot.variant);
    std::replace(name.begin(), name.end(), ',', '_');
    return name;
}
std::string shotName(const ::testing::TestParamInfo<Shot>& info) { return fileName(info.param); }

// The variants: oblique slices, iso levels out and in (in voxels of the res-128 bunny field), the
// see-through wireframe, another colour map with a fixed range.
// The scene's meshes as separate parts (one colour each): the bunny and the placed torus.
std::vector<MeshInstance> sceneParts();

std::function<void(Scene&)> tweakFor(const std::string& variant) {
    if (variant == "oblique") return [](Scene& s) { s.sliceNormal = glm::normalize(glm::vec3(1.0f, 1.0f, 0.5f)); s.slicePosition = 0.45f; };
    if (variant == "isoout") return [](Scene& s) { s.view<RaymarchView>().iso = 0.5f; };
    if (variant == "isoin") return [](Scene& s) { s.view<RaymarchView>().iso = -0.3f; };
    if (variant == "seethrough") return [](Scene& s) { s.view<WireView>().seeThrough = true; };
    if (variant == "viridis") return [](Scene& s) { s.colormap = 1; s.view<SliceView>().range = glm::vec2(-1.0f, 1.0f); };
    if (variant == "cut") return [](Scene& s) { s.sliceCut = 1; s.sliceNormal = axisNormal(0); s.slicePosition = 0.55f; };
    if (variant == "parts") return [](Scene& s) { s.setMeshes(sceneParts()); };
    return {};
}

std::vector<MeshInstance> sceneParts() {
    // The bunny as loaded (the merged scene's first part) and the ring where the scene put it.
    static const Mesh bunny = loadMesh(test::bundledBunnyPath());
    return {{&bunny, glm::dmat4(1.0)}, {RenderTest::ring_, RenderTest::ringPlace_}};
}

class Screenshot : public RenderTest, public ::testing::WithParamInterface<Shot> {};

TEST_P(Screenshot, MatchesReference) {
    const Shot& shot = GetParam();
    const Image image = draw(shot.model, only(shot.view), 30.0f, 20.0f, glm::vec3(0.16f, 0.17f, 0.19f), true, tweakFor(shot.variant));
    const std::string name = fileName(shot) + ".png";
    const fs::path reference = fs::path(SDFGEN_SOURCE_DIR) / "tests/render/reference" / name;
    if (const char* update = std::getenv("SDFGEN_UPDATE_REFERENCES"); update && std::string(update) == "1") {
        savePng(image, reference.string());
        GTEST_SKIP() << "wrote " << reference;
    }
    ASSERT_TRUE(fs::exists(reference)) << reference << " is missing; create it with SDFGEN_UPDATE_REFERENCES=1";
    const Image expected = loadPng(reference.string());
    ASSERT_EQ(expected.width, image.width);
    ASSERT_EQ(expected.height, image.height);
    // Tolerance. llvmpipe's results vary a little between Mesa versions and CPUs (vector width,
    // FMA contraction, rasterisation and texture-filtering precision): shading moves by a few
    // levels, and edges, wireframe lines and contours move by about a pixel. So a pixel counts as
    // different only when a channel moves by more than 24 of 255 (shading drift stays well below
    // that; a wrong colour map, light or transfer function does not), and up to 1.5% of the
    // pixels (737 of 49152) may differ: about a one-pixel shift along every silhouette and line of
    // these images. A missing or misplaced view, a wrong camera or a broken field changes far more.
    int largest = 0;
    const std::size_t differing = differingPixels(image, expected, 24, &largest);
    const std::size_t budget = pixelCount(image) * 15 / 1000;
    if (differing > budget) {
        const fs::path actual = fs::path("render-actual") / name;
        fs::create_directories(actual.parent_path());
        savePng(image, actual.string());
        ADD_FAILURE() << name << ": " << differing << " pixels differ by more than 24 levels (budget " << budget
                      << ", largest difference " << largest << "); got " << fs::absolute(actual);
    }
}

std::vector<Shot> allShots() {
    std::vector<Shot> shots;
    for (const char* model : {"torus", "bunny"}) {
        for (const ViewType& type : viewTypes()) shots.push_back({model, type.name, ""}); // every registered view
    }
    // The colour bar (beside every slice and volume shot above) with another map; slice
    // orientation; iso levels; hidden-line and see-through wireframes; a scene of two meshes.
    shots.push_back({"bunny", "slice", "viridis"});
    shots.push_back({"bunny", "slice,box", "oblique"});
    shots.push_back({"torus", "slice", "oblique"});
    shots.push_back({"bunny", "raymarch", "isoout"});
    shots.push_back({"bunny", "raymarch", "isoin"});
    shots.push_back({"bunny", "wire", "seethrough"});
    shots.push_back({"scene", "grid,mesh", ""});
    shots.push_back({"scene", "raymarch,slice", ""});
    // The slice cutting the mesh and the ray-marched surface away on its normal's side; one
    // colour per mesh of a scene.
    shots.push_back({"bunny", "mesh", "cut"});
    shots.push_back({"bunny", "raymarch", "cut"});
    shots.push_back({"bunny", "raymarch,slice", "cut"});
    shots.push_back({"scene", "grid,mesh", "parts"});
    return shots;
}
INSTANTIATE_TEST_SUITE_P(Views, Screenshot, ::testing::ValuesIn(allShots()), shotName);

// ---------------------------------------------------------------------------------------------
// Checks without references.

TEST_F(RenderTest, EveryViewDrawsSomething) {
    const Image empty = draw("bunny", only("none"));
    for (const ViewType& type : viewTypes()) {
        const Image image = draw("bunny", only(type.name));
        const std::size_t changed = differingPixels(image, empty, 8);
        EXPECT_GT(changed, pixelCount(image) / 400) << type.name << " leaves the image (nearly) blank"; // the box's lines: about 1%
    }
}

TEST_F(RenderTest, TogglingAViewChangesTheImage) {
    const Image base = draw("torus", only("grid,mesh"));
    for (const ViewType& type : viewTypes()) {
        const std::string extra = type.name;
        if (extra == "grid" || extra == "mesh") continue; // the base
        const Image image = draw("torus", only("grid,mesh," + extra));
        EXPECT_GT(differingPixels(image, base, 8), pixelCount(image) / 400) << "turning on " << extra;
    }
    EXPECT_GT(differingPixels(draw("torus", only("grid")), base, 8), pixelCount(base) / 50) << "turning off mesh";
    EXPECT_GT(differingPixels(draw("torus", only("mesh")), base, 8), pixelCount(base) / 50) << "turning off grid";
}

TEST_F(RenderTest, ModelOccludesGridAndRaymarchCompositesWithMesh) {
    // The mesh drawn alone and with the grid must agree where the mesh is: the grid never shows
    // through it. Likewise the ray-marched surface (which writes depth) hides the grid.
    const glm::vec3 black(0.0f);
    for (const char* view : {"mesh", "raymarch"}) {
        const Image alone = draw("bunny", only(view), 30.0f, 20.0f, black);
        const Image withGrid = draw("bunny", only(std::string(view) + ",grid"), 30.0f, 20.0f, black);
        const std::vector<bool> mask = coverage(alone);
        std::size_t covered = 0, changed = 0;
        for (std::size_t i = 0; i < mask.size(); ++i) {
            if (!mask[i]) continue;
            ++covered;
            int d = 0;
            for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(int(alone.rgba[i * 4 + c]) - int(withGrid.rgba[i * 4 + c])));
            if (d > 8) ++changed;
        }
        ASSERT_GT(covered, 1000u);
        EXPECT_LT(changed, covered / 100) << view << ": the grid shows through the model";
    }
}

// The set of pixels the sphere tracer hits must match the rasterised mesh's: this checks the
// generator, the texture upload, the mapping of the field's box and the marcher together.
TEST_F(RenderTest, RaymarchedSilhouetteMatchesMesh) {
    const glm::vec3 black(0.0f);
    for (const auto& [yaw, pitch] : std::vector<std::pair<float, float>>{{30, 20}, {120, 5}, {210, 45}, {300, -25}, {0, 85}}) {
        const std::vector<bool> mesh = coverage(draw("bunny", only("mesh"), yaw, pitch, black, false));
        const std::vector<bool> marched = coverage(draw("bunny", only("raymarch"), yaw, pitch, black, false));
        std::size_t both = 0, either = 0;
        for (std::size_t i = 0; i < mesh.size(); ++i) {
            both += mesh[i] && marched[i];
            either += mesh[i] || marched[i];
        }
        ASSERT_GT(either, 1000u);
        const double iou = double(both) / double(either);
        EXPECT_GE(iou, 0.95) << "camera yaw " << yaw << ", pitch " << pitch;
        RecordProperty("iou_" + std::to_string(int(yaw)), std::to_string(iou));
    }
}

// Offset surfaces: the ray-marched level set covers more pixels as the iso level grows.
TEST_F(RenderTest, IsoLevelGrowsAndShrinksTheSurface) {
    const glm::vec3 black(0.0f);
    auto covered = [&](float iso) {
        const std::vector<bool> mask = coverage(draw("bunny", only("raymarch"), 30.0f, 20.0f, black, false, [iso](Scene& s) { s.view<RaymarchView>().iso = iso; }));
        return std::count(mask.begin(), mask.end(), true);
    };
    const auto inner = covered(-0.3f), surface = covered(0.0f), outer = covered(0.5f);
    EXPECT_LT(inner, surface);
    EXPECT_LT(surface, outer);
    EXPECT_GT(outer, surface * 11 / 10) << "an offset of 0.5 (about 4% of the bunny) should grow the silhouette visibly";
}

// Hidden-line removal: the wireframe alone draws only the front edges, far fewer line pixels than
// the see-through one, and none where the mesh is not.
TEST_F(RenderTest, WireframeHidesHiddenLines) {
    const glm::vec3 black(0.0f);
    const std::vector<bool> hidden = coverage(draw("bunny", only("wire"), 30.0f, 20.0f, black));
    const std::vector<bool> through = coverage(draw("bunny", only("wire"), 30.0f, 20.0f, black, true, [](Scene& s) { s.view<WireView>().seeThrough = true; }));
    const std::vector<bool> solid = coverage(draw("bunny", only("mesh"), 30.0f, 20.0f, black));
    const auto hiddenCount = std::count(hidden.begin(), hidden.end(), true), throughCount = std::count(through.begin(), through.end(), true);
    std::size_t outside = 0;
    for (std::size_t i = 0; i < hidden.size(); ++i) outside += hidden[i] && !solid[i];
    EXPECT_LT(hiddenCount, throughCount * 9 / 10);
    EXPECT_LT(outside, std::size_t(hiddenCount) / 20);
}

// Where the ray-marched surface and the shaded mesh are both drawn, the ray-marched one wins
// everywhere (no z-fighting pattern of mesh pixels showing through).
TEST_F(RenderTest, RaymarchWinsOverTheMesh) {
    const glm::vec3 black(0.0f);
    const Image marched = draw("bunny", only("raymarch"), 30.0f, 20.0f, black, false);
    const Image both = draw("bunny", only("raymarch,mesh"), 30.0f, 20.0f, black, false);
    const std::vector<bool> mask = coverage(marched);
    std::size_t covered = 0, differ = 0;
    for (std::size_t i = 0; i < mask.size(); ++i) {
        if (!mask[i]) continue;
        ++covered;
        int d = 0;
        for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(int(marched.rgba[i * 4 + c]) - int(both.rgba[i * 4 + c])));
        differ += d > 8;
    }
    ASSERT_GT(covered, 1000u);
    EXPECT_LT(differ, covered / 100) << "mesh pixels show through the ray-marched surface";
}

// The colour bar is drawn at the right edge with the slice, follows the colour map, and goes away
// when turned off.
TEST_F(RenderTest, ColourBarFollowsTheColourMap) {
    auto barColumn = [](const Image& image) {
        std::vector<std::uint8_t> column;
        const int x = image.width - 14; // inside the bar (10 px margin, 8 px wide at this size)
        for (int y = image.height / 4; y < image.height * 3 / 4; ++y) column.insert(column.end(), image.pixel(x, y), image.pixel(x, y) + 3);
        return column;
    };
    const Image diverging = draw("torus", only("slice"));
    const Image viridis = draw("torus", only("slice"), 30.0f, 20.0f, glm::vec3(0.16f, 0.17f, 0.19f), true, [](Scene& s) { s.colormap = 1; });
    const Image none = draw("torus", only("slice"), 30.0f, 20.0f, glm::vec3(0.16f, 0.17f, 0.19f), true, [](Scene& s) { s.colourBar = false; });
    EXPECT_NE(barColumn(diverging), barColumn(viridis));
    EXPECT_NE(barColumn(diverging), barColumn(none));
    // Top of the bar is the outside colour (blue in the diverging map), bottom the inside (red).
    const int x = diverging.width - 14, top = int(0.5f * (1.0f - 0.45f) * float(diverging.height)) + 3;
    const int bottom = int(0.5f * (1.0f + 0.45f) * float(diverging.height)) - 3;
    EXPECT_GT(diverging.pixel(x, top)[2], diverging.pixel(x, top)[0] + 60);
    EXPECT_GT(diverging.pixel(x, bottom)[0], diverging.pixel(x, bottom)[2] + 60);
}

// One colour bar per range: with the slice and the volume on the same range, one bar (not named);
// with different ranges, a bar each, named "slice" and "volume", the volume's drawn left of the
// slice's, whose bar stays where the single one was.
TEST_F(RenderTest, ColourBarPerRange) {
    const std::vector<bool> both = only("slice,volume");
    std::vector<ColourBar> bars;
    const Image one = draw("torus", both, 30.0f, 20.0f, glm::vec3(0.16f, 0.17f, 0.19f), true, [&](Scene& s) { bars = s.colourBars(); });
    ASSERT_EQ(bars.size(), 1u);
    EXPECT_EQ(bars[0].name, nullptr);
    const Image two = draw("torus", both, 30.0f, 20.0f, glm::vec3(0.16f, 0.17f, 0.19f), true, [&](Scene& s) {
        s.view<VolumeView>().range = glm::vec2(-0.1f, 0.1f);
        bars = s.colourBars();
    });
    ASSERT_EQ(bars.size(), 2u);
    EXPECT_STREQ(bars[0].name, "slice");
    EXPECT_STREQ(bars[1].name, "volume");
    EXPECT_EQ(bars[1].range, glm::vec2(-0.1f, 0.1f));
    // The bars' columns: the slice's at the right edge as before, another one further left (the
    // colour map's top and bottom: blue over red in the diverging map).
    auto barAt = [](const Image& image, int x) {
        const int top = int(0.5f * (1.0f - 0.45f) * float(image.height)) + 3, bottom = int(0.5f * (1.0f + 0.45f) * float(image.height)) - 3;
        const std::uint8_t *t = image.pixel(x, top), *b = image.pixel(x, bottom);
        return t[2] > t[0] + 60 && b[0] > b[2] + 60;
    };
    EXPECT_TRUE(barAt(one, one.width - 14));
    EXPECT_TRUE(barAt(two, two.width - 14));
    int left = 0;
    for (int x = two.width - 40; x > two.width / 2 && !left; --x) left = barAt(two, x) && !barAt(one, x) ? x : 0;
    EXPECT_GT(left, 0) << "no second bar left of the slice's";
}

// A scene's mesh hidden with its visibility toggle is not drawn, and nothing else changes.
TEST_F(RenderTest, HiddenMeshOfASceneIsNotDrawn) {
    const glm::vec3 grey(0.16f, 0.17f, 0.19f);
    const Image both = draw("scene", only("mesh"), 30.0f, 20.0f, grey, true, [](Scene& s) { s.setMeshes(sceneParts()); });
    const Image hidden = draw("scene", only("mesh"), 30.0f, 20.0f, grey, true, [](Scene& s) {
        s.setMeshes(sceneParts());
        s.meshStyles[1].visible = false;
    });
    const Image bunnyAlone = draw("scene", only("mesh"), 30.0f, 20.0f, grey, true, [](Scene& s) { s.setMeshes({sceneParts()[0]}); });
    EXPECT_GT(differingPixels(both, hidden, 8), pixelCount(both) / 50) << "hiding the torus changed little";
    EXPECT_EQ(differingPixels(hidden, bunnyAlone, 0), 0u) << "a hidden mesh still shows";
}

// The cut removes the model on the normal's side of the slice only: the other half is unchanged.
TEST_F(RenderTest, SliceCutRemovesOneSide) {
    const glm::vec3 black(0.0f);
    const Image whole = draw("bunny", only("mesh"), 0.0f, 0.0f, black);
    const Image cut = draw("bunny", only("mesh"), 0.0f, 0.0f, black, true, [](Scene& s) {
        s.sliceCut = 1;
        s.sliceNormal = axisNormal(0);
        s.colourBar = false;
        s.slicePosition = 0.5f;
    });
    // Seen from the front (yaw 0), +x is to the right: the left half must be as without the cut,
    // the right half is gone.
    std::size_t leftChanged = 0, rightChanged = 0;
    for (int y = 0; y < whole.height; ++y) {
        for (int x = 0; x < whole.width; ++x) {
            int d = 0;
            for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(int(whole.pixel(x, y)[c]) - int(cut.pixel(x, y)[c])));
            (x < whole.width / 2 - 4 ? leftChanged : rightChanged) += d > 8;
        }
    }
    EXPECT_GT(rightChanged, pixelCount(whole) / 50);
    EXPECT_LT(leftChanged, pixelCount(whole) / 200);
}

// ---------------------------------------------------------------------------------------------
// A band field, shown resampled.

TEST_F(RenderTest, BandFieldIsResampledToFit) {
    const glm::ivec3 d = band_->grid().dims, shown = bandShown_->field.grid.dims;
    EXPECT_EQ(bandShown_->factor, 4);
    EXPECT_EQ(shown, (d + 3) / 4);
    EXPECT_EQ(bandShown_->line, "band field " + std::to_string(d.x) + "x" + std::to_string(d.y) + "x" + std::to_string(d.z) +
                                    " (band 1 voxels): shown resampled to " + std::to_string(shown.x) + "x" + std::to_string(shown.y) + "x" +
                                    std::to_string(shown.z));
    EXPECT_EQ(bandShown_->field.background, band_->background());
    // The shown samples lie on the res-128 dense bake's: their sides agree but next to the surface.
    const Field& dense = models_->at("bunny").field;
    ASSERT_EQ(dense.grid.origin, bandShown_->field.grid.origin);
    std::size_t differ = 0, compared = 0;
    for (int k = 0; k < std::min(shown.z, dense.grid.dims.z); ++k)
        for (int j = 0; j < std::min(shown.y, dense.grid.dims.y); ++j)
            for (int i = 0; i < std::min(shown.x, dense.grid.dims.x); ++i) {
                const float v = bandShown_->field.at(i, j, k);
                ASSERT_LE(std::abs(v), band_->background());
                if ((i + j + k) % 5 == 0) { // SparseField::sample's value, exactly (clamped to the background)
                    const float sampled = band_->sample(bandShown_->field.grid.position(i, j, k));
                    ASSERT_EQ(v, std::clamp(sampled, -band_->background(), band_->background())) << i << " " << j << " " << k;
                }
                differ += std::abs(dense.at(i, j, k)) > float(dense.grid.voxel) && (v < 0.0f) != (dense.at(i, j, k) < 0.0f);
                ++compared;
            }
    EXPECT_EQ(differ, 0u) << "of " << compared;
    // The band's dense form where it fits.
    const Mesh torus = test::torus(1.0f, 0.4f, 48, 24);
    BakeSettings settings;
    settings.res = 32;
    settings.band = 2;
    const SparseField small = bake(torus, Bvh(torus), settings, RunControl{}).field.band();
    const BandDisplay full = bandDisplay(small, 128);
    EXPECT_EQ(full.factor, 1);
    EXPECT_EQ(full.field.values, small.toDense().values);
    EXPECT_EQ(full.line.substr(full.line.find(':')), ": shown at full resolution");
}

// Beyond the band the values are only the background (a quarter of a shown voxel here): the sphere
// tracer steps by it without overshooting and with enough steps to reach the surface, and the
// colours span the band.
TEST_F(RenderTest, BandFieldRaymarchMatchesMesh) {
    const glm::vec3 black(0.0f);
    for (const auto& [yaw, pitch] : std::vector<std::pair<float, float>>{{30, 20}, {210, 45}}) {
        const std::vector<bool> mesh = coverage(draw("bunny band", only("mesh"), yaw, pitch, black, false));
        const std::vector<bool> marched = coverage(draw("bunny band", only("raymarch"), yaw, pitch, black, false));
        std::size_t both = 0, either = 0;
        for (std::size_t i = 0; i < mesh.size(); ++i) {
            both += mesh[i] && marched[i];
            either += mesh[i] || marched[i];
        }
        ASSERT_GT(either, 1000u);
        EXPECT_GE(double(both) / double(either), 0.95) << "camera yaw " << yaw << ", pitch " << pitch;
    }
    // Shadows and occlusion take nothing from the background (a bound, not a distance): the band
    // field's surface is lit about as the dense field's is.
    auto brightness = [](const Image& image) {
        double sum = 0.0;
        std::size_t lit = 0;
        for (std::size_t i = 0; i < image.rgba.size(); i += 4) {
            const int v = std::max({image.rgba[i], image.rgba[i + 1], image.rgba[i + 2]});
            if (v > 0) sum += v, ++lit;
        }
        return lit ? sum / double(lit) : 0.0;
    };
    const double band = brightness(draw("bunny band", only("raymarch"), 30.0f, 20.0f, black, true));
    const double dense = brightness(draw("bunny", only("raymarch"), 30.0f, 20.0f, black, true));
    EXPECT_GT(band, 0.85 * dense) << "the band field's surface is darker than the dense field's";
    draw("bunny band", only("slice"));
    EXPECT_EQ(scene_->effectiveRange(glm::vec2(0.0f)), glm::vec2(-band_->background(), band_->background()));
    const Image empty = draw("bunny band", only("none"));
    for (const char* view : {"slice", "volume"}) {
        EXPECT_GT(differingPixels(draw("bunny band", only(view)), empty, 8), pixelCount(empty) / 50) << view << " leaves the image (nearly) blank";
    }
}

TEST_F(RenderTest, SlicePolygonCutsTheBox) {
    // Axis-aligned: a rectangle; through a corner diagonal: a hexagon at the middle.
    EXPECT_EQ(slicePolygon(glm::vec3(0.0f), glm::vec3(1.0f, 2.0f, 3.0f), axisNormal(2), 0.5f).size(), 4u);
    const std::vector<glm::vec3> hexagon = slicePolygon(glm::vec3(0.0f), glm::vec3(1.0f), glm::normalize(glm::vec3(1.0f)), 0.5f);
    ASSERT_EQ(hexagon.size(), 6u);
    for (const glm::vec3& p : hexagon) EXPECT_NEAR(p.x + p.y + p.z, 1.5f, 1e-5f);
}

TEST_F(RenderTest, FieldLargerThanTheTextureLimitIsAnError) {
    Field field;
    field.grid.dims = glm::ivec3(100000, 1, 1);
    field.values.assign(100000, 1.0f);
    EXPECT_THROW(scene_->setField(field), Error);
}

// "From the slice" colours: the range of the samples the slice interpolates. A plane midway
// between two layers of samples (position 0.5 across an even count) has both layers half a voxel
// away; rounding must not drop them and leave no range at all.
TEST(SliceValueRange, TakesTheLayersAroundThePlane) {
    Field field;
    field.grid.origin = glm::dvec3(-0.3);
    field.grid.voxel = 0.1;
    field.grid.dims = glm::ivec3(3, 3, 8);
    // Each sample's height above the middle plane (z = 0.1).
    for (int k = 0; k < 8; ++k) field.values.insert(field.values.end(), 9, float((k + 0.5) * 0.1 - 0.4));
    const glm::vec2 range = sliceValueRange(field, axisNormal(2), 0.5f);
    EXPECT_NEAR(range.x, -0.05f, 1e-6f);
    EXPECT_NEAR(range.y, 0.05f, 1e-6f);
    const glm::vec2 whole = fieldValueRange(field);
    EXPECT_NEAR(whole.x, -0.35f, 1e-6f);
    EXPECT_NEAR(whole.y, 0.35f, 1e-6f);
}

} // namespace
} // namespace sdfgen::render

