// The core's compute-device registry (sdfgen/device.hpp) without OpenGL: which device a bake
// picks among several registered by name, and that a bake on a device uses its distances and
// winding numbers (with the holes' fractional part still added on the CPU). The devices here are
// stand-ins that answer on the CPU (support/stand_in_device.hpp); the GPU device is tested in tests/gpu.
#include "sdfgen/device.hpp"
#include "support/checks.hpp"
#include "support/shapes.hpp"
#include "support/stand_in_device.hpp"

#include <gtest/gtest.h>
#include <memory>
#include <string>
#include <vector>

namespace sdfgen {
namespace {

BakeResult bakeOn(const Mesh& mesh, const std::string& device, SignMethod sign) {
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

std::vector<std::string> deviceNames() {
    std::vector<std::string> names;
    for (const Choice<std::string>& choice : deviceChoices()) names.push_back(choice.name);
    return names;
}

TEST(DeviceRegistry, ChoosesWhereTheBakeRuns) {
    std::string why;
    EXPECT_EQ(selectComputeDevice("cpu", &why), nullptr);
    EXPECT_EQ(why, "cpu: asked for");
    EXPECT_EQ(selectComputeDevice("auto", &why), nullptr);
    EXPECT_EQ(why, "cpu: no GPU (this program was built without a GPU device)");
    EXPECT_EQ(test::errorFrom([] { selectComputeDevice("gpu"); }),
              "unknown device 'gpu'; known: cpu (the CPU) or auto (the CPU: this program has no compute device)");
    {
        ComputeDevicePlugin failing = test::standInDevice("stand-in", true);
        failing.open = []() -> std::unique_ptr<ComputeDevice> { throw Error("no context today"); };
        const test::ScopedDevice registered(failing);
        EXPECT_EQ(selectComputeDevice("auto", &why), nullptr);
        EXPECT_EQ(why, "cpu: no GPU (no context today)");
        EXPECT_EQ(test::errorFrom([] { selectComputeDevice("stand-in"); }), "device stand-in: no context today");
    }
    {
        const test::ScopedDevice software(test::standInDevice("stand-in", false));
        EXPECT_EQ(selectComputeDevice("auto", &why), nullptr) << "a software device is not taken by auto";
        EXPECT_EQ(why, "cpu: the only stand-in driver runs on the CPU (stand-in)");
        EXPECT_NE(selectComputeDevice("Stand-In", &why), nullptr) << "a name in any case";
        EXPECT_EQ(why, "stand-in: stand-in");
    }
    {
        // A probe that finds no hardware spares opening anything.
        bool opened = false;
        ComputeDevicePlugin probed = test::standInDevice("stand-in", true);
        probed.open = [&opened]() -> std::unique_ptr<ComputeDevice> {
            opened = true;
            return std::make_unique<test::StandInDevice>(true, nullptr);
        };
        probed.mayBeHardware = [] { return false; };
        const test::ScopedDevice registered(probed);
        EXPECT_EQ(selectComputeDevice("auto", &why), nullptr);
        EXPECT_EQ(why, "cpu: no GPU hardware found");
        EXPECT_FALSE(opened);
    }
    const test::ScopedDevice hardware(test::standInDevice("stand-in", true));
    EXPECT_NE(selectComputeDevice("auto", &why), nullptr);
    EXPECT_EQ(why, "stand-in: stand-in");
    EXPECT_EQ(deviceNames(), (std::vector<std::string>{"cpu", "stand-in", "auto"}));
}

// Devices coexist by name: listed between cpu and auto in the order registered, each chosen by its
// name; auto takes the first on hardware, or says why it passed over each.
TEST(DeviceRegistry, SeveralDevicesCoexistByName) {
    const test::ScopedDevice software(test::standInDevice("software", false));
    const test::ScopedDevice first(test::standInDevice("first", true));
    const test::ScopedDevice second(test::standInDevice("second", true));
    EXPECT_EQ(deviceNames(), (std::vector<std::string>{"cpu", "software", "first", "second", "auto"}));
    EXPECT_EQ(parseDevice("SECOND"), "second");
    ComputeDevice* chosen[3] = {selectComputeDevice("software"), selectComputeDevice("first"), selectComputeDevice("second")};
    for (ComputeDevice* device : chosen) EXPECT_NE(device, nullptr);
    EXPECT_NE(chosen[0], chosen[1]);
    EXPECT_NE(chosen[1], chosen[2]);
    std::string why;
    EXPECT_EQ(selectComputeDevice("auto", &why), chosen[1]);
    EXPECT_EQ(why, "first: stand-in");
    // Registered again under its name, a device is replaced in its place.
    registerComputeDevice(test::standInDevice("first", false));
    EXPECT_EQ(deviceNames(), (std::vector<std::string>{"cpu", "software", "first", "second", "auto"}));
    EXPECT_NE(selectComputeDevice("auto", &why), nullptr);
    EXPECT_EQ(why, "second: stand-in");
    unregisterComputeDevice("second");
    EXPECT_EQ(selectComputeDevice("auto", &why), nullptr);
    EXPECT_EQ(why, "cpu: device software: the only stand-in driver runs on the CPU (stand-in); "
                   "device first: the only stand-in driver runs on the CPU (stand-in)");
    EXPECT_EQ(deviceChoices().back().description, std::string("the GPU when a hardware stand-in driver or stand-in driver is there, else the CPU"));
    // The core's own choices are not a device's to take, and a device needs its name, texts and opener.
    EXPECT_CONTAINS(test::errorFrom([] { registerComputeDevice(test::standInDevice("auto", true)); }), "cannot be named auto");
    ComputeDevicePlugin unopenable = test::standInDevice("x", true);
    unopenable.open = nullptr;
    EXPECT_CONTAINS(test::errorFrom([&] { registerComputeDevice(unopenable); }), "a way to open it");
}

// A bake on the device uses its answers, and gives the CPU's field: pseudonormal signed by the
// device (the samples it leaves undecided by the CPU), and winding from its integers plus the
// fans' part near the hole.
TEST(DeviceRegistry, BakesWithTheDevicesAnswers) {
    int calls = 0;
    const test::ScopedDevice registered(test::standInDevice("stand-in", true, &calls));
    for (const Mesh& mesh : {test::icosphere(1.0f, 2), holedSphere()}) {
        for (SignMethod sign : {SignMethod::Auto, SignMethod::Winding}) {
            SCOPED_TRACE(mesh.source + ", sign " + toString(sign));
            const BakeResult cpu = bakeOn(mesh, "cpu", sign);
            const int before = calls;
            const BakeResult device = bakeOn(mesh, "stand-in", sign);
            EXPECT_TRUE(device.onDevice);
            EXPECT_FALSE(cpu.onDevice);
            EXPECT_EQ(calls - before, device.sign == SignMethod::Winding ? 2 : 1);
            EXPECT_EQ(cpu.sign, device.sign);
            EXPECT_EQ(cpu.field.dense().values, device.field.dense().values);
        }
    }
    // Other methods stay on the CPU: refused for a device named, quietly for auto.
    BakeSettings settings;
    settings.res = 8;
    settings.method = DistanceMethod::Rays;
    settings.device = "stand-in";
    EXPECT_EQ(test::errorFrom([&] { test::bakeMesh(test::box({1, 1, 1}), settings); }),
              "device stand-in computes exact distances; method rays runs on the CPU");
    settings.device = "auto";
    EXPECT_FALSE(test::bakeMesh(test::box({1, 1, 1}), settings).onDevice);
}

} // namespace
} // namespace sdfgen
