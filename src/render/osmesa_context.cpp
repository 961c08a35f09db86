#include "render/osmesa_context.hpp"
#include "sdfgen/error.hpp"
#include "render/gl.hpp"

#include <GL/osmesa.h>
#include <dlfcn.h>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

namespace sdfgen::render {

namespace {

// libOSMesa is opened on first use rather than linked: it pulls in LLVM, whose relocations alone
// add some 50 MB to the resident memory of every sdfgen command, renders or not.
struct OsMesaLibrary {
    decltype(&::OSMesaCreateContextAttribs) createContextAttribs = nullptr;
    decltype(&::OSMesaDestroyContext) destroyContext = nullptr;
    decltype(&::OSMesaMakeCurrent) makeCurrent = nullptr;
    decltype(&::OSMesaGetProcAddress) getProcAddress = nullptr;

    static const OsMesaLibrary& get() {
        static const OsMesaLibrary library;
        if (!library.handle) throw Error("OSMesa: cannot load libOSMesa.so.8 (Debian package libosmesa6): " + library.error);
        return library;
    }

private:
    OsMesaLibrary() {
        handle = dlopen("libOSMesa.so.8", RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            error = dlerror();
            return;
        }
        bool found = true;
        auto symbol = [&](auto& function, const char* name) {
            function = reinterpret_cast<std::remove_reference_t<decltype(function)>>(dlsym(handle, name));
            if (!function) found = false, error = std::string("no symbol ") + name;
        };
        symbol(createContextAttribs, "OSMesaCreateContextAttribs");
        symbol(destroyContext, "OSMesaDestroyContext");
        symbol(makeCurrent, "OSMesaMakeCurrent");
        symbol(getProcAddress, "OSMesaGetProcAddress");
        if (!found) handle = nullptr; // left open: the process ends soon after this error
    }
    void* handle = nullptr;
    std::string error;
};

class OsMesaContext final : public GlContext {
public:
    explicit OsMesaContext(glm::ivec2 size) : size_(size) {
        if (size.x < 1 || size.y < 1 || size.x > 16384 || size.y > 16384) {
            throw Error("image size " + std::to_string(size.x) + "x" + std::to_string(size.y) + " is out of range (1 to 16384)");
        }
        const int attributes[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24, OSMESA_STENCIL_BITS, 8,
                                  OSMESA_PROFILE, OSMESA_CORE_PROFILE, OSMESA_CONTEXT_MAJOR_VERSION, 4,
                                  OSMESA_CONTEXT_MINOR_VERSION, 5, 0};
        context_ = osmesa_.createContextAttribs(attributes, nullptr);
        if (!context_) throw Error("OSMesa: could not create an OpenGL 4.5 core context (is Mesa's llvmpipe installed?)");
        buffer_.resize(std::size_t(size.x) * std::size_t(size.y));
        makeCurrent();
        loadGl(reinterpret_cast<GLADloadfunc>(osmesa_.getProcAddress), "OSMesa");
    }
    ~OsMesaContext() override { osmesa_.destroyContext(context_); }

    void makeCurrent() override {
        if (!osmesa_.makeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, size_.x, size_.y)) {
            throw Error("OSMesa: could not make the context current");
        }
    }
    void release() override { osmesa_.makeCurrent(nullptr, nullptr, 0, 0, 0); }
    glm::ivec2 framebufferSize() const override { return size_; }
    void present() override { glFinish(); }
    const char* kind() const override { return "OSMesa"; }

private:
    const OsMesaLibrary& osmesa_ = OsMesaLibrary::get();
    glm::ivec2 size_;
    OSMesaContext context_ = nullptr;
    std::vector<std::uint32_t> buffer_; // RGBA8, bottom row first
};

} // namespace

std::unique_ptr<GlContext> createOsMesaContext(glm::ivec2 size) { return std::make_unique<OsMesaContext>(size); }

} // namespace sdfgen::render
