#include "core/openvdb_plugin.hpp"
#include "core/formats/format.hpp"
#include "sdfgen/error.hpp"

#include <dlfcn.h>
#include <mutex>

namespace sdfgen {

namespace {

constexpr const char* kPluginName = "libsdfgen_openvdb.so";

const OpenVdbPlugin* openPlugin() {
    // Beside the object this code is in (libsdfgen.so, or the program that links the core), then
    // wherever the dynamic loader looks.
    std::string beside;
    Dl_info self{};
    if (dladdr(reinterpret_cast<void*>(&openPlugin), &self) != 0 && self.dli_fname) {
        const std::string where = self.dli_fname;
        const std::size_t slash = where.rfind('/');
        if (slash != std::string::npos) beside = where.substr(0, slash + 1) + kPluginName;
    }
    void* handle = beside.empty() ? nullptr : dlopen(beside.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) handle = dlopen(kPluginName, RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
        const char* why = dlerror();
        throw Error(std::string("OpenVDB support (") + kPluginName + ") cannot be loaded: " + (why ? why : "not found"));
    }
    const auto entry = reinterpret_cast<OpenVdbPluginEntry>(dlsym(handle, kOpenVdbPluginEntry));
    if (!entry) throw Error(std::string(kPluginName) + " has no entry point " + kOpenVdbPluginEntry);
    return entry();
}

} // namespace

const OpenVdbPlugin& openVdbPlugin() {
    // Kept once opened; a failure is reported again by the next call, which tries again.
    static std::mutex mutex;
    static const OpenVdbPlugin* plugin = nullptr;
    const std::lock_guard<std::mutex> lock(mutex);
    if (!plugin) plugin = openPlugin();
    return *plugin;
}

namespace formats {

void saveVdb(const Field& field, const std::string& path, const SaveOptions& options) { openVdbPlugin().save(field, path, options); }

Field loadVdb(const std::string& path) { return openVdbPlugin().load(path); }

} // namespace formats

} // namespace sdfgen
