// The compute devices a program registers, by name, and which one a bake runs on.
#include "sdfgen/device.hpp"
#include "sdfgen/error.hpp"

#include <algorithm>
#include <mutex>

namespace sdfgen {

namespace {

// A registered device, opened on first use and kept.
struct Entry {
    ComputeDevicePlugin plugin;
    std::unique_ptr<ComputeDevice> device;
    std::string failure; // why opening failed, remembered so that it is tried once
};

// Auto's description, naming what the registered devices run through.
std::string describeAuto(const std::vector<Entry>& entries) {
    if (entries.empty()) return "the CPU: this program has no compute device";
    std::string drivers;
    for (std::size_t i = 0; i < entries.size(); ++i) drivers += (i == 0 ? "" : " or ") + std::string(entries[i].plugin.driver);
    return "the GPU when a hardware " + drivers + " is there, else the CPU";
}

struct Registry {
    std::mutex mutex;
    std::vector<Entry> entries; // in the order registered: auto's preference
    std::string autoDescription = describeAuto({});
};

// Never destroyed: a device's driver (EGL) tears itself down at exit before function statics
// would be, so the devices are left to the operating system.
Registry& registry() {
    static Registry* instance = new Registry;
    return *instance;
}

// The choices, as deviceChoices() lists them (the registry's lock held).
std::vector<Choice<std::string>> choicesOf(const Registry& r) {
    std::vector<Choice<std::string>> choices = {{"cpu", "cpu", "the CPU"}};
    for (const Entry& entry : r.entries) choices.push_back({entry.plugin.name, entry.plugin.name, entry.plugin.description});
    choices.push_back({"auto", "auto", r.autoDescription.c_str()});
    return choices;
}

std::vector<Entry>::iterator find(std::vector<Entry>& entries, const std::string& name) {
    return std::find_if(entries.begin(), entries.end(), [&](const Entry& entry) { return name == entry.plugin.name; });
}

// The entry's device, opened on first use; null (with entry.failure) when it cannot open.
ComputeDevice* open(Entry& entry) {
    if (!entry.device && entry.failure.empty()) {
        try {
            entry.device = entry.plugin.open();
        } catch (const Error& e) {
            entry.failure = e.what();
        }
    }
    return entry.device.get();
}

// Why auto passes the entry's device over; empty when it takes it.
std::string whyNotAuto(Entry& entry) {
    if (!entry.device && entry.plugin.mayBeHardware && !entry.plugin.mayBeHardware()) return "no GPU hardware found";
    if (!open(entry)) return "no GPU (" + entry.failure + ")";
    if (!entry.device->hardware()) return std::string("the only ") + entry.plugin.driver + " runs on the CPU (" + entry.device->description() + ")";
    return "";
}

// Auto's choice: the first device on hardware, else the CPU with why each was passed over (named
// when there are several).
ComputeDevice* selectAuto(std::vector<Entry>& entries, std::string& why) {
    if (entries.empty()) {
        why = "cpu: no GPU (this program was built without a GPU device)";
        return nullptr;
    }
    std::string passedOver;
    for (Entry& entry : entries) {
        const std::string reason = whyNotAuto(entry);
        if (reason.empty()) {
            why = std::string(entry.plugin.name) + ": " + entry.device->description();
            return entry.device.get();
        }
        const std::string named = entries.size() > 1 ? "device " + std::string(entry.plugin.name) + ": " : "";
        passedOver += (passedOver.empty() ? "" : "; ") + named + reason;
    }
    why = "cpu: " + passedOver;
    return nullptr;
}

} // namespace

std::vector<Choice<std::string>> deviceChoices() {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    return choicesOf(r);
}

std::string parseDevice(const std::string& name) { return parseChoice(deviceChoices(), name, "device"); }

void registerComputeDevice(ComputeDevicePlugin plugin) {
    const std::string name = plugin.name ? plugin.name : "";
    if (name.empty() || !plugin.description || !plugin.driver || !plugin.open) {
        throw Error("a compute device needs a name, a description, a driver and a way to open it");
    }
    if (name == "cpu" || name == "auto") throw Error("a compute device cannot be named " + name + ": that choice is the core's");
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    const auto existing = find(r.entries, name);
    if (existing != r.entries.end()) {
        *existing = Entry{std::move(plugin), nullptr, {}};
    } else {
        r.entries.push_back(Entry{std::move(plugin), nullptr, {}});
    }
    r.autoDescription = describeAuto(r.entries);
}

void unregisterComputeDevice(const std::string& name) {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    const auto existing = find(r.entries, name);
    if (existing == r.entries.end()) return;
    r.entries.erase(existing);
    r.autoDescription = describeAuto(r.entries);
}

ComputeDevice* selectComputeDevice(const std::string& device, std::string* why) {
    std::string reason;
    ComputeDevice* chosen = nullptr;
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    const std::string name = parseChoice(choicesOf(r), device, "device");
    if (name == "cpu") {
        reason = "cpu: asked for";
    } else if (name == "auto") {
        chosen = selectAuto(r.entries, reason);
    } else {
        Entry& entry = *find(r.entries, name);
        chosen = open(entry);
        if (!chosen) throw Error("device " + name + ": " + entry.failure);
        reason = name + ": " + chosen->description();
    }
    if (why) *why = reason;
    return chosen;
}

} // namespace sdfgen
