#include "render/image.hpp"
#include "core/io/atomic_file.hpp"
#include "sdfgen/error.hpp"
#include "render/gl.hpp"

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <unistd.h>

namespace sdfgen::render {

Image readFramebuffer(int width, int height) {
    Image image{width, height, std::vector<std::uint8_t>(std::size_t(width) * std::size_t(height) * 4)};
    std::vector<std::uint8_t> rows(image.rgba.size());
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rows.data());
    const std::size_t stride = std::size_t(width) * 4;
    for (int y = 0; y < height; ++y) {
        std::memcpy(&image.rgba[std::size_t(y) * stride], &rows[std::size_t(height - 1 - y) * stride], stride);
    }
    return image;
}

void savePng(const Image& image, const std::string& path) {
    writeFileAtomically(path, [&](std::ostream& out) {
        auto append = [](void* stream, void* data, int size) {
            static_cast<std::ostream*>(stream)->write(static_cast<const char*>(data), size);
        };
        if (!stbi_write_png_to_func(append, &out, image.width, image.height, 4, image.rgba.data(), image.width * 4)) {
            throw Error(path + ": cannot encode the PNG image");
        }
    });
}

Image loadPng(const std::string& path) {
    int w = 0, h = 0, channels = 0;
    unsigned char* data = stbi_load(path.c_str(), &w, &h, &channels, 4);
    if (!data) throw Error(path + ": cannot read the PNG file (" + (stbi_failure_reason() ? stbi_failure_reason() : "unknown") + ")");
    Image image{w, h, std::vector<std::uint8_t>(data, data + std::size_t(w) * std::size_t(h) * 4)};
    stbi_image_free(data);
    return image;
}

} // namespace sdfgen::render
