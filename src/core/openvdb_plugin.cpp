#include "core/openvdb_plugin.hpp"
#include "core/formats/format.hpp"
#include "core/plugin.hpp"

#include <mutex>

namespace sdfgen {

const OpenVdbPlugin& openVdbPlugin() {
    // Kept once opened; a failure is reported again by the next call, which tries again.
    static std::mutex mutex;
    static const OpenVdbPlugin* plugin = nullptr;
    const std::lock_guard<std::mutex> lock(mutex);
    if (!plugin) {
        plugin = reinterpret_cast<OpenVdbPluginEntry>(openPlugin("libsdfgen_openvdb.so", kOpenVdbPluginEntry, "OpenVDB support"))();
    }
    return *plugin;
}

namespace formats {

void saveVdb(const Field& field, const std::string& path, const SaveOptions& options) { openVdbPlugin().save(field, path, options); }

Field loadVdb(const std::string& path) { return openVdbPlugin().load(path); }

} // namespace formats

} // namespace sdfgen
