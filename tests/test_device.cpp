// The core's compute-device hook (sdfgen/device.hpp) without OpenGL: which device a bake picks,
// and that a bake on a device uses its distances and winding numbers (with the holes' fractional
// part still added on the CPU). The device here is a stand-in that answers on the CPU, by brute
// force for the winding numbers; the real GPU device is tested in tests/gpu.
#include "core/distance/exact.hpp"
#include "core/mesh/geometry.hpp"
#include "core/mesh/sample_positions.hpp"
#include "sdfgen/device.hpp"
#include "support/checks.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>
#include <cmath>

namespace sdfgen {
namespace {

class StandInDevice final : public ComputeDevice {
public:
    StandInDevice(bool hardware, int* calls) : hardware_(hardware), calls_(calls) {}
    std::string description() const override { return "stand-in"; }
    std::string renderer() const override { return "stand-in"; }
    bool hardware() const override { return hardware_; }
    // Signed as the CPU signs, except every third sample left undecided (NaN) for the core to decide.
    void nearest(const Mesh& mesh, const Grid& grid, const PseudonormalSign* sign, const RunControl& control,
                 std::vector<float>& distance) override {
        ++*calls_;
        NearestField field = computeNearest(mesh, Bvh(mesh), grid, control);
        distance = std::move(field.distance);
        if (!sign) return;
        for (int k = 0; k < grid.dims.z; ++k) {
            for (int j = 0; j < grid.dims.y; ++j) {
                for (int i = 0; i < grid.dims.x; ++i) {
                    const std::size_t index = grid.index(i, j, k);
                    const std::uint32_t t = field.triangle[index];
                    const glm::dvec3 p = localPosition(mesh, grid, i, j, k);
                    const ClosestPoint q = closestPointOnTriangle(p, glm::dvec3(mesh.vertex(t, 0)), glm::dvec3(mesh.vertex(t, 1)),
                                                                  glm::dvec3(mesh.vertex(t, 2)));
                    const bool inside = (glm::dot(p - q.point, sign->normals[7 * t + int(q.feature)]) < 0.0) != sign->flipped;
                    if (inside) distance[index] = -distance[index];
                    if (index % 3 == 0) distance[index] = std::nanf("");
                }
            }
        }
    }
    // With fans: every other sample's side from w in double, the rest left undecided (2) for the core.
    std::vector<std::int32_t> windingNumbers(const Mesh& mesh, const std::vector<glm::dvec3>& corners, const std::vector<std::int32_t>& weights,
                                             const WindingFans* fans, const Grid& grid, const RunControl&,
                                             std::vector<std::uint8_t>& sides) override {
        ++*calls_;
        std::vector<std::int32_t> out(grid.sampleCount());
        if (fans) sides.assign(grid.sampleCount(), 2);
        for (int k = 0; k < grid.dims.z; ++k) {
            for (int j = 0; j < grid.dims.y; ++j) {
                for (int i = 0; i < grid.dims.x; ++i) {
                    const glm::dvec3 p = localPosition(mesh, grid, i, j, k);
                    double sum = 0;
                    for (std::size_t t = 0; 3 * t + 2 < corners.size(); ++t) {
                        sum += weights[t] * solidAngle(p, corners[3 * t], corners[3 * t + 1], corners[3 * t + 2]);
                    }
                    const std::size_t index = grid.index(i, j, k);
                    out[index] = std::int32_t(std::lround(sum / (4.0 * M_PI)));
                    if (!fans || index % 2 == 0) continue;
                    double w = out[index];
                    for (const WindingFans::Fan& fan : fans->fans) {
                        const glm::dvec3& centre = fans->points[fan.first];
                        for (std::uint32_t v = 0; v < fan.count; ++v) {
                            const glm::dvec3& a = fans->points[fan.first + 1 + (v + 1) % fan.count];
                            const glm::dvec3& b = fans->points[fan.first + 1 + v];
                            w -= fan.weight * solidAngle(p, a, b, centre) / (4.0 * M_PI);
                        }
                    }
                    sides[index] = std::fabs(w) > 0.5;
                }
            }
        }
        return out;
    }

private:
    bool hardware_;
    int* calls_;
};

BakeResult bakeOn(const Mesh& mesh, Device device, SignMethod sign) {
    BakeSettings settings;
    settings.res = 12;
    settings.sign = sign;
    settings.device = device;
    return test::bakeMesh(mesh, settings);
}

// The icosphere without its top cap: a hole, so the winding sign needs the fans' fractional part.
Mesh holedSphere() {
    const Mesh sphere = test::icosphere(1.0f, 2);
    std::vector<glm::uvec3> kept;
    for (std::size_t t = 0; t < sphere.triangleCount(); ++t) {
        if ((sphere.vertex(t, 0).y + sphere.vertex(t, 1).y + sphere.vertex(t, 2).y) / 3.0f <= 0.8f) kept.push_back(sphere.triangles[t]);
    }
    return buildMesh("holed sphere", sphere.positions, std::move(kept));
}

class DeviceHook : public ::testing::Test {
protected:
    void TearDown() override { registerComputeDevice({}); }
};

TEST_F(DeviceHook, ChoosesWhereTheBakeRuns) {
    registerComputeDevice({});
    std::string why;
    EXPECT_EQ(selectComputeDevice(Device::Cpu, &why), nullptr);
    EXPECT_EQ(selectComputeDevice(Device::Auto, &why), nullptr);
    EXPECT_CONTAINS(why, "built without a GPU device");
    EXPECT_CONTAINS(test::errorFrom([] { selectComputeDevice(Device::Gpu); }), "device gpu: this program was built without a GPU device");

    registerComputeDevice([]() -> std::unique_ptr<ComputeDevice> { throw Error("no context today"); });
    EXPECT_EQ(selectComputeDevice(Device::Auto, &why), nullptr);
    EXPECT_CONTAINS(why, "no context today");
    EXPECT_CONTAINS(test::errorFrom([] { selectComputeDevice(Device::Gpu); }), "no context today");

    int calls = 0;
    registerComputeDevice([&] { return std::make_unique<StandInDevice>(false, &calls); });
    EXPECT_EQ(selectComputeDevice(Device::Auto, &why), nullptr) << "a software device is not taken by auto";
    EXPECT_CONTAINS(why, "runs on the CPU");
    EXPECT_NE(selectComputeDevice(Device::Gpu), nullptr);
    // A probe that finds no hardware spares opening anything.
    bool opened = false;
    registerComputeDevice([&] { opened = true; return std::make_unique<StandInDevice>(true, &calls); }, [] { return false; });
    EXPECT_EQ(selectComputeDevice(Device::Auto, &why), nullptr);
    EXPECT_FALSE(opened);
    registerComputeDevice([&] { return std::make_unique<StandInDevice>(true, &calls); });
    EXPECT_NE(selectComputeDevice(Device::Auto, &why), nullptr);
    EXPECT_EQ(why, "gpu: stand-in");
}

// A bake on the device uses its answers, and gives the CPU's field: pseudonormal signed by the
// device (the samples it leaves undecided by the CPU), and winding from its integers plus the
// fans' part near the hole.
TEST_F(DeviceHook, BakesWithTheDevicesAnswers) {
    int calls = 0;
    registerComputeDevice([&] { return std::make_unique<StandInDevice>(true, &calls); });
    for (const Mesh& mesh : {test::icosphere(1.0f, 2), holedSphere()}) {
        for (SignMethod sign : {SignMethod::Auto, SignMethod::Winding}) {
            SCOPED_TRACE(mesh.source + ", sign " + toString(sign));
            const BakeResult cpu = bakeOn(mesh, Device::Cpu, sign);
            const int before = calls;
            const BakeResult device = bakeOn(mesh, Device::Gpu, sign);
            EXPECT_TRUE(device.onDevice);
            EXPECT_FALSE(cpu.onDevice);
            EXPECT_EQ(calls - before, device.sign == SignMethod::Winding ? 2 : 1);
            EXPECT_EQ(cpu.sign, device.sign);
            EXPECT_EQ(cpu.field.dense().values, device.field.dense().values);
        }
    }
    // Other methods stay on the CPU: refused for gpu, quietly for auto.
    BakeSettings settings;
    settings.res = 8;
    settings.method = DistanceMethod::Rays;
    settings.device = Device::Gpu;
    EXPECT_CONTAINS(test::errorFrom([&] { test::bakeMesh(test::box({1, 1, 1}), settings); }), "method rays runs on the CPU");
    settings.device = Device::Auto;
    EXPECT_FALSE(test::bakeMesh(test::box({1, 1, 1}), settings).onDevice);
}

} // namespace
} // namespace sdfgen
