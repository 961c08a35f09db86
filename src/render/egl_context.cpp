#include "render/egl_context.hpp"
#include "render/gl.hpp"
#include "render/osmesa_context.hpp"
#include "sdfgen/error.hpp"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace sdfgen::render {

namespace {

bool hasExtension(const char* list, const char* name) {
    if (!list) return false;
    const std::size_t length = std::strlen(name);
    for (const char* at = std::strstr(list, name); at; at = std::strstr(at + 1, name)) {
        if ((at == list || at[-1] == ' ') && (at[length] == ' ' || at[length] == '\0')) return true;
    }
    return false;
}

std::string eglErrorName(EGLint code) {
    switch (code) {
    case EGL_SUCCESS: return "no EGL error code";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
    default: return "EGL error " + std::to_string(code);
    }
}

// A display with a 4.5 core context current on a pbuffer.
struct EglSetup {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLSurface surface = EGL_NO_SURFACE;
    EGLContext context = EGL_NO_CONTEXT;
};

// Tries one display; on failure returns false with the reason in `why`. Displays are never
// terminated: an EGL display is one per process, and terminating it would end every context on it
// (the compute device's and a renderer's may share one).
bool trySetup(EGLDisplay display, glm::ivec2 size, EglSetup& out, std::string& why) {
    if (display == EGL_NO_DISPLAY) {
        why = "no display";
        return false;
    }
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor)) {
        why = "eglInitialize failed (" + eglErrorName(eglGetError()) + ")";
        return false;
    }
    auto fail = [&](const std::string& reason) {
        why = reason + " (" + eglErrorName(eglGetError()) + ")";
        return false;
    };
    if (!eglBindAPI(EGL_OPENGL_API)) return fail("no desktop OpenGL");
    const EGLint configAttributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                                       EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_ALPHA_SIZE, 8,
                                       EGL_DEPTH_SIZE, 24, EGL_STENCIL_SIZE, 8, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint configs = 0;
    if (!eglChooseConfig(display, configAttributes, &config, 1, &configs) || configs < 1) {
        return fail("no RGBA8 pbuffer configuration with depth and stencil");
    }
    const EGLint surfaceAttributes[] = {EGL_WIDTH, size.x, EGL_HEIGHT, size.y, EGL_NONE};
    const EGLSurface surface = eglCreatePbufferSurface(display, config, surfaceAttributes);
    if (surface == EGL_NO_SURFACE) return fail("could not create a " + std::to_string(size.x) + "x" + std::to_string(size.y) + " pbuffer");
    const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                        EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    const EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttributes);
    if (context == EGL_NO_CONTEXT) {
        eglDestroySurface(display, surface);
        return fail("could not create an OpenGL 4.5 core context");
    }
    if (!eglMakeCurrent(display, surface, surface, context)) {
        eglDestroyContext(display, context);
        eglDestroySurface(display, surface);
        return fail("could not make the context current");
    }
    out = {display, surface, context};
    return true;
}

// The EGL devices, hardware ones first then Mesa's software one(s); empty when EGL cannot list them.
struct EglDevice {
    EGLDeviceEXT device;
    bool software;
};
std::vector<EglDevice> listDevices(const char* client) {
    std::vector<EglDevice> out;
    if (!hasExtension(client, "EGL_EXT_device_enumeration")) return out;
    const auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    const auto queryDeviceString = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
    EGLint count = 0;
    if (!queryDevices || !queryDevices(0, nullptr, &count) || count < 1) return out;
    std::vector<EGLDeviceEXT> devices(std::size_t(count), nullptr);
    if (!queryDevices(count, devices.data(), &count)) return out;
    for (EGLint d = 0; d < count; ++d) {
        const char* extensions = queryDeviceString ? queryDeviceString(devices[d], EGL_EXTENSIONS) : nullptr;
        out.push_back({devices[d], hasExtension(extensions, "EGL_MESA_device_software")});
    }
    return out;
}

EglSetup setUp(glm::ivec2 size) {
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    std::string tried;
    auto note = [&](const std::string& what, const std::string& why) { tried += (tried.empty() ? "" : "; ") + what + ": " + why; };
    EglSetup setup;
    std::string why;
    const auto getPlatformDisplay =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (getPlatformDisplay && hasExtension(client, "EGL_EXT_platform_device")) {
        const std::vector<EglDevice> devices = listDevices(client);
        for (std::size_t d = 0; d < devices.size(); ++d) {
            // Mesa lists its software renderer as a device too; the surfaceless platform covers it.
            if (devices[d].software) continue;
            if (trySetup(getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[d].device, nullptr), size, setup, why)) return setup;
            note("EGL device " + std::to_string(d), why);
        }
    }
    if (getPlatformDisplay && hasExtension(client, "EGL_MESA_platform_surfaceless")) {
        if (trySetup(getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr), size, setup, why)) return setup;
        note("surfaceless platform", why);
    }
    if (trySetup(eglGetDisplay(EGL_DEFAULT_DISPLAY), size, setup, why)) return setup;
    note("default display", why);
    throw Error("EGL: no OpenGL 4.5 core context (" + tried + ")");
}

void checkSize(glm::ivec2 size) {
    if (size.x < 1 || size.y < 1 || size.x > 16384 || size.y > 16384) {
        throw Error("image size " + std::to_string(size.x) + "x" + std::to_string(size.y) + " is out of range (1 to 16384)");
    }
}

class EglContext final : public GlContext {
public:
    explicit EglContext(glm::ivec2 size) : size_(size) {
        checkSize(size);
        setup_ = setUp(size);
        try {
            loadGl(reinterpret_cast<GLADloadfunc>(eglGetProcAddress), "EGL");
        } catch (...) {
            destroy();
            throw;
        }
    }
    ~EglContext() override { destroy(); }

    void makeCurrent() override {
        if (!eglMakeCurrent(setup_.display, setup_.surface, setup_.surface, setup_.context)) {
            throw Error("EGL: could not make the context current (" + eglErrorName(eglGetError()) + ")");
        }
    }
    void release() override { eglMakeCurrent(setup_.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT); }
    glm::ivec2 framebufferSize() const override { return size_; }
    void present() override { glFinish(); }
    const char* kind() const override { return "EGL"; }

private:
    void destroy() {
        release();
        eglDestroyContext(setup_.display, setup_.context);
        eglDestroySurface(setup_.display, setup_.surface);
    }

    glm::ivec2 size_;
    EglSetup setup_;
};

} // namespace

bool eglMayHaveHardwareDevice() {
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!hasExtension(client, "EGL_EXT_device_enumeration")) return true;
    const std::vector<EglDevice> devices = listDevices(client);
    if (devices.empty()) return true;
    for (const EglDevice& d : devices) {
        if (!d.software) return true;
    }
    return false;
}

std::unique_ptr<GlContext> createEglContext(glm::ivec2 size) { return std::make_unique<EglContext>(size); }

std::unique_ptr<GlContext> createHeadlessContext(glm::ivec2 size) {
    checkSize(size);
    const char* only = std::getenv("SDFGEN_HEADLESS");
    const std::string choice = only ? only : "";
    if (choice == "egl") return createEglContext(size);
    if (choice == "osmesa") return createOsMesaContext(size);
    if (!choice.empty()) throw Error("SDFGEN_HEADLESS is '" + choice + "'; expected egl or osmesa (or unset: EGL, else OSMesa)");
    std::string eglFailure;
    try {
        return createEglContext(size);
    } catch (const Error& e) {
        eglFailure = e.what();
    }
    try {
        return createOsMesaContext(size);
    } catch (const Error& e) {
        throw Error(eglFailure + "; " + e.what());
    }
}

} // namespace sdfgen::render
