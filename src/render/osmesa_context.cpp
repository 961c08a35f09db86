#include "render/osmesa_context.hpp"
#include "sdfgen/error.hpp"
#include "render/gl.hpp"

#include <GL/osmesa.h>
#include <cstdint>
#include <vector>

namespace sdfgen::render {

namespace {

class OsMesaContext final : public GlContext {
public:
    explicit OsMesaContext(glm::ivec2 size) : size_(size) {
        if (size.x < 1 || size.y < 1 || size.x > 16384 || size.y > 16384) {
            throw Error("image size " + std::to_string(size.x) + "x" + std::to_string(size.y) + " is out of range (1 to 16384)");
        }
        const int attributes[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24, OSMESA_STENCIL_BITS, 8,
                                  OSMESA_PROFILE, OSMESA_CORE_PROFILE, OSMESA_CONTEXT_MAJOR_VERSION, 4,
                                  OSMESA_CONTEXT_MINOR_VERSION, 5, 0};
        context_ = OSMesaCreateContextAttribs(attributes, nullptr);
        if (!context_) throw Error("OSMesa: could not create an OpenGL 4.5 core context (is Mesa's llvmpipe installed?)");
        buffer_.resize(std::size_t(size.x) * std::size_t(size.y));
        makeCurrent();
        loadGl(reinterpret_cast<GLADloadfunc>(OSMesaGetProcAddress), "OSMesa");
    }
    ~OsMesaContext() override { OSMesaDestroyContext(context_); }

    void makeCurrent() override {
        if (!OSMesaMakeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, size_.x, size_.y)) {
            throw Error("OSMesa: could not make the context current");
        }
    }
    void release() override { OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0); }
    glm::ivec2 framebufferSize() const override { return size_; }
    void present() override { glFinish(); }
    const char* kind() const override { return "OSMesa"; }

private:
    glm::ivec2 size_;
    OSMesaContext context_ = nullptr;
    std::vector<std::uint32_t> buffer_; // RGBA8, bottom row first
};

} // namespace

std::unique_ptr<GlContext> createOsMesaContext(glm::ivec2 size) { return std::make_unique<OsMesaContext>(size); }

} // namespace sdfgen::render
