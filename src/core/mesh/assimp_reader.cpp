// Assimp in libsdfgen_assimp.so, opened on first use (loadMesh in mesh_formats.cpp uses it for the
// formats sdfgen has no reader of its own for).
#include "core/mesh/assimp_reader.hpp"
#include "core/runtime/plugin.hpp"
#include "sdfgen/error.hpp"

#include <mutex>

namespace sdfgen {

const AssimpPlugin& assimpPlugin() {
    // Kept once opened; a failure is reported again by the next call, which tries again.
    static std::mutex mutex;
    static const AssimpPlugin* plugin = nullptr;
    const std::lock_guard<std::mutex> lock(mutex);
    if (!plugin) plugin = reinterpret_cast<AssimpPluginEntry>(openPlugin("libsdfgen_assimp.so", kAssimpPluginEntry, "Assimp support"))();
    return *plugin;
}

} // namespace sdfgen
