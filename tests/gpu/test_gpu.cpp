// The GPU compute device (src/gpu) against the CPU, under whatever OpenGL 4.5 driver the machine
// has (Mesa's llvmpipe in CI): the same distances (within 1e-4 voxel) and not one sign different,
// on closed, open, self-intersecting and overlapping meshes and the bundled bunny; determinism;
// cancellation. The bad-context suite (GpuBadContext) runs in its own process with
// MESA_GL_VERSION_OVERRIDE=3.3 (tests/CMakeLists.txt), since Mesa reads that once per process.
#include "core/bake/bake.hpp"
#include "core/distance/exact.hpp"
#include "core/mesh/sample_positions.hpp"
#include "core/sign/winding_sign.hpp"
#include "core/accel/topology.hpp"
#include "gpu/devices.hpp"
#include "gpu/gl_device.hpp"
#include "render/egl_context.hpp"
#include "render/gl.hpp"
#include "sdfgen/device.hpp"
#include "support/checks.hpp"
#include "support/shapes.hpp"
#include "support/stand_in_device.hpp"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <optional>
#include <thread>

namespace sdfgen {
namespace {

Mesh combined(const std::string& name, const std::vector<Mesh>& parts) {
    std::vector<glm::vec3> positions;
    std::vector<glm::uvec3> triangles;
    for (const Mesh& part : parts) {
        const unsigned shift = unsigned(positions.size());
        positions.insert(positions.end(), part.positions.begin(), part.positions.end());
        for (const glm::uvec3& t : part.triangles) triangles.push_back(t + glm::uvec3(shift));
    }
    return buildMesh(name, std::move(positions), std::move(triangles));
}

Mesh moved(const Mesh& mesh, glm::vec3 offset, bool flip) {
    std::vector<glm::vec3> positions = mesh.positions;
    for (glm::vec3& p : positions) p += offset;
    std::vector<glm::uvec3> triangles = mesh.triangles;
    if (flip) {
        for (glm::uvec3& t : triangles) std::swap(t.y, t.z);
    }
    return buildMesh(mesh.source, std::move(positions), std::move(triangles));
}

// `mesh` without the triangles whose centroid lies beyond `cut` along `axis`: holes.
Mesh cutOpen(const Mesh& mesh, glm::vec3 axis, float cut) {
    std::vector<glm::uvec3> kept;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const glm::vec3 centroid = (mesh.vertex(t, 0) + mesh.vertex(t, 1) + mesh.vertex(t, 2)) / 3.0f;
        if (glm::dot(centroid, axis) <= cut) kept.push_back(mesh.triangles[t]);
    }
    return buildMesh(mesh.source + " (cut open)", mesh.positions, std::move(kept));
}

// `mesh` placed far from the world origin at a small scale: only local coordinates keep its float
// work as exact as at unit size, and the device must sample at localPosition as the CPU does.
Mesh farAway(const Mesh& mesh, double scale, glm::dvec3 offset) {
    std::vector<glm::dvec3> positions = mesh.worldPositions();
    for (glm::dvec3& p : positions) p = offset + p * scale;
    return buildMesh(mesh.source + " (far away)", std::move(positions), mesh.triangles);
}

// `mesh` with every triangle `copies` times over (what a careless export or a stacked decal gives).
Mesh repeated(const Mesh& mesh, int copies) {
    std::vector<glm::uvec3> triangles;
    for (int copy = 0; copy < copies; ++copy) triangles.insert(triangles.end(), mesh.triangles.begin(), mesh.triangles.end());
    return buildMesh(mesh.source + " x" + std::to_string(copies), mesh.positions, std::move(triangles));
}

struct Shape {
    std::string name;
    Mesh mesh;
    int res;
};

std::vector<Shape> shapes() {
    const Mesh sphere = test::icosphere(1.0f, 2), small = test::icosphere(0.6f, 2);
    return {
        {"icosphere (closed)", sphere, 16},
        {"box (closed, faces on grid planes)", test::box({1.0f, 0.5f, 0.25f}), 16},
        {"torus (closed)", test::torus(1.0f, 0.3f, 24, 12), 16},
        {"sphere with a hole", cutOpen(sphere, {0, 1, 0}, 0.8f), 16},
        {"torus with holes", cutOpen(test::torus(1.0f, 0.3f, 24, 12), glm::normalize(glm::vec3(1, 0.2f, 0.1f)), 0.9f), 16},
        {"two overlapping shells", combined("two shells", {moved(sphere, {-0.5f, 0, 0}, false), moved(sphere, {0.5f, 0, 0}, false)}), 16},
        {"overlapping shells, one flipped", combined("flipped", {moved(sphere, {-0.5f, 0, 0}, false), moved(sphere, {0.5f, 0, 0}, true)}), 16},
        {"bunny", loadObj(test::bundledBunnyPath()), 20},
        {"bunny far from the origin, small", farAway(loadObj(test::bundledBunnyPath()), 3e-3, {1e5, -2.5e5, 7e4}), 20},
        {"holed sphere far from the origin, large", farAway(cutOpen(sphere, {0, 1, 0}, 0.8f), 1e4, {-3e7, 1e6, 5e8}), 16},
        {"2,000 stacked copies of an open triangle",
         repeated(buildMesh("triangle", std::vector<glm::vec3>{{0, 0, 0}, {1, 0.2f, 0}, {0.3f, 1, 0.4f}}, {{0, 1, 2}}), 2000), 12},
        {"holed torus, every triangle three times", repeated(cutOpen(test::torus(1.0f, 0.3f, 16, 8), {0, 0, 1}, 0.1f), 3), 14},
        {"closed sphere, every triangle twice", repeated(sphere, 2), 12},
        {"inside-out torus (auto flips the pseudonormal sign)", moved(test::torus(1.0f, 0.3f, 24, 12), {0, 0, 0}, true), 14},
        // The inside rule |w| > 1/2: parts inside out are solid (w = -1), a reversed inner shell's cavity
        // is empty, opposite copies cancel where they overlap.
        {"sphere beside a smaller one inside out", combined("beside", {moved(sphere, {-1.2f, 0, 0}, false), moved(small, {1.0f, 0, 0}, true)}), 16},
        {"hollow sphere (inner shell reversed)", combined("hollow", {sphere, moved(small, {0, 0, 0}, true)}), 16},
        {"sphere overlapped by a smaller one inside out", combined("overlapped", {sphere, moved(small, {0.8f, 0, 0}, true)}), 16},
        {"sphere and its reversed copy", combined("opposite copies", {sphere, moved(sphere, {0, 0, 0}, true)}), 12},
        {"inside-out sphere with a hole", moved(cutOpen(sphere, {0, 1, 0}, 0.8f), {0, 0, 0}, true), 16},
        {"inside-out sheet beside a closed sphere", combined("sheet", {moved(small, {0, 0, -1.0f}, false), moved(cutOpen(sphere, {0, 1, 0}, 0.0f), {0, 0, 1.0f}, true)}), 16},
    };
}

// Every sample within 1e-4 voxel of the CPU's distance and not one sign different.
void expectEqualFields(const BakeResult& cpu, const BakeResult& gpu) {
    EXPECT_FALSE(cpu.onDevice);
    EXPECT_TRUE(gpu.onDevice);
    EXPECT_EQ(cpu.sign, gpu.sign);
    EXPECT_EQ(cpu.field.dense().method, gpu.field.dense().method);
    const std::vector<float>& a = cpu.field.dense().values;
    const std::vector<float>& b = gpu.field.dense().values;
    ASSERT_EQ(a.size(), b.size());
    const double voxel = cpu.field.dense().grid.voxel;
    double worst = 0;
    std::size_t signs = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        worst = std::max(worst, std::fabs(double(std::fabs(a[i])) - double(std::fabs(b[i]))) / voxel);
        signs += std::signbit(a[i]) != std::signbit(b[i]);
    }
    EXPECT_LE(worst, 1e-4);
    EXPECT_EQ(signs, 0u) << "of " << a.size() << " samples";
}

BakeResult bakeOn(const Mesh& mesh, int res, const std::string& device, SignMethod sign, const RunControl& control = {}) {
    BakeSettings settings;
    settings.res = res;
    settings.sign = sign;
    settings.device = device;
    const Bvh tree(mesh);
    return bake(mesh, tree, settings, control);
}

// The triangles the device's winding pass sums over: the mesh's (weight 1), then each cap's fan.
void windingTriangles(const Mesh& mesh, const WindingCaps& caps, std::vector<glm::dvec3>& corners, std::vector<std::int32_t>& weights) {
    for (std::uint32_t t = 0; t < mesh.triangleCount(); ++t) {
        corners.insert(corners.end(), {glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)), glm::dvec3(mesh.vertex(t, 2))});
        weights.push_back(1);
    }
    for (const Cap& cap : caps.caps()) {
        for (std::size_t i = 0; i < cap.loop.size(); ++i) {
            corners.insert(corners.end(), {cap.loop[(i + 1) % cap.loop.size()], cap.loop[i], cap.centre});
            weights.push_back(cap.weight);
        }
    }
}

class Gpu : public ::testing::Test {
protected:
    static void SetUpTestSuite() { gpu::registerDevices(); }
};

TEST_F(Gpu, OpensAndDescribesItsDriver) {
    std::string why;
    ComputeDevice* device = selectComputeDevice("gpu", &why);
    ASSERT_NE(device, nullptr);
    EXPECT_NE(device->description().find("renderer"), std::string::npos) << device->description();
    // gpu-osmesa (tests/CMakeLists.txt) runs this with SDFGEN_HEADLESS=osmesa.
    const char* only = std::getenv("SDFGEN_HEADLESS");
    const std::string through = only && std::string(only) == "osmesa" ? "through OSMesa" : "through EGL";
    EXPECT_NE(device->description().find(through), std::string::npos) << device->description();
    // Auto takes the device only when it is hardware.
    EXPECT_EQ(selectComputeDevice("auto") != nullptr, device->hardware());
    EXPECT_EQ(selectComputeDevice("cpu"), nullptr);
    EXPECT_TRUE(gpu::isSoftwareRenderer("llvmpipe (LLVM 15.0.6, 256 bits)"));
    EXPECT_FALSE(gpu::isSoftwareRenderer("NVIDIA H200/PCIe/SSE2"));
}

// A second device beside the OpenGL one (a stand-in that answers on the CPU): both are listed and
// chosen by name, and auto passes over the one that is not hardware.
TEST_F(Gpu, CoexistsWithAnotherDevice) {
    int calls = 0;
    const test::ScopedDevice fake(test::standInDevice("fake", false, &calls));
    std::vector<std::string> names;
    for (const Choice<std::string>& choice : deviceChoices()) names.push_back(choice.name);
    EXPECT_EQ(names, (std::vector<std::string>{"cpu", "gpu", "fake", "auto"}));
    std::string why;
    ComputeDevice* gl = selectComputeDevice("gpu");
    ComputeDevice* other = selectComputeDevice("fake", &why);
    ASSERT_NE(gl, nullptr);
    ASSERT_NE(other, nullptr);
    EXPECT_NE(gl, other);
    EXPECT_EQ(why, "fake: stand-in");
    // Auto: the GL device where it is hardware, else the CPU; never the fake.
    EXPECT_EQ(selectComputeDevice("auto", &why), gl->hardware() ? gl : nullptr) << why;
    if (!gl->hardware()) {
        EXPECT_CONTAINS(why, "; device fake: the only stand-in driver runs on the CPU (stand-in)");
    }
    {
        // A fake on hardware, after the GL device: taken by auto only where the GL device is not hardware.
        const test::ScopedDevice hardwareFake(test::standInDevice("hardware-fake", true));
        ComputeDevice* fast = selectComputeDevice("hardware-fake");
        EXPECT_EQ(selectComputeDevice("auto", &why), gl->hardware() ? gl : fast) << why;
    }
    // A bake on the fake uses its answers: the CPU's field, as the GL device's.
    const Mesh sphere = test::icosphere(1.0f, 2);
    const BakeResult onFake = bakeOn(sphere, 12, "fake", SignMethod::Winding);
    EXPECT_EQ(calls, 2);
    EXPECT_EQ(onFake.deviceReason, "fake: stand-in");
    expectEqualFields(bakeOn(sphere, 12, "cpu", SignMethod::Winding), onFake);
}

// Sign auto (pseudonormal on the closed clean meshes, from the GPU's nearest triangles; winding on
// the others) and, where auto picks pseudonormal, winding as well.
TEST_F(Gpu, EqualsTheCpu) {
    for (const Shape& shape : shapes()) {
        SCOPED_TRACE(shape.name);
        const BakeResult cpu = bakeOn(shape.mesh, shape.res, "cpu", SignMethod::Auto);
        expectEqualFields(cpu, bakeOn(shape.mesh, shape.res, "gpu", SignMethod::Auto));
        if (cpu.sign == SignMethod::Pseudonormal) {
            SCOPED_TRACE("sign winding");
            expectEqualFields(bakeOn(shape.mesh, shape.res, "cpu", SignMethod::Winding),
                              bakeOn(shape.mesh, shape.res, "gpu", SignMethod::Winding));
        }
    }
}

// Rows of samples through the mesh's shared edges and vertices, where only the symbolic
// tie-breaking decides which triangle a row crosses: a cube whose padding puts samples at -2..2 in
// whole units, so rows run through its corners and along its edges, and a finer grid whose
// diagonal rows (j = k) run along the faces' diagonals.
TEST_F(Gpu, EqualsTheCpuWhereRowsHitEdgesAndVertices) {
    const Mesh cube = test::box({1.0f, 1.0f, 1.0f});
    for (const auto& [res, padding] : {std::pair{5, 0.75f}, std::pair{16, 0.1f}}) {
        for (SignMethod sign : {SignMethod::Winding, SignMethod::Pseudonormal}) {
            SCOPED_TRACE("res " + std::to_string(res) + ", sign " + toString(sign));
            BakeSettings settings;
            settings.res = res;
            settings.padding = padding;
            settings.sign = sign;
            settings.device = "cpu";
            const BakeResult cpu = test::bakeMesh(cube, settings);
            settings.device = "gpu";
            const BakeResult gpu = test::bakeMesh(cube, settings);
            if (res == 5) {
                ASSERT_EQ(cpu.field.dense().grid.position(1, 1, 1), glm::dvec3(-1.0)) << "samples should sit on the cube's corners";
            }
            expectEqualFields(cpu, gpu);
        }
    }
}

// Where several triangles are equally near (a cube's corners and edges seen from samples on whole
// and half units, every distance exact in float), the distances are the CPU's bit for bit, and so
// are the pseudonormal signs, but for samples on the surface, which the device leaves to the CPU.
TEST_F(Gpu, WhereTrianglesTieDistancesAndSignsAreTheCpus) {
    const Mesh cube = test::box({1.0f, 1.0f, 1.0f});
    const Bvh tree(cube);
    const WideBvh wide(cube, tree);
    const MeshTopology topology(cube);
    PseudonormalSign sign;
    for (std::uint32_t t = 0; t < cube.triangleCount(); ++t) {
        for (int feature = 0; feature < 7; ++feature) sign.normals.push_back(topology.pseudonormal(t, TriangleFeature(feature)));
    }
    ComputeDevice* device = selectComputeDevice("gpu");
    ASSERT_NE(device, nullptr);
    for (int res : {5, 10}) {
        SCOPED_TRACE("res " + std::to_string(res));
        const Grid grid = makeGrid(cube.worldBounds(), res, 0.75);
        ASSERT_EQ(grid.voxel, 5.0 / res);
        const NearestField cpu = computeNearest(cube, tree, grid, {});
        std::vector<float> gpu;
        device->nearest(cube, grid, nullptr, {}, gpu);
        EXPECT_EQ(cpu.distance, gpu);
        std::vector<float> cpuSigned(grid.sampleCount()), gpuSigned;
        computeExactField(cube, wide, grid, &topology, false, cpuSigned.data(), {});
        device->nearest(cube, grid, &sign, {}, gpuSigned);
        std::size_t undecided = 0, different = 0, onSurface = 0;
        for (std::size_t i = 0; i < cpuSigned.size(); ++i) {
            onSurface += cpuSigned[i] == 0.0f;
            if (std::isnan(gpuSigned[i])) ++undecided;
            else different += std::memcmp(&cpuSigned[i], &gpuSigned[i], sizeof(float)) != 0;
        }
        EXPECT_EQ(different, 0u);
        EXPECT_EQ(undecided, onSurface);
        if (res == 5) {
            EXPECT_GT(onSurface, 0u);
        }
    }
}

// Where the winding number is ½ to within the GPU's float (just below the centre of an open box's
// missing face the other five faces fill half of all directions, and a hair more), the device
// leaves the sample to the CPU's exact refinement; and a bake's signs are the CPU's.
TEST_F(Gpu, LeavesWindingNumbersNearOneHalfToTheCpu) {
    const Mesh open = cutOpen(test::box({1.0f, 1.0f, 1.0f}), {0, 1, 0}, 0.9f);
    BakeSettings settings;
    settings.res = 5;
    settings.padding = 0.75f;
    settings.sign = SignMethod::Winding;
    settings.device = "cpu";
    const BakeResult cpu = test::bakeMesh(open, settings);
    settings.device = "gpu";
    expectEqualFields(cpu, test::bakeMesh(open, settings));

    const MeshTopology topology(open);
    const WindingCaps caps(topology);
    ASSERT_FALSE(caps.empty());
    std::vector<glm::dvec3> corners;
    std::vector<std::int32_t> weights;
    windingTriangles(open, caps, corners, weights);
    const WindingFans fans = caps.flattened();
    ComputeDevice* device = selectComputeDevice("gpu");
    ASSERT_NE(device, nullptr);
    // Two samples 2.5e-7 and 1.5e-7 below the centre of the missing face, and one far outside.
    Grid grid;
    grid.voxel = 1e-7;
    grid.origin = glm::dvec3(0.0, 1.0, 0.0) - glm::dvec3(0.5e-7, 3e-7, 0.5e-7);
    grid.dims = {1, 2, 1};
    std::vector<std::uint8_t> sides;
    const std::vector<std::int32_t> ahead = device->windingNumbers(open, corners, weights, &fans, grid, {}, sides);
    ASSERT_EQ(sides.size(), grid.sampleCount());
    for (int j = 0; j < 2; ++j) {
        const double w = caps.winding(localPosition(open, grid, 0, j, 0), ahead[grid.index(0, j, 0)]);
        EXPECT_NEAR(w, 0.5, 1e-5);
        EXPECT_NE(w, 0.5);
        EXPECT_EQ(sides[grid.index(0, j, 0)], 2) << "w - 1/2 = " << w - 0.5;
    }
    std::vector<std::uint8_t> farSides;
    Grid far = grid;
    far.origin = glm::dvec3(3.0, 3.0, 3.0);
    device->windingNumbers(open, corners, weights, &fans, far, {}, farSides);
    EXPECT_EQ(farSides, std::vector<std::uint8_t>(2, 0));
}

// The device decides |w| > 1/2 itself, on either side of zero: inside an inside-out sphere with a
// hole (w near -1) its sides say inside, outside (w near 0) outside, each the CPU's answer, and
// few samples are left to the CPU.
TEST_F(Gpu, DecidesInsideOutPartsByTheMagnitudeOfW) {
    const Mesh open = moved(cutOpen(test::icosphere(1.0f, 2), {0, 1, 0}, 0.8f), {0, 0, 0}, true);
    const MeshTopology topology(open);
    const WindingCaps caps(topology);
    ASSERT_FALSE(caps.empty());
    std::vector<glm::dvec3> corners;
    std::vector<std::int32_t> weights;
    windingTriangles(open, caps, corners, weights);
    const WindingFans fans = caps.flattened();
    ComputeDevice* device = selectComputeDevice("gpu");
    ASSERT_NE(device, nullptr);
    const Grid grid = makeGrid(open.worldBounds(), 16, 0.1);
    std::vector<std::uint8_t> sides;
    const std::vector<std::int32_t> ahead = device->windingNumbers(open, corners, weights, &fans, grid, {}, sides);
    std::size_t inside = 0, outside = 0, undecided = 0;
    for (int k = 0; k < grid.dims.z; ++k)
        for (int j = 0; j < grid.dims.y; ++j)
            for (int i = 0; i < grid.dims.x; ++i) {
                const std::size_t index = grid.index(i, j, k);
                if (sides[index] == 2) {
                    ++undecided;
                    continue;
                }
                const glm::dvec3 p = localPosition(open, grid, i, j, k);
                ASSERT_EQ(bool(sides[index]), caps.inside(p, ahead[index])) << i << "," << j << "," << k << ": w = " << caps.winding(p, ahead[index]);
                (sides[index] ? inside : outside) += 1;
                if (sides[index]) {
                    EXPECT_LT(caps.winding(p, ahead[index]), -0.5);
                }
            }
    EXPECT_GT(inside, grid.sampleCount() / 10);
    EXPECT_GT(outside, grid.sampleCount() / 10);
    EXPECT_LT(undecided, grid.sampleCount() / 100);
}

TEST_F(Gpu, IsDeterministic) {
    const Mesh bunny = loadObj(test::bundledBunnyPath());
    const BakeResult first = bakeOn(bunny, 24, "gpu", SignMethod::Winding);
    const BakeResult second = bakeOn(bunny, 24, "gpu", SignMethod::Winding);
    ASSERT_EQ(first.field.dense().values.size(), second.field.dense().values.size());
    EXPECT_EQ(std::memcmp(first.field.dense().values.data(), second.field.dense().values.data(), first.field.dense().values.size() * sizeof(float)), 0);
}

// Large grids go through in slabs with bounded buffers: a tiny budget (the test hook) makes this
// small grid take many, with the last one partly filled.
TEST_F(Gpu, StreamsSlabs) {
    const Mesh holed = cutOpen(test::torus(1.0f, 0.3f, 24, 12), {0, 0, 1}, 0.5f);
    const BakeResult cpu = bakeOn(holed, 18, "cpu", SignMethod::Winding);
    ASSERT_EQ(setenv("SDFGEN_GPU_SLAB_BYTES", "4000", 1), 0);
    std::unique_ptr<ComputeDevice> small = gpu::openGlDevice();
    unsetenv("SDFGEN_GPU_SLAB_BYTES");
    ComputeDevicePlugin slabbed = gpu::glDevicePlugin();
    slabbed.open = [&small] { return std::move(small); };
    registerComputeDevice(slabbed); // in the GL device's place, under its name
    const BakeResult gpu = bakeOn(holed, 18, "gpu", SignMethod::Winding);
    registerComputeDevice(gpu::glDevicePlugin());
    expectEqualFields(cpu, gpu);
}

// As in the viewer: a window's context current on the main thread, the bake on a worker thread
// (the device makes its own context current there and releases it), then drawing again.
TEST_F(Gpu, BakesOnAWorkerThreadBesideAnotherContext) {
    const std::unique_ptr<render::GlContext> window = render::createEglContext({16, 16});
    const Mesh sphere = cutOpen(test::icosphere(1.0f, 2), {0, 1, 0}, 0.8f);
    std::optional<BakeResult> gpu;
    std::thread worker([&] { gpu = bakeOn(sphere, 12, "gpu", SignMethod::Winding); });
    worker.join();
    ASSERT_TRUE(gpu.has_value());
    expectEqualFields(bakeOn(sphere, 12, "cpu", SignMethod::Winding), *gpu);
    window->makeCurrent();
    glClearColor(0.0f, 1.0f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    unsigned char pixel[4] = {0, 0, 0, 0};
    glReadPixels(0, 0, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, pixel);
    EXPECT_EQ(pixel[1], 255);
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

TEST_F(Gpu, Cancels) {
    const Mesh bunny = loadObj(test::bundledBunnyPath());
    std::atomic<bool> cancel{false};
    RunControl control;
    control.cancel = &cancel;
    double reported = 0;
    // Cancel at the first progress report: the next dispatch must not start.
    control.progress = [&](double fraction) {
        reported = fraction;
        cancel = true;
    };
    EXPECT_THROW(bakeOn(bunny, 48, "gpu", SignMethod::Winding, control), Cancelled);
    EXPECT_GT(reported, 0.0);
    EXPECT_LT(reported, 0.5);
}

TEST_F(Gpu, RefusesMethodsItDoesNotRun) {
    BakeSettings settings;
    settings.res = 8;
    settings.method = DistanceMethod::Rays;
    settings.device = "gpu";
    const std::string message = test::errorFrom([&] { test::bakeMesh(test::box({1, 1, 1}), settings); });
    EXPECT_NE(message.find("device gpu computes exact distances; method rays runs on the CPU"), std::string::npos) << message;
}

// Under MESA_GL_VERSION_OVERRIDE=3.3 (its own ctest): no 4.5 context, a clear error for gpu, the CPU for auto.
TEST(GpuBadContext, ClearErrorAndAutoFallsBack) {
    const char* override = std::getenv("MESA_GL_VERSION_OVERRIDE");
    ASSERT_TRUE(override && std::string(override) == "3.3") << "run with MESA_GL_VERSION_OVERRIDE=3.3";
    const std::string message = test::errorFrom([] { gpu::openGlDevice(); });
    EXPECT_NE(message.find("4.5"), std::string::npos) << message;
    gpu::registerDevices();
    const Mesh sphere = test::icosphere(1.0f, 1);
    const std::string gpuMessage = test::errorFrom([&] { bakeOn(sphere, 8, "gpu", SignMethod::Winding); });
    EXPECT_NE(gpuMessage.find("device gpu: "), std::string::npos) << gpuMessage;
    const BakeResult automatic = bakeOn(sphere, 8, "auto", SignMethod::Winding);
    EXPECT_FALSE(automatic.onDevice);
    EXPECT_NE(automatic.deviceReason.find("cpu"), std::string::npos) << automatic.deviceReason;
    EXPECT_EQ(automatic.field.dense().values.size(), 8u * 8u * 8u);
}

} // namespace
} // namespace sdfgen
