// loadMesh: the formats sdfgen reads itself (the table below), every other one through Assimp
// (core/mesh/assimp_reader.hpp); then what every reader's result is checked for.
#include "core/mesh/assimp_reader.hpp"
#include "core/mesh/mesh_readers.hpp"
#include "sdfgen/error.hpp"
#include "core/runtime/out_of_memory.hpp"
#include "core/runtime/file_extension.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <unistd.h>
#include <vector>

namespace sdfgen {

namespace {

struct MeshReader {
    const char* extension; // lower case, with its dot
    Mesh (*load)(const std::string& path);
};

const MeshReader kMeshReaders[] = {
    {".obj", loadObj},
    {".ply", loadPly},
    {".off", loadOff},
    {".stl", loadStl},
};

// Vertices that no triangle uses are harmless to the field, but many of them usually mean that
// geometry the file holds was not read as triangles (points, lines, an element this reader skips).
void warnAboutUnusedVertices(Mesh& mesh) {
    std::vector<bool> used(mesh.positions.size());
    for (const glm::uvec3& t : mesh.triangles) used[t.x] = used[t.y] = used[t.z] = true;
    const std::size_t unused = std::size_t(std::count(used.begin(), used.end(), false));
    if (unused > 0 && unused * 100 >= mesh.positions.size()) {
        mesh.warnings.push_back(mesh.source + ": " + std::to_string(unused) + " of " + std::to_string(mesh.positions.size()) +
                                " vertices are used by no triangle");
    }
}

} // namespace

void checkDeclaredCount(const std::string& path, std::uint64_t count, const char* what, std::uint64_t bytesEach,
                        std::uint64_t available) {
    if (bytesEach == 0 || count <= available / bytesEach) return;
    const long double needed = static_cast<long double>(count) * bytesEach;
    char line[160];
    std::snprintf(line, sizeof line, ": the header declares %llu %s (at least %.4Lg bytes) but only %llu bytes follow it",
                  static_cast<unsigned long long>(count), what, needed, static_cast<unsigned long long>(available));
    throw Error(path + line);
}

void badVertexIndex(const std::string& where, std::int64_t index, std::uint64_t vertexCount) {
    throw Error(where + " refers to vertex " + std::to_string(index) + " but the file has " + std::to_string(vertexCount) +
                " vertices (counted from 0)");
}

std::string skippedFacesWarning(const std::string& path, std::uint64_t count) {
    if (count == 0) return {};
    return path + ": skipped " + std::to_string(count) + (count == 1 ? " face" : " faces") + " of fewer than 3 vertices";
}

std::vector<std::string> meshFormatExtensions() {
    std::vector<std::string> extensions;
    for (const MeshReader& reader : kMeshReaders) extensions.push_back(reader.extension);
    // The formats read through Assimp that sdfgen is tested with (Assimp reads more).
    for (const char* extension : {".gltf", ".glb", ".fbx", ".dae", ".3ds", ".3mf"}) extensions.push_back(extension);
    return extensions;
}

namespace {
Mesh readMesh(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw Error(path + ": is a directory, not a mesh file");
    std::string extension = lowerExtension(path);
    // Pipes and /dev/stdin have no extension: OBJ text. The readers report unreadable files
    // themselves, each reading the file once (opening a FIFO here first would swallow it).
    if (extension.empty()) extension = ".obj";
    Mesh mesh;
    const auto reader = std::find_if(std::begin(kMeshReaders), std::end(kMeshReaders),
                                     [&](const MeshReader& r) { return extension == r.extension; });
    if (reader != std::end(kMeshReaders)) {
        mesh = reader->load(path);
    } else {
        // Whether it can be read, without opening it (a FIFO opened here would be swallowed).
        if (access(path.c_str(), R_OK) != 0) throw Error(path + ": cannot open file (" + std::strerror(errno) + ")");
        if (!SDFGEN_HAS_ASSIMP) {
            std::string own;
            for (const MeshReader& r : kMeshReaders) own += (own.empty() ? "" : ", ") + std::string(r.extension);
            throw Error(path + ": mesh formats other than " + own + " need Assimp, and this sdfgen was built without Assimp "
                               "(configure with -DSDFGEN_ASSIMP=ON)");
        }
        const AssimpPlugin& assimp = assimpPlugin();
        if (!assimp.supports(extension)) {
            std::string known;
            for (const std::string& e : meshFormatExtensions()) known += e + ", ";
            throw Error(path + ": unknown mesh format '" + printable(extension, 40) + "'; known: " + known + "and the other formats Assimp reads");
        }
        mesh = assimp.load(path);
    }
    warnAboutUnusedVertices(mesh);
    return mesh;
}
} // namespace

Mesh loadMesh(const std::string& path) { return namingOutOfMemory(path, "reading it", [&] { return readMesh(path); }); }

} // namespace sdfgen
