#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace sdfgen::render {

// An RGBA8 image, top row first.
struct Image {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgba;

    const std::uint8_t* pixel(int x, int y) const { return &rgba[(std::size_t(y) * std::size_t(width) + std::size_t(x)) * 4]; }
};

// Reads the bound read framebuffer's colour (glReadPixels), flipped so the top row comes first.
Image readFramebuffer(int width, int height);

// PNG files through stb; errors throw Error naming the file. Saving is atomic (a temporary file in
// the same folder, renamed over the target).
void savePng(const Image& image, const std::string& path);
Image loadPng(const std::string& path);

} // namespace sdfgen::render
