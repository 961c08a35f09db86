// Mesh files sdfgen has no reader of its own for (glTF/GLB, FBX, DAE, 3DS, 3MF, ...) through
// Assimp; glTF files, by content whatever their names, are checked first (gltf_guard.hpp). Node transforms are applied and every
// mesh of the scene is merged into one; Assimp only triangulates polygons and joins identical
// vertices, so no geometry is "repaired" or dropped behind the user's back (buildMesh drops and
// counts zero-area triangles, as for OBJ; points and lines are counted in a warning).
//
// The library the core opens on first use (core/mesh/assimp_reader.hpp), so that only runs that read
// such files load Assimp.
#include "gltf_guard.hpp"
#include "core/mesh/assimp_reader.hpp"
#include "core/mesh/input_file.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/mesh.hpp"
#include "core/runtime/file_extension.hpp"
#include "core/runtime/printable.hpp"

#include <assimp/BaseImporter.h>
#include <assimp/IOSystem.hpp>
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
#include <map>
#include <memory>
#include <set>
#include <string_view>
#include <sys/stat.h>
#include <utility>
#include <vector>

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

// Assimp's file access: the file itself from the bytes read once (a file changed or swapped after
// sdfgen looked at it is not read) and, for a glTF, only the external buffers the guard checked,
// from the bytes it checked. No other file is opened. Importers open the files a model refers to
// through this: IRR (from Assimp 5.3) and MD3 scenes load them with a nested Importer that has
// every importer and no guard (a scene may refer to itself, endlessly); MD3, MD5, SMD, NFF, Unreal
// and Half-Life MDL files open skin, animation, material or data files. Names from the file may
// lead anywhere (/etc/passwd, ../outside.obj). The first of those files that exists is kept, and
// loadWithAssimp refuses the model naming it; names that do not exist are probes for optional files.
class ReadOnceIOSystem : public Assimp::IOSystem {
public:
    ReadOnceIOSystem(std::string path, std::string bytes) : path_(std::move(path)), bytes_(std::move(bytes)) {}
    ReadOnceIOSystem(std::string path, GltfCheck gltf)
        : path_(std::move(path)), bytes_(std::move(gltf.bytes)), gltfExternalFiles_(std::move(gltf.externalFiles)) {}

    bool Exists(const char* file) const override {
        if (file == path_) return !readingModel();
        return gltfExternalFiles_.count(file) != 0 || refuse(file);
    }
    Assimp::IOStream* Open(const char* file, const char* /*mode*/) override {
        if (file == path_) return new ModelStream(bytes_, openModelStreams_);
        const auto checked = gltfExternalFiles_.find(file);
        if (checked != gltfExternalFiles_.end()) return memoryStream(checked->second);
        refuse(file);
        return nullptr;
    }
    void Close(Assimp::IOStream* stream) override { delete stream; }
    char getOsSeparator() const override { return '/'; }

    // The first file other than the model (and a glTF's checked buffers) that an importer asked
    // for and that exists; `path` when the model asked for itself while being read. Empty if none.
    const std::string& refused() const { return refused_; }

private:
    // Counts itself among the model's open streams while it lives (importers delete streams
    // rather than closing them through the IOSystem).
    class ModelStream : public Assimp::MemoryIOStream {
    public:
        ModelStream(const std::string& bytes, int& open)
            : MemoryIOStream(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()), open_(open) {
            ++open_;
        }
        ~ModelStream() override { --open_; }

    private:
        int& open_;
    };

    static Assimp::IOStream* memoryStream(const std::string& bytes) {
        return new Assimp::MemoryIOStream(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    }
    // Whether the model's existence is asked while a stream of it is open: a nested Importer
    // (which asks before it opens) loading the file it is inside, as IRR and LWS hold their own
    // stream while theirs loads what they name. Open is not asked: X3D opens its file twice at once.
    bool readingModel() const {
        if (openModelStreams_ == 0) return false;
        if (refused_.empty()) refused_ = path_;
        return true;
    }
    // Returns false (the file is not there, for Assimp).
    bool refuse(const char* file) const {
        struct stat status {};
        if (refused_.empty() && stat(file, &status) == 0 && !S_ISDIR(status.st_mode)) refused_ = file;
        return false;
    }

    std::string path_, bytes_;
    std::map<std::string, std::string> gltfExternalFiles_;
    int openModelStreams_ = 0;
    mutable std::string refused_;
};

std::string firstLine(std::string text) {
    text = text.substr(0, text.find('\n'));
    while (!text.empty() && (text.back() == '\r' || text.back() == ' ')) text.pop_back();
    return text;
}

// Whether Assimp may read the file as glTF, and as which kind: Assimp picks its importer by the
// name's extension, but by content when no importer or several claim the extension (a glTF named
// .xml is read as glTF, its buffers opened wherever its URIs lead). So the guard runs by content
// too: a GLB by its magic, JSON by its first character after a byte-order mark and white space
// (no other format Assimp reads starts with '{').
enum class GltfKind { None, Json, Binary };
GltfKind gltfKind(std::string_view bytes, const std::string& extension) {
    if (extension == ".gltf") return GltfKind::Json;
    if (extension == ".glb") return GltfKind::Binary;
    const std::string_view start = bytes.substr(0, 256);
    if (start.substr(0, 4) == "glTF") return GltfKind::Binary;
    std::size_t first = start.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;
    while (first < start.size() && std::strchr(" \t\r\n", start[first]) && start[first] != '\0') ++first;
    return first < start.size() && start[first] == '{' ? GltfKind::Json : GltfKind::None;
}

// Assimp picks an importer by the name's extension, but when none of the importers claiming it
// takes the file (a .xml), by content among all of them: a file named .xml reached importers no
// name would (its OFF importer allocated 46 GB for an OFF claiming 4.6e11 vertices, its OpenGEX
// parser read past its buffer). So only the importers claiming the name's extension stay, and
// the glTF ones for a file the glTF guard checked.
void keepOnlyImportersFor(Assimp::Importer& importer, const std::string& path, bool gltf) {
    std::string name = path;
    std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    auto endsWith = [&](const std::string& tail) { return name.size() >= tail.size() && name.compare(name.size() - tail.size(), tail.size(), tail) == 0; };
    std::vector<Assimp::BaseImporter*> others;
    for (std::size_t i = 0; i < importer.GetImporterCount(); ++i) {
        Assimp::BaseImporter* candidate = importer.GetImporter(i);
        std::set<std::string> extensions; // lower case, without the dot; some with dots inside (mesh.xml)
        candidate->GetExtensionList(extensions);
        const bool keep = extensions.count("mesh.xml") == 0 && // Ogre's: see loadWithAssimp
                          std::any_of(extensions.begin(), extensions.end(), [&](const std::string& extension) {
                              return endsWith("." + extension) || (gltf && (extension == "gltf" || extension == "glb"));
                          });
        if (!keep) others.push_back(candidate);
    }
    for (Assimp::BaseImporter* other : others) {
        if (importer.UnregisterLoader(other) == aiReturn_SUCCESS) delete other; // unregistered, it is ours to free
    }
}

Mesh loadWithAssimp(const std::string& path) {
    Assimp::Importer importer;
    // Without normals, colours and texture coordinates, identical positions are identical
    // vertices, so an STL's per-face corners are joined into a connected mesh.
    importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS, aiComponent_NORMALS | aiComponent_TANGENTS_AND_BITANGENTS |
                                                            aiComponent_COLORS | aiComponent_TEXCOORDS |
                                                            aiComponent_BONEWEIGHTS);
    const std::string extension = lowerExtension(path);
    // A LightWave scene's objects are all in other files, which are not read, so it can give no
    // mesh; and Assimp 5.2's scene importer aborts the process on an object named by an empty
    // string (an assertion in BatchLoader::AddLoadRequest).
    if (extension == ".lws" || extension == ".mot") {
        throw Error(path + ": a LightWave scene holds no geometry of its own, only objects it loads from other files, which sdfgen does not read (bake its .lwo objects)");
    }
    bool gltfCounted = false;
    std::uint64_t gltfTriangles = 0;
    // Read once: what is told apart as glTF or not, and checked, is what Assimp reads.
    std::string bytes = readInputFile(path, InputKind::Binary);
    ReadOnceIOSystem* files = nullptr;
    if (const GltfKind kind = gltfKind(bytes, extension); kind != GltfKind::None) {
        GltfCheck gltf = guardGltf(path, std::move(bytes), kind == GltfKind::Binary);
        gltfCounted = gltf.counted;
        gltfTriangles = gltf.triangles;
        files = new ReadOnceIOSystem(path, std::move(gltf));
        keepOnlyImportersFor(importer, path, true);
    } else {
        // Assimp 5.2's Ogre importer dereferences a null pointer for a submesh without vertices
        // (one flipped byte of a valid file), and reads skeleton and material files named anywhere.
        if (extension == ".mesh" || (extension == ".xml" && lowerExtension(path.substr(0, path.size() - 4)) == ".mesh")) {
            throw Error(path + ": Ogre meshes are not read (Assimp's Ogre importer crashes on a submesh without vertices)");
        }
        files = new ReadOnceIOSystem(path, std::move(bytes));
        keepOnlyImportersFor(importer, path, false);
    }
    importer.SetIOHandler(files); // the importer's from now on
    const aiScene* scene = importer.ReadFile(path, aiProcess_RemoveComponent | aiProcess_Triangulate |
                                                       aiProcess_JoinIdenticalVertices | aiProcess_ValidateDataStructure);
    if (const std::string& other = files->refused(); other == path) {
        throw Error(path + ": refers to itself as a file to load, which sdfgen does not read");
    } else if (!other.empty()) {
        throw Error(path + ": refers to another file, '" + printable(other, 300) +
                    "', which sdfgen does not read (a mesh read through Assimp must be one file; a glTF's buffers excepted)");
    }
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
    if (gltfCounted && read != gltfTriangles) {
        // Dropped triangles are a wrong field, not a detail: the guard missed something Assimp did.
        throw Error(path + ": Assimp read " + std::to_string(read) + " triangles where the file's scene has " + std::to_string(gltfTriangles));
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
