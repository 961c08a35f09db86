#pragma once
// Mesh formats other than OBJ are read through Assimp, in libsdfgen_assimp.so (src/assimp/),
// opened on first use (core/runtime/plugin.hpp): Assimp and the libraries it pulls in (Draco, minizip)
// would otherwise cost every run, OBJ bakes included, about 4 MB of resident memory.
#include "sdfgen/mesh.hpp"

#include <string>

namespace sdfgen {

struct AssimpPlugin {
    // Whether Assimp reads files with this (lower-case, dotted) extension.
    bool (*supports)(const std::string& extension);
    // The file's every mesh, node transforms applied, as one Mesh (buildMesh); Error if unreadable.
    Mesh (*load)(const std::string& path);
};

constexpr const char* kAssimpPluginEntry = "sdfgen_assimp_plugin";
using AssimpPluginEntry = const AssimpPlugin* (*)();

// Opens the plugin on first use; throws Error (naming the library and why) when it cannot.
const AssimpPlugin& assimpPlugin();

} // namespace sdfgen
