// Mesh files sdfgen has no reader of its own for (glTF/GLB, FBX, DAE, 3DS, 3MF, ...) through
// Assimp; glTF files are checked first (gltf_guard.hpp). Node transforms are applied and every
// mesh of the scene is merged into one; Assimp only triangulates polygons and joins identical
// vertices, so no geometry is "repaired" or dropped behind the user's back (buildMesh drops and
// counts zero-area triangles, as for OBJ; points and lines are counted in a warning).
//
// The library the core opens on first use (core/mesh/assimp_reader.hpp), so that only runs that read
// such files load Assimp.
#include "gltf_guard.hpp"
#include "core/mesh/assimp_reader.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/mesh.hpp"
#include "core/io/file_extension.hpp"

#include <assimp/DefaultIOSystem.h>
#include <assimp/Importer.hpp>
#include <assimp/MemoryIOWrapper.h>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <glm/mat4x4.hpp>
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace sdfgen {

namespace {

glm::dmat4 toMatrix(const aiMatrix4x4& m) {
    // Assimp's matrices are row-major with the translation in the last column; glm is column-major.
    glm::dmat4 out;
    for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 4; ++c) out[c][r] = m[r][c];
    }
    return out;
}

// Appends every triangle of the scene's nodes, in world coordinates (a mesh that several nodes
// instance appears once per node); counts the faces that are points or lines. Without recursion:
// a file's node tree may be deeper than the stack.
void collect(const aiScene& scene, std::vector<glm::vec3>& positions, std::vector<glm::uvec3>& triangles,
             std::size_t& pointsAndLines) {
    std::vector<std::pair<const aiNode*, glm::dmat4>> stack{{scene.mRootNode, glm::dmat4(1.0)}};
    while (!stack.empty()) {
        const auto [node, parent] = stack.back();
        stack.pop_back();
        const glm::dmat4 transform = parent * toMatrix(node->mTransformation);
        for (unsigned m = 0; m < node->mNumMeshes; ++m) {
            const aiMesh& mesh = *scene.mMeshes[node->mMeshes[m]];
            const auto first = unsigned(positions.size());
            for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
                const aiVector3D& p = mesh.mVertices[v];
                positions.emplace_back(transform * glm::dvec4(p.x, p.y, p.z, 1.0));
            }
            for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
                const aiFace& face = mesh.mFaces[f];
                if (face.mNumIndices != 3) { // points and lines: not part of any surface
                    ++pointsAndLines;
                    continue;
                }
                triangles.emplace_back(first + face.mIndices[0], first + face.mIndices[1], first + face.mIndices[2]);
            }
        }
        // Children pushed last first, so that they are read in their order.
        for (unsigned c = node->mNumChildren; c-- > 0;) stack.emplace_back(node->mChildren[c], transform);
    }
}

// Assimp's file access, with one file read from memory instead (the guarded glTF).
class ReplacingIOSystem : public Assimp::DefaultIOSystem {
public:
    ReplacingIOSystem(std::string path, std::string contents) : path_(std::move(path)), contents_(std::move(contents)) {}

    Assimp::IOStream* Open(const char* file, const char* mode) override {
        if (file == path_) return new Assimp::MemoryIOStream(reinterpret_cast<const std::uint8_t*>(contents_.data()), contents_.size());
        return DefaultIOSystem::Open(file, mode);
    }

private:
    std::string path_;
    std::string contents_;
};

std::string firstLine(std::string text) {
    text = text.substr(0, text.find('\n'));
    while (!text.empty() && (text.back() == '\r' || text.back() == ' ')) text.pop_back();
    return text;
}

Mesh loadWithAssimp(const std::string& path) {
    Assimp::Importer importer;
    // Without normals, colours and texture coordinates, identical positions are identical
    // vertices, so an STL's per-face corners are joined into a connected mesh.
    importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS, aiComponent_NORMALS | aiComponent_TANGENTS_AND_BITANGENTS |
                                                            aiComponent_COLORS | aiComponent_TEXCOORDS |
                                                            aiComponent_BONEWEIGHTS);
    const std::string extension = lowerExtension(path);
    GltfCheck gltf;
    if (extension == ".gltf" || extension == ".glb") {
        gltf = guardGltf(path, extension == ".glb");
        if (!gltf.replacement.empty()) importer.SetIOHandler(new ReplacingIOSystem(path, std::move(gltf.replacement)));
    }
    const aiScene* scene = importer.ReadFile(path, aiProcess_RemoveComponent | aiProcess_Triangulate |
                                                       aiProcess_JoinIdenticalVertices | aiProcess_ValidateDataStructure);
    if (!scene) {
        const std::string problem = firstLine(importer.GetErrorString());
        throw Error(path + ": cannot read the file" + (problem.empty() ? "" : " (" + problem + ")"));
    }
    if ((scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !scene->mRootNode) throw Error(path + ": the file holds no complete scene");
    std::vector<glm::vec3> positions;
    std::vector<glm::uvec3> triangles;
    std::size_t pointsAndLines = 0;
    collect(*scene, positions, triangles, pointsAndLines);
    const std::size_t read = triangles.size();
    Mesh mesh = buildMesh(path, std::move(positions), std::move(triangles));
    if (gltf.counted && read != gltf.triangles) {
        mesh.warnings.push_back(path + ": Assimp read " + std::to_string(read) + " triangles where the file's scene has " +
                                std::to_string(gltf.triangles));
    }
    if (pointsAndLines) {
        mesh.warnings.push_back(path + ": skipped " + std::to_string(pointsAndLines) + " points and lines (only triangles and polygons make a surface)");
    }
    return mesh;
}

bool supports(const std::string& extension) { return Assimp::Importer().IsExtensionSupported(extension); }

} // namespace

} // namespace sdfgen

extern "C" __attribute__((visibility("default"))) const sdfgen::AssimpPlugin* sdfgen_assimp_plugin() {
    static const sdfgen::AssimpPlugin plugin{sdfgen::supports, sdfgen::loadWithAssimp};
    return &plugin;
}
