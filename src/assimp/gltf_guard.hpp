#pragma once
// Checks of a glTF 2.0 file (.gltf, or .glb binary) before Assimp reads it: Assimp runs in our
// process, trusts what the file declares and recurses into what it nests, so a hostile file would
// crash, hang or exhaust memory there.
#include <cstdint>
#include <map>
#include <memory>
#include <string>

namespace sdfgen {

// A regular file opened once and read at offsets: the guard checks an external buffer through it,
// and Assimp then reads the same open file, so that a file swapped in after the check is not read.
class RandomAccessFile {
public:
    // `name` starts every error message.
    RandomAccessFile(const std::string& path, const std::string& name);
    ~RandomAccessFile();
    RandomAccessFile(const RandomAccessFile&) = delete;
    RandomAccessFile& operator=(const RandomAccessFile&) = delete;

    std::uint64_t size() const { return size_; }
    // Throws Error("NAME: ...") when [offset, offset + length) is not in the file.
    std::string read(std::uint64_t offset, std::uint64_t length) const;
    // The bytes read, fewer than `length` only at the end of the file.
    std::size_t readSome(std::uint64_t offset, void* into, std::size_t length) const;
    // Where the open file is, symbolic links resolved (as opened, not as named).
    std::string realPath() const;

private:
    std::string name_;
    int fd_ = -1;
    std::uint64_t size_ = 0;
};

// The folders a glTF's external files may be in besides its own: SDFGEN_GLTF_FOLDERS, a list
// separated by ':' (each with its subfolders).
constexpr const char* kGltfFoldersVariable = "SDFGEN_GLTF_FOLDERS";

struct GltfCheck {
    // What Assimp should read in place of the file: empty for the file itself, else the same file
    // with every external buffer's byteLength lowered to the bytes its views use (Assimp reads a
    // buffer's whole byteLength).
    std::string replacement;
    // The external buffer files, by the path Assimp opens each under (the glTF's folder, then the
    // URI), opened and confined by the guard: Assimp may open these and no other file.
    std::map<std::string, std::shared_ptr<const RandomAccessFile>> externalFiles;
    // The triangles the scene Assimp reads instances (a node used twice counts twice), when the
    // file has that scene (`counted`): what Assimp's result is compared with.
    bool counted = false;
    std::uint64_t triangles = 0;
};

// Checks `path` (a GLB container when `binary`) before Assimp reads it. Throws Error("PATH:
// problem") for: an external buffer or image whose URI is absolute, or leads (through '..' or
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
GltfCheck guardGltf(const std::string& path, bool binary);

} // namespace sdfgen
