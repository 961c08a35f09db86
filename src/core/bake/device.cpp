#include "sdfgen/device.hpp"
#include "sdfgen/error.hpp"

#include <mutex>

namespace sdfgen {

namespace {

// Where a bake may run, as front ends list it.
const std::vector<Choice<Device>>& devices() {
    static const std::vector<Choice<Device>> table = {
        {Device::Cpu, "cpu", "the CPU"},
        {Device::Gpu, "gpu", "OpenGL 4.5 compute, on Mesa's llvmpipe too; an error when it cannot start"},
        {Device::Auto, "auto", "the GPU when a hardware OpenGL 4.5 driver is there, else the CPU"},
    };
    return table;
}

} // namespace

const char* toString(Device device) {
    for (const Choice<Device>& choice : devices()) {
        if (choice.id == device) return choice.name;
    }
    return "?";
}

std::vector<Choice<Device>> deviceChoices() { return devices(); }

Device parseDevice(const std::string& name) { return parseChoice(devices(), name, "device"); }

namespace {

struct Registry {
    std::mutex mutex;
    std::function<std::unique_ptr<ComputeDevice>()> open;
    std::function<bool()> mayBeHardware;
    std::unique_ptr<ComputeDevice> device;
    std::string failure; // why opening failed, remembered so that it is tried once
};

// Never destroyed: a device's driver (EGL) tears itself down at exit before function statics
// would be, so the device is left to the operating system.
Registry& registry() {
    static Registry* instance = new Registry;
    return *instance;
}

} // namespace

void registerComputeDevice(std::function<std::unique_ptr<ComputeDevice>()> open, std::function<bool()> mayBeHardware) {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    r.open = std::move(open);
    r.mayBeHardware = std::move(mayBeHardware);
    r.device.reset();
    r.failure.clear();
}

ComputeDevice* selectComputeDevice(Device device, std::string* why) {
    auto say = [&](const std::string& reason) {
        if (why) *why = reason;
    };
    if (device == Device::Cpu) {
        say("cpu: asked for");
        return nullptr;
    }
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    if (device == Device::Auto && !r.device && r.open && r.mayBeHardware && !r.mayBeHardware()) {
        say("cpu: no GPU hardware found");
        return nullptr;
    }
    if (!r.device && r.failure.empty()) {
        if (!r.open) {
            r.failure = "this program was built without a GPU device";
        } else {
            try {
                r.device = r.open();
            } catch (const Error& e) {
                r.failure = e.what();
            }
        }
    }
    if (!r.device) {
        if (device == Device::Gpu) throw Error("device gpu: " + r.failure);
        say("cpu: no GPU (" + r.failure + ")");
        return nullptr;
    }
    if (device == Device::Auto && !r.device->hardware()) {
        say("cpu: the only OpenGL 4.5 driver runs on the CPU (" + r.device->description() + ")");
        return nullptr;
    }
    say("gpu: " + r.device->description());
    return r.device.get();
}

} // namespace sdfgen
