#include "render/font.hpp"

#include <stb/stb_truetype.h>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace sdfgen::render {

const std::string& uiFontPath() {
    static const std::string path = [] {
        // Debian's fonts-dejavu-core (extern/debian-packages.txt), then where other systems keep it.
        for (const char* candidate : {"/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf", "/usr/share/fonts/TTF/DejaVuSans.ttf",
                                      "/usr/share/fonts/dejavu/DejaVuSans.ttf"}) {
            std::error_code ec;
            if (std::filesystem::is_regular_file(candidate, ec)) return std::string(candidate);
        }
        return std::string();
    }();
    return path;
}

GlyphAtlas::~GlyphAtlas() {
    if (texture_) glDeleteTextures(1, &texture_);
}

bool GlyphAtlas::load(const std::string& fontPath, float pixelHeight) {
    if (texture_ && fontPath == path_ && pixelHeight == pixelHeight_) return true;
    std::ifstream in(fontPath, std::ios::binary);
    const std::vector<unsigned char> font((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    stbtt_fontinfo info;
    if (font.empty() || !stbtt_InitFont(&info, font.data(), stbtt_GetFontOffsetForIndex(font.data(), 0))) return false;
    std::vector<unsigned char> bitmap(std::size_t(kSide) * kSide);
    glyphData_.assign(sizeof(stbtt_bakedchar) * kCount, 0);
    auto* glyphs = reinterpret_cast<stbtt_bakedchar*>(glyphData_.data());
    if (stbtt_BakeFontBitmap(font.data(), 0, pixelHeight, bitmap.data(), kSide, kSide, kFirst, kCount, glyphs) <= 0) return false;
    int ascent = 0, descent = 0, gap = 0;
    stbtt_GetFontVMetrics(&info, &ascent, &descent, &gap);
    ascent_ = float(ascent) * stbtt_ScaleForPixelHeight(&info, pixelHeight);
    if (texture_) glDeleteTextures(1, &texture_);
    glCreateTextures(GL_TEXTURE_2D, 1, &texture_);
    glTextureStorage2D(texture_, 1, GL_R8, kSide, kSide);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(texture_, 0, 0, 0, kSide, kSide, GL_RED, GL_UNSIGNED_BYTE, bitmap.data());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureParameteri(texture_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(texture_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    path_ = fontPath;
    pixelHeight_ = pixelHeight;
    return true;
}

std::vector<GlyphAtlas::Quad> GlyphAtlas::layout(const std::string& text, float x, float baseline) const {
    std::vector<Quad> quads;
    const auto* glyphs = reinterpret_cast<const stbtt_bakedchar*>(glyphData_.data());
    for (const char c : text) {
        if (c < kFirst || c >= kFirst + kCount) continue;
        stbtt_aligned_quad q;
        stbtt_GetBakedQuad(glyphs, kSide, kSide, c - kFirst, &x, &baseline, &q, 1);
        quads.push_back({q.x0, q.y0, q.x1, q.y1, q.s0, q.t0, q.s1, q.t1});
    }
    return quads;
}

float GlyphAtlas::width(const std::string& text) const {
    const auto* glyphs = reinterpret_cast<const stbtt_bakedchar*>(glyphData_.data());
    float w = 0.0f;
    for (const char c : text) {
        if (c >= kFirst && c < kFirst + kCount) w += glyphs[c - kFirst].xadvance;
    }
    return w;
}

} // namespace sdfgen::render
