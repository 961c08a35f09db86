#include "gltf_guard.hpp"
#include "core/mesh/input_file.hpp"
#include "core/runtime/memory.hpp"
#include "core/mesh/mesh_readers.hpp"
#include "sdfgen/error.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <limits>
#include <memory>
#include <sys/stat.h>
#include <unistd.h>
#include <utility>

namespace sdfgen {

namespace {

// A regular file opened once and read at offsets: an external buffer is confined by where the
// opened file is, then read through it.
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
    // Where the open file is, symbolic links resolved (as opened, not as named).
    std::string realPath() const;

private:
    // The bytes read, fewer than `length` only at the end of the file.
    std::size_t readSome(std::uint64_t offset, void* into, std::size_t length) const;

    std::string name_;
    int fd_ = -1;
    std::uint64_t size_ = 0;
};

RandomAccessFile::RandomAccessFile(const std::string& path, const std::string& name) : name_(name) {
    fd_ = open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK); // a FIFO must not block
    if (fd_ < 0) throw Error(name + ": cannot open file (" + std::strerror(errno) + ")");
    struct stat status {};
    if (fstat(fd_, &status) != 0 || !S_ISREG(status.st_mode)) {
        close(fd_);
        throw Error(name + ": not a regular file");
    }
    size_ = std::uint64_t(status.st_size);
}

RandomAccessFile::~RandomAccessFile() { close(fd_); }

std::string RandomAccessFile::read(std::uint64_t offset, std::uint64_t length) const {
    if (offset > size_ || length > size_ - offset) throw Error(name_ + ": the file ends before byte " + std::to_string(offset + length));
    std::string bytes(std::size_t(length), '\0');
    if (readSome(offset, bytes.data(), bytes.size()) != bytes.size()) throw Error(name_ + ": the file ends before byte " + std::to_string(offset + length));
    return bytes;
}

std::size_t RandomAccessFile::readSome(std::uint64_t offset, void* into, std::size_t length) const {
    std::size_t done = 0;
    while (done < length) {
        const ssize_t n = pread(fd_, static_cast<char*>(into) + done, length - done, off_t(offset + done));
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) throw Error(name_ + ": read error (" + std::strerror(errno) + ")");
        if (n == 0) break;
        done += std::size_t(n);
    }
    return done;
}

std::string RandomAccessFile::realPath() const {
    std::error_code error;
    const std::filesystem::path opened = std::filesystem::read_symlink("/proc/self/fd/" + std::to_string(fd_), error);
    if (error) throw Error(name_ + ": cannot tell where the opened file is (" + error.message() + ")");
    return opened.string();
}

using nlohmann::json;

constexpr int kMaxJsonDepth = 200;  // real files nest about 10 deep; Assimp's JSON parser recurses
constexpr int kMaxNodeDepth = 1000; // Assimp recurses once per level of the node tree
constexpr std::uint64_t kNoData = std::numeric_limits<std::uint64_t>::max();

std::uint32_t littleEndian32(const std::string& bytes, std::size_t at) {
    std::uint32_t v = 0;
    std::memcpy(&v, bytes.data() + at, 4); // little-endian hosts only (x86, ARM Linux)
    return v;
}

// The deepest nesting of arrays and objects in JSON text (strings skipped), or kMaxJsonDepth + 1.
int jsonDepth(std::string_view text) {
    int depth = 0, deepest = 0;
    bool inString = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (inString) {
            if (c == '\\') ++i;
            else if (c == '"') inString = false;
        } else if (c == '"') {
            inString = true;
        } else if (c == '[' || c == '{') {
            deepest = std::max(deepest, ++depth);
            if (deepest > kMaxJsonDepth) return deepest;
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
    return deepest;
}

std::size_t base64Value(char c) {
    if (c >= 'A' && c <= 'Z') return std::size_t(c - 'A');
    if (c >= 'a' && c <= 'z') return std::size_t(c - 'a' + 26);
    if (c >= '0' && c <= '9') return std::size_t(c - '0' + 52);
    if (c == '+' || c == '-') return 62;
    if (c == '/' || c == '_') return 63;
    return 64;
}

std::string decodeBase64(std::string_view text) {
    std::string out;
    out.reserve(text.size() / 4 * 3);
    std::uint32_t bits = 0;
    int count = 0;
    for (const char c : text) {
        const std::size_t v = base64Value(c);
        if (v == 64) continue; // padding (and anything else Assimp's decoder passes over)
        bits = (bits << 6) | std::uint32_t(v);
        if (++count == 4) {
            out += char(bits >> 16);
            out += char(bits >> 8);
            out += char(bits);
            bits = 0;
            count = 0;
        }
    }
    if (count == 2) out += char(bits >> 4);
    if (count == 3) {
        out += char(bits >> 10);
        out += char(bits >> 2);
    }
    return out;
}

class GltfGuard {
public:
    GltfGuard(const std::string& path, std::string bytes, bool binary) : path_(path), file_(std::move(bytes)) {
        if (binary) readContainer();
        else {
            json_ = file_;
            // Skipped, and Assimp (which would refuse it) reads the JSON without it.
            if (withoutByteOrderMark(json_).size() != json_.size()) {
                json_.erase(0, 3);
                byteOrderMark_ = true;
            }
        }
    }

    GltfCheck check() {
        if (jsonDepth(json_) > kMaxJsonDepth) fail("its JSON nests deeper than " + std::to_string(kMaxJsonDepth) + " levels");
        try {
            doc_ = json::parse(json_);
        } catch (const json::exception& e) {
            fail("not valid JSON (" + printable(e.what(), 160) + ")");
        }
        if (!doc_.is_object()) fail("its JSON is not an object");
        const json* asset = member(doc_, "asset");
        const json* version = asset && asset->is_object() ? member(*asset, "version") : nullptr;
        if (!version || !version->is_string() || version->get<std::string>().rfind("2.", 0) != 0) {
            fail("only glTF 2.x files are read (asset.version is not 2.x)");
        }
        checkBuffers();
        checkImages();
        checkBufferViews();
        checkAccessors();
        checkMeshes();
        checkNodes();
        result_.bytes = bounded_ || byteOrderMark_ ? rewritten() : std::move(file_);
        return std::move(result_);
    }

private:
    [[noreturn]] void fail(const std::string& problem) const { throw Error(path_ + ": " + problem); }

    static const json* member(const json& object, const char* key) {
        const auto it = object.find(key);
        return it == object.end() ? nullptr : &*it;
    }

    const json& array(const char* key) const {
        static const json empty = json::array();
        const json* a = member(doc_, key);
        if (!a) return empty;
        if (!a->is_array()) fail(std::string("'") + key + "' is not an array");
        return *a;
    }

    // An unsigned member (`fallback` when absent; kNoData as fallback: required).
    std::uint64_t number(const json& object, const char* key, const std::string& what, std::uint64_t fallback) const {
        const json* v = member(object, key);
        if (!v) {
            if (fallback == kNoData) fail(what + " has no " + key);
            return fallback;
        }
        if (!v->is_number_unsigned()) fail(what + "'s " + key + " is not a whole number >= 0");
        return v->get<std::uint64_t>();
    }

    // An index into the top-level array `arrayKey`.
    std::size_t reference(const json& object, const char* key, const char* arrayKey, const std::string& what) const {
        const std::uint64_t i = number(object, key, what, kNoData);
        if (i >= array(arrayKey).size()) {
            fail(what + "'s " + key + " " + std::to_string(i) + " is past the " + std::to_string(array(arrayKey).size()) + " " + arrayKey);
        }
        return std::size_t(i);
    }

    // The bytes [offset, offset + length) of the file.
    std::string fileBytes(std::uint64_t offset, std::uint64_t length) const {
        if (offset > file_.size() || length > file_.size() - offset) fail("the file ends before byte " + std::to_string(offset + length));
        return file_.substr(std::size_t(offset), std::size_t(length));
    }

    // The GLB container: 12-byte header, a JSON chunk, an optional binary chunk.
    void readContainer() {
        if (file_.size() < 20) fail("too short for a binary glTF (GLB) file");
        const std::string header = fileBytes(0, 20);
        if (header.compare(0, 4, "glTF") != 0) fail("not a binary glTF (GLB) file: it does not start with 'glTF'");
        if (littleEndian32(header, 4) != 2) fail("only binary glTF version 2 is read, not version " + std::to_string(littleEndian32(header, 4)));
        const std::uint64_t length = littleEndian32(header, 8);
        if (length > file_.size()) fail("the header declares " + std::to_string(length) + " bytes but the file has " + std::to_string(file_.size()));
        const std::uint64_t jsonLength = littleEndian32(header, 12);
        if (littleEndian32(header, 16) != 0x4E4F534A) fail("the first chunk is not JSON");
        if (jsonLength > length - 20) fail("the JSON chunk declares " + std::to_string(jsonLength) + " bytes but only " + std::to_string(length - 20) + " follow it");
        json_ = fileBytes(20, jsonLength);
        // Assimp looks for the binary chunk after the JSON chunk padded to 4 bytes.
        const std::uint64_t at = 20 + (jsonLength + 3) / 4 * 4;
        binaryOffset_ = std::min(at, length);
        if (at + 8 <= length) {
            const std::string chunk = fileBytes(at, 8);
            const std::uint64_t chunkLength = littleEndian32(chunk, 0);
            if (chunkLength > length - at - 8) fail("the binary chunk declares " + std::to_string(chunkLength) + " bytes but only " + std::to_string(length - at - 8) + " follow it");
            if (littleEndian32(chunk, 4) == 0x004E4942) {
                binaryStart_ = at + 8;
                binaryLength_ = chunkLength;
            }
        }
    }

    struct Buffer {
        std::uint64_t length = 0;     // as declared
        std::uint64_t used = 0;       // the end of its last view
        std::string inline_;          // decoded data URI
        std::shared_ptr<const RandomAccessFile> file; // external file, or none
        std::string opened;                           // its path as Assimp opens it
        const std::string* data = nullptr;            // its bytes as checked, when external
        bool glbChunk = false;
    };

    void checkBuffers() {
        const json& buffers = array("buffers");
        for (std::size_t i = 0; i < buffers.size(); ++i) {
            const std::string what = "buffer " + std::to_string(i);
            const json& b = buffers[i];
            if (!b.is_object()) fail(what + " is not an object");
            Buffer buffer;
            buffer.length = number(b, "byteLength", what, kNoData);
            const json* uri = member(b, "uri");
            if (binaryOffset_ != 0 && i == 0) {
                // Assimp reads a GLB's buffer 0 from its binary chunk, whatever its uri says.
                if (uri) fail(what + " has a uri, but in a GLB file buffer 0 is read from the binary chunk");
                if (binaryStart_ == 0) fail(what + " has no uri and the GLB file has no binary chunk");
                buffer.glbChunk = true;
                if (buffer.length > binaryLength_) fail(what + " declares " + std::to_string(buffer.length) + " bytes but the binary chunk has " + std::to_string(binaryLength_));
            } else {
                if (!uri) fail(what + " has no uri and is not a GLB file's binary chunk");
                if (!uri->is_string()) fail(what + "'s uri is not a string");
                const std::string& text = uri->get_ref<const std::string&>();
                if (text.rfind("data:", 0) == 0) {
                    const std::size_t comma = text.find(',');
                    if (comma == std::string::npos || text.rfind(";base64", comma) == std::string::npos) fail(what + "'s data URI is not base64");
                    buffer.inline_ = decodeBase64(std::string_view(text).substr(comma + 1));
                    if (buffer.length != buffer.inline_.size()) fail(what + " declares " + std::to_string(buffer.length) + " bytes but its data URI holds " + std::to_string(buffer.inline_.size()));
                } else if (buffer.length > 0) { // Assimp opens no file for an empty buffer
                    const std::string opened = confined(what, text);
                    buffer.file = std::make_shared<const RandomAccessFile>(opened, path_ + ": " + what + " ('" + printable(text, 40) + "')");
                    if (!inside(buffer.file->realPath())) refuseOutside(what, text); // swapped after the check above
                    if (buffer.length > buffer.file->size()) {
                        fail(what + " declares " + std::to_string(buffer.length) + " bytes but its file '" + printable(text, 40) + "' has " + std::to_string(buffer.file->size()));
                    }
                    if (buffer.length > maxInputBytes()) {
                        fail(what + " declares " + std::to_string(buffer.length) + " bytes, more than the input limit of " +
                             std::to_string(maxInputBytes() >> 20) + " MiB (set SDFGEN_MAX_INPUT_MB to raise it)");
                    }
                    buffer.opened = opened;
                }
            }
            buffers_.push_back(std::move(buffer));
        }
    }

    // Images are not read (sdfgen uses no textures), but their URIs are confined as buffers' are.
    void checkImages() {
        const json& images = array("images");
        for (std::size_t i = 0; i < images.size(); ++i) {
            const json* uri = images[i].is_object() ? member(images[i], "uri") : nullptr;
            if (uri && uri->is_string() && uri->get_ref<const std::string&>().rfind("data:", 0) != 0) {
                confined("image " + std::to_string(i), uri->get_ref<const std::string&>());
            }
        }
    }

    [[noreturn]] void refuseOutside(const std::string& what, const std::string& uri) const {
        fail(what + "'s uri '" + printable(uri, 60) + "' leads outside the glTF's folder (" + kGltfFoldersVariable +
             " lists more folders to read from)");
    }

    // The path Assimp opens for an external `uri` (the glTF's folder as Assimp takes it from the
    // path, then the URI as written), after checking that it names a file in the glTF's folder or
    // one of kGltfFoldersVariable's once '..' and symbolic links are resolved.
    std::string confined(const std::string& what, const std::string& uri) {
        if (uri.empty()) fail(what + "'s uri is empty");
        if (uri[0] == '/' || uri[0] == '\\') fail(what + "'s uri '" + printable(uri, 60) + "' is an absolute path (a glTF names its files relative to its folder)");
        const std::size_t slash = path_.find_last_of("/\\");
        std::string folder = slash == std::string::npos ? "" : path_.substr(0, slash + 1);
        if (!folder.empty() && folder.back() != '/') folder += '/';
        const std::string opened = folder + uri;
        std::error_code error;
        const std::filesystem::path resolved = std::filesystem::weakly_canonical(opened, error);
        if (error || !inside(resolved)) refuseOutside(what, uri);
        return opened;
    }

    // Whether a resolved path is in the glTF's folder or one of kGltfFoldersVariable's.
    bool inside(const std::filesystem::path& resolved) {
        if (allowedFolders_.empty()) {
            const std::filesystem::path own = std::filesystem::path(path_).parent_path();
            allowedFolders_.push_back(std::filesystem::canonical(own.empty() ? "." : own));
            const char* list = std::getenv(kGltfFoldersVariable);
            for (std::string_view rest = list ? list : ""; !rest.empty();) {
                const std::string entry(rest.substr(0, rest.find(':')));
                rest.remove_prefix(std::min(rest.size(), entry.size() + 1));
                if (entry.empty()) continue;
                std::error_code error;
                const std::filesystem::path folder = std::filesystem::canonical(entry, error);
                if (error || !std::filesystem::is_directory(folder)) {
                    fail(std::string(kGltfFoldersVariable) + " names '" + printable(entry, 60) + "', which is not a folder");
                }
                allowedFolders_.push_back(folder);
            }
        }
        for (const std::filesystem::path& folder : allowedFolders_) {
            const std::filesystem::path relative = resolved.lexically_relative(folder);
            if (!relative.empty() && *relative.begin() != "..") return true;
        }
        return false;
    }

    struct View {
        std::size_t buffer = 0;
        std::uint64_t offset = 0, length = 0, stride = 0;
    };

    void checkBufferViews() {
        const json& views = array("bufferViews");
        for (std::size_t i = 0; i < views.size(); ++i) {
            const std::string what = "bufferView " + std::to_string(i);
            if (!views[i].is_object()) fail(what + " is not an object");
            View v;
            v.buffer = reference(views[i], "buffer", "buffers", what);
            v.offset = number(views[i], "byteOffset", what, 0);
            v.length = number(views[i], "byteLength", what, kNoData);
            v.stride = number(views[i], "byteStride", what, 0);
            Buffer& b = buffers_[v.buffer];
            if (v.offset > b.length || v.length > b.length - v.offset) {
                fail(what + " (bytes " + std::to_string(v.offset) + " + " + std::to_string(v.length) + ") is outside buffer " +
                     std::to_string(v.buffer) + " (" + std::to_string(b.length) + " bytes)");
            }
            b.used = std::max(b.used, v.offset + v.length);
            views_.push_back(v);
        }
        for (std::size_t i = 0; i < buffers_.size(); ++i) {
            Buffer& b = buffers_[i];
            if (!b.file) continue;
            // Assimp reads an external buffer's whole byteLength: give it the bytes the views use.
            if (b.used < b.length) {
                doc_["buffers"][i]["byteLength"] = b.used;
                bounded_ = true;
            }
            // Read here, and again only for a buffer of the same file that reaches further: the
            // bytes the checks below read are the ones Assimp is given.
            std::string& data = result_.externalFiles[b.opened];
            if (b.used > data.size()) data = b.file->read(0, b.used);
            b.data = &data;
        }
    }

    struct Accessor {
        std::uint64_t count = 0, elementSize = 0, componentSize = 0;
        std::uint32_t componentType = 0;
        std::string type;
        bool hasView = false;
        bool sparse = false;
        std::size_t view = 0;
        std::uint64_t offset = 0;
    };

    void checkAccessors() {
        const json& accessors = array("accessors");
        std::uint64_t dataBytes = file_.size();
        for (const Buffer& b : buffers_) dataBytes += b.length;
        for (std::size_t i = 0; i < accessors.size(); ++i) {
            const std::string what = "accessor " + std::to_string(i);
            const json& a = accessors[i];
            if (!a.is_object()) fail(what + " is not an object");
            Accessor acc;
            acc.count = number(a, "count", what, kNoData);
            acc.componentType = std::uint32_t(std::min<std::uint64_t>(number(a, "componentType", what, kNoData), 0xffffffffu));
            switch (acc.componentType) {
            case 5120: case 5121: acc.componentSize = 1; break;
            case 5122: case 5123: acc.componentSize = 2; break;
            case 5125: case 5126: acc.componentSize = 4; break;
            default: fail(what + "'s componentType " + std::to_string(acc.componentType) + " is not a glTF component type");
            }
            const json* type = member(a, "type");
            if (!type || !type->is_string()) fail(what + " has no type");
            acc.type = type->get<std::string>();
            static const std::pair<const char*, int> kComponents[] = {{"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4},
                                                                     {"MAT2", 4},   {"MAT3", 9}, {"MAT4", 16}};
            int components = 0;
            for (const auto& [name, n] : kComponents) {
                if (acc.type == name) components = n;
            }
            if (components == 0) fail(what + "'s type '" + printable(acc.type, 40) + "' is not a glTF accessor type");
            acc.elementSize = acc.componentSize * std::uint64_t(components);
            acc.offset = number(a, "byteOffset", what, 0);
            if (member(a, "bufferView")) {
                acc.hasView = true;
                acc.view = reference(a, "bufferView", "bufferViews", what);
                const View& v = views_[acc.view];
                const std::uint64_t stride = v.stride ? v.stride : acc.elementSize;
                // The last element must end inside the view (Assimp checks less than this).
                const bool fits = acc.count == 0 ||
                                  (acc.offset <= v.length && acc.elementSize <= v.length - acc.offset &&
                                   (acc.count - 1) <= (v.length - acc.offset - acc.elementSize) / std::max<std::uint64_t>(stride, 1) &&
                                   acc.count <= v.length);
                if (!fits || (v.stride && v.stride < acc.elementSize)) {
                    fail(what + " (" + std::to_string(acc.count) + " elements of " + std::to_string(acc.elementSize) +
                         " bytes from byte " + std::to_string(acc.offset) + ") does not fit bufferView " + std::to_string(acc.view) +
                         " (" + std::to_string(v.length) + " bytes)");
                }
            } else if (acc.count > dataBytes * 64 / acc.elementSize) {
                // Without a view its elements are zeros (or sparse), allocated whole by Assimp.
                fail(what + " claims " + std::to_string(acc.count) + " elements without data, more than the file could describe");
            }
            if (const json* sparse = member(a, "sparse")) {
                checkSparse(what + "'s sparse", *sparse, acc);
                acc.sparse = true;
            }
            accessors_.push_back(acc);
        }
    }

    // A sparse accessor's indices and values, which Assimp reads without checking their views.
    void checkSparse(const std::string& what, const json& sparse, const Accessor& acc) const {
        if (!sparse.is_object()) fail(what + " is not an object");
        // Assimp copies the base elements packed, then reads them at the view's stride: past its copy.
        if (acc.hasView && views_[acc.view].stride > acc.elementSize) fail(what + " patches an accessor on an interleaved (strided) bufferView, which Assimp misreads");
        const std::uint64_t count = number(sparse, "count", what, kNoData);
        if (count > acc.count) fail(what + " count " + std::to_string(count) + " exceeds the accessor's " + std::to_string(acc.count));
        for (const char* part : {"indices", "values"}) {
            const json* p = member(sparse, part);
            if (!p || !p->is_object()) fail(what + " has no " + part);
            const std::string partWhat = what + " " + part;
            const View& v = views_[reference(*p, "bufferView", "bufferViews", partWhat)];
            const std::uint64_t offset = number(*p, "byteOffset", partWhat, 0);
            std::uint64_t size = acc.elementSize;
            if (std::string(part) == "indices") {
                const std::uint64_t type = number(*p, "componentType", partWhat, kNoData);
                if (type != 5121 && type != 5123 && type != 5125) fail(partWhat + " are not unsigned integers");
                size = type == 5121 ? 1 : type == 5123 ? 2 : 4;
            }
            if (offset > v.length || count > (v.length - offset) / size) {
                fail(partWhat + " (" + std::to_string(count) + " of " + std::to_string(size) + " bytes from byte " +
                     std::to_string(offset) + ") do not fit their bufferView (" + std::to_string(v.length) + " bytes)");
            }
        }
    }

    // The bytes [offset, offset + length) of a buffer (checked to lie in it by the view checks).
    std::string bufferBytes(std::size_t buffer, std::uint64_t offset, std::uint64_t length) const {
        const Buffer& b = buffers_[buffer];
        if (b.glbChunk) return fileBytes(binaryStart_ + offset, length);
        if (b.data) return b.data->substr(std::size_t(offset), std::size_t(length));
        return b.inline_.substr(std::size_t(offset), std::size_t(length));
    }

    void checkMeshes() {
        const json& meshes = array("meshes");
        meshTriangles_.assign(meshes.size(), 0);
        meshVertices_.assign(meshes.size(), 0);
        for (std::size_t m = 0; m < meshes.size(); ++m) {
            const json* primitives = meshes[m].is_object() ? member(meshes[m], "primitives") : nullptr;
            if (!primitives || !primitives->is_array()) fail("mesh " + std::to_string(m) + " has no primitives array");
            for (std::size_t p = 0; p < primitives->size(); ++p) {
                const std::string what = "mesh " + std::to_string(m) + " primitive " + std::to_string(p);
                const json& primitive = (*primitives)[p];
                if (!primitive.is_object()) fail(what + " is not an object");
                const std::uint64_t mode = number(primitive, "mode", what, 4);
                if (mode > 6) fail(what + "'s mode " + std::to_string(mode) + " is not a glTF primitive mode");
                const json* attributes = member(primitive, "attributes");
                if (!attributes || !attributes->is_object()) fail(what + " has no attributes");
                for (const auto& [name, index] : attributes->items()) {
                    if (!index.is_number_unsigned() || index.get<std::uint64_t>() >= accessors_.size()) {
                        fail(what + "'s attribute " + printable(name, 40) + " refers to no accessor");
                    }
                }
                if (mode < 4) continue; // points and lines: the mesh counts what it skips
                if (!member(*attributes, "POSITION")) fail(what + " has no POSITION attribute");
                const Accessor& positions = accessors_[(*attributes)["POSITION"].get<std::size_t>()];
                if (positions.type != "VEC3") fail(what + "'s POSITION accessor is not VEC3");
                std::uint64_t corners = positions.count;
                // Draco-compressed primitives are decoded by Assimp; their accessors hold no data here.
                const json* extensions = member(primitive, "extensions");
                const bool compressed = extensions && extensions->is_object() && member(*extensions, "KHR_draco_mesh_compression");
                // Assimp copies integer positions' bytes into floats as they are: refused, not misread.
                if (!compressed && positions.componentType != 5126) {
                    fail(what + "'s positions are integers (KHR_mesh_quantization), which Assimp does not convert; only float positions are read");
                }
                if (member(primitive, "indices")) {
                    const std::size_t i = reference(primitive, "indices", "accessors", what);
                    const Accessor& indices = accessors_[i];
                    if (indices.type != "SCALAR" || (indices.componentType != 5121 && indices.componentType != 5123 && indices.componentType != 5125)) {
                        fail(what + "'s indices are not unsigned integer scalars");
                    }
                    // Assimp reads sparse indices patched; refused rather than checked in a second reading.
                    if (indices.sparse) fail(what + "'s indices accessor is sparse, which sdfgen does not read");
                    if (!compressed) checkIndices(what, indices, positions.count);
                    corners = indices.count;
                }
                std::uint64_t triangles = 0;
                if (mode == 4) {
                    if (corners % 3 != 0) fail(what + " has " + std::to_string(corners) + " triangle corners, not a multiple of 3");
                    triangles = corners / 3;
                } else if (corners >= 3) {
                    triangles = corners - 2;
                }
                meshTriangles_[m] += triangles;
                meshVertices_[m] += positions.count;
            }
        }
    }

    void checkIndices(const std::string& what, const Accessor& indices, std::uint64_t vertexCount) const {
        if (indices.count == 0) return;
        if (!indices.hasView) {
            if (vertexCount == 0) fail(what + "'s indices refer to vertex 0 but it has no vertices");
            return; // all zeros
        }
        const View& v = views_[indices.view];
        const std::uint64_t stride = v.stride ? v.stride : indices.elementSize;
        const std::string bytes = bufferBytes(v.buffer, v.offset + indices.offset, (indices.count - 1) * stride + indices.elementSize);
        for (std::uint64_t k = 0; k < indices.count; ++k) {
            const char* at = bytes.data() + k * stride;
            std::uint64_t index = 0;
            if (indices.elementSize == 1) index = std::uint8_t(*at);
            else if (indices.elementSize == 2) { std::uint16_t x; std::memcpy(&x, at, 2); index = x; }
            else { std::uint32_t x; std::memcpy(&x, at, 4); index = x; }
            if (index >= vertexCount) {
                fail(what + " refers to vertex " + std::to_string(index) + " but it has " + std::to_string(vertexCount) + " vertices (counted from 0)");
            }
        }
    }

    // Node trees: references in range, no cycles, at most kMaxNodeDepth deep; the triangles the
    // scenes instance (a node used twice is read twice) must fit into memory.
    void checkNodes() {
        const json& nodes = array("nodes");
        std::vector<std::vector<std::size_t>> children(nodes.size());
        std::vector<std::size_t> meshOf(nodes.size(), kNone);
        for (std::size_t n = 0; n < nodes.size(); ++n) {
            const std::string what = "node " + std::to_string(n);
            if (!nodes[n].is_object()) fail(what + " is not an object");
            if (member(nodes[n], "mesh")) meshOf[n] = reference(nodes[n], "mesh", "meshes", what);
            if (const json* c = member(nodes[n], "children")) {
                if (!c->is_array()) fail(what + "'s children is not an array");
                for (const json& child : *c) {
                    if (!child.is_number_unsigned() || child.get<std::uint64_t>() >= nodes.size()) fail(what + " has a child that is no node");
                    children[n].push_back(child.get<std::size_t>());
                }
            }
        }
        // Depth-first, without recursion: depth and instanced triangles of each node's subtree.
        enum : std::uint8_t { Unvisited, Open, Done };
        std::vector<std::uint8_t> state(nodes.size(), Unvisited);
        std::vector<std::uint64_t> height(nodes.size(), 0), triangles(nodes.size(), 0), vertices(nodes.size(), 0);
        const auto saturatingAdd = [](std::uint64_t a, std::uint64_t b) { return a > kNoData - b ? kNoData : a + b; };
        for (std::size_t root = 0; root < nodes.size(); ++root) {
            if (state[root] != Unvisited) continue;
            std::vector<std::pair<std::size_t, std::size_t>> stack{{root, 0}}; // node, next child
            state[root] = Open;
            while (!stack.empty()) {
                auto& [node, next] = stack.back();
                if (next < children[node].size()) {
                    const std::size_t child = children[node][next++];
                    if (state[child] == Open) fail("node " + std::to_string(child) + " is its own ancestor (a cycle in the node tree)");
                    if (state[child] == Unvisited) {
                        state[child] = Open;
                        stack.emplace_back(child, 0);
                    }
                    continue;
                }
                std::uint64_t h = 0, t = meshOf[node] == kNone ? 0 : meshTriangles_[meshOf[node]];
                std::uint64_t v = meshOf[node] == kNone ? 0 : meshVertices_[meshOf[node]];
                for (const std::size_t child : children[node]) {
                    h = std::max(h, height[child] + 1);
                    t = saturatingAdd(t, triangles[child]);
                    v = saturatingAdd(v, vertices[child]);
                }
                if (h >= kMaxNodeDepth) fail("its node tree is deeper than " + std::to_string(kMaxNodeDepth) + " levels");
                height[node] = h;
                triangles[node] = t;
                vertices[node] = v;
                state[node] = Done;
                stack.pop_back();
            }
        }
        std::uint64_t totalTriangles = 0, totalVertices = 0;
        const json& scenes = array("scenes");
        // The scene Assimp reads: `scene`, else the first.
        const std::uint64_t defaultScene = scenes.empty() ? 0 : number(doc_, "scene", "the file", 0);
        for (std::size_t s = 0; s < scenes.size(); ++s) {
            const json* roots = scenes[s].is_object() ? member(scenes[s], "nodes") : nullptr;
            if (!roots) continue;
            if (!roots->is_array()) fail("a scene's nodes is not an array");
            for (const json& r : *roots) {
                if (!r.is_number_unsigned() || r.get<std::uint64_t>() >= nodes.size()) fail("a scene refers to a node that does not exist");
                totalTriangles = saturatingAdd(totalTriangles, triangles[r.get<std::size_t>()]);
                totalVertices = saturatingAdd(totalVertices, vertices[r.get<std::size_t>()]);
                if (s == defaultScene) result_.triangles = saturatingAdd(result_.triangles, triangles[r.get<std::size_t>()]);
            }
        }
        result_.counted = defaultScene < scenes.size();
        // What the mesh built from them holds: positions read (12), in double (24) and local (12)
        // bytes per vertex; indices (12), normals (12) and the degenerate flags per triangle.
        const std::uint64_t available = availableMemoryBytes();
        const long double needed = 48.0L * totalVertices + 25.0L * totalTriangles;
        if (totalVertices > 0xffffffffu || (available > 0 && needed > available)) {
            char line[200];
            std::snprintf(line, sizeof line, "its scenes instance %llu triangles on %llu vertices, about %.0Lf MiB, more than %s",
                          static_cast<unsigned long long>(totalTriangles), static_cast<unsigned long long>(totalVertices),
                          needed / 1048576.0L,
                          totalVertices > 0xffffffffu ? "the 2^32 - 1 vertices sdfgen supports" : "the memory available");
            fail(line);
        }
    }

    // The file with the JSON as bounded (GLB: the same chunks after the new JSON chunk).
    std::string rewritten() const {
        std::string text = doc_.dump();
        if (binaryOffset_ == 0) return text;
        while (text.size() % 4 != 0) text += ' ';
        const std::string rest = fileBytes(binaryOffset_, file_.size() - binaryOffset_);
        std::string out = fileBytes(0, 12);
        const auto put32 = [&](std::size_t at, std::uint32_t v) { std::memcpy(out.data() + at, &v, 4); };
        put32(8, std::uint32_t(12 + 8 + text.size() + rest.size()));
        out.append(8, '\0');
        put32(12, std::uint32_t(text.size()));
        put32(16, 0x4E4F534A);
        return out + text + rest;
    }

    static constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
    const std::string& path_;
    std::string file_; // the whole file, as read once
    std::string json_;
    json doc_;
    std::uint64_t binaryOffset_ = 0, binaryStart_ = 0, binaryLength_ = 0;
    std::vector<Buffer> buffers_;
    std::vector<std::filesystem::path> allowedFolders_; // resolved; the glTF's own first
    std::vector<View> views_;
    std::vector<Accessor> accessors_;
    std::vector<std::uint64_t> meshTriangles_, meshVertices_;
    bool bounded_ = false;
    bool byteOrderMark_ = false; // the .gltf started with a UTF-8 byte-order mark (skipped)
    GltfCheck result_;
};

} // namespace

GltfCheck guardGltf(const std::string& path, std::string bytes, bool binary) { return GltfGuard(path, std::move(bytes), binary).check(); }

} // namespace sdfgen
