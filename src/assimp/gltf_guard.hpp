#pragma once
// Checks of a glTF 2.0 file (.gltf, or .glb binary) before Assimp reads it: Assimp runs in our
// process, trusts what the file declares and recurses into what it nests, so a hostile file would
// crash, hang or exhaust memory there.
#include <cstdint>
#include <map>
#include <string>

namespace sdfgen {

// The folders a glTF's external files may be in besides its own: SDFGEN_GLTF_FOLDERS, a list
// separated by ':' (each with its subfolders).
constexpr const char* kGltfFoldersVariable = "SDFGEN_GLTF_FOLDERS";

struct GltfCheck {
    // What Assimp reads in place of the file: the bytes checked, rewritten when needed (every
    // external buffer's byteLength lowered to the bytes its views use, as Assimp reads a buffer's
    // whole byteLength; a byte-order mark dropped).
    std::string bytes;
    // The external buffers as checked (as far as their views reach), by the path Assimp opens each
    // under (the glTF's folder, then the URI): Assimp may open these and no other file.
    std::map<std::string, std::string> externalFiles;
    // The triangles the scene Assimp reads instances (a node used twice counts twice), when the
    // file has that scene (`counted`): what Assimp's result is compared with.
    bool counted = false;
    std::uint64_t triangles = 0;
};

// Checks `bytes`, the whole file `path` as read once (a GLB container when `binary`), before
// Assimp reads it: what is checked is what Assimp is given, so a file changed or swapped after the
// check is not read. Throws Error("PATH: problem") for: an external buffer or image whose URI is absolute, or leads (through '..' or
// symbolic links) outside the glTF's folder and the SDFGEN_GLTF_FOLDERS ones; a GLB whose buffer
// 0 has a URI (Assimp reads the binary chunk in its place); a sparse index accessor; a sparse
// accessor on a strided view; a GLB header or chunk length that does not fit the file; JSON nested deeper than
// 200 levels or not valid; glTF other than 2.x; a buffer that declares more bytes than its data
// holds; a buffer view, accessor or sparse accessor's part outside what it refers to; an accessor
// without data larger than 64 times the bytes of the file and its buffers; integer positions
// (KHR_mesh_quantization, which Assimp would misread); a triangle index past
// its primitive's vertices; triangles whose vertex count is not a multiple of 3; node trees deeper
// than 1000, with cycles or references past the arrays; a scene whose instanced triangles would
// need more memory than is available.
GltfCheck guardGltf(const std::string& path, std::string bytes, bool binary);

} // namespace sdfgen
