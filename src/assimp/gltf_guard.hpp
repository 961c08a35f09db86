#pragma once
// Checks of a glTF 2.0 file (.gltf, or .glb binary) before Assimp reads it: Assimp runs in our
// process, trusts what the file declares and recurses into what it nests, so a hostile file would
// crash, hang or exhaust memory there.
#include <cstdint>
#include <string>

namespace sdfgen {

struct GltfCheck {
    // What Assimp should read in place of the file: empty for the file itself, else the same file
    // with every external buffer's byteLength lowered to the bytes its views use (Assimp reads a
    // buffer's whole byteLength).
    std::string replacement;
    // The triangles the scene Assimp reads instances (a node used twice counts twice), when the
    // file has that scene (`counted`): what Assimp's result is compared with.
    bool counted = false;
    std::uint64_t triangles = 0;
};

// Checks `path` (a GLB container when `binary`) before Assimp reads it. Throws Error("PATH:
// problem") for: a GLB header or chunk length that does not fit the file; JSON nested deeper than
// 200 levels or not valid; glTF other than 2.x; a buffer that declares more bytes than its data
// holds; a buffer view, accessor or sparse accessor's part outside what it refers to; an accessor
// without data larger than 64 times the bytes of the file and its buffers; integer positions
// (KHR_mesh_quantization, which Assimp would misread); a triangle index past
// its primitive's vertices; triangles whose vertex count is not a multiple of 3; node trees deeper
// than 1000, with cycles or references past the arrays; a scene whose instanced triangles would
// need more memory than is available.
GltfCheck guardGltf(const std::string& path, bool binary);

} // namespace sdfgen
