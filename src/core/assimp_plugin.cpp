// loadMesh: OBJ through tinyobjloader (mesh.cpp), every other format through Assimp in
// libsdfgen_assimp.so, opened on first use.
#include "core/assimp_plugin.hpp"
#include "core/plugin.hpp"
#include "sdfgen/error.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
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

Mesh loadMesh(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw Error(path + ": is a directory, not a mesh file");
    std::string extension = std::filesystem::path(path).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    // OBJ is read once by loadObj (which reports unreadable files itself): opening a FIFO or pipe
    // here first would swallow its contents. Pipes and /dev/stdin have no extension: OBJ text.
    if (extension == ".obj" || extension.empty()) return loadObj(path);
    if (!std::ifstream(path, std::ios::binary)) throw Error(path + ": cannot open file (" + std::strerror(errno) + ")");
    if (!SDFGEN_HAS_ASSIMP) {
        throw Error(path + ": mesh formats other than OBJ need Assimp, and this sdfgen was built without Assimp "
                           "(configure with -DSDFGEN_ASSIMP=ON)");
    }
    const AssimpPlugin& assimp = assimpPlugin();
    if (!assimp.supports(extension)) {
        throw Error(path + ": unknown mesh format '" + extension + "'" +
                    "; known: .obj, .stl, .ply, .off, .gltf, .glb, .fbx, .dae, .3ds, .3mf and the other formats Assimp reads");
    }
    return assimp.load(path);
}

} // namespace sdfgen
