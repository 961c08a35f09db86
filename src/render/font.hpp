#pragma once
// The interface font: DejaVu Sans from Debian's fonts-dejavu-core, read at run time, for the
// viewer's panel and the colour bar's labels alike. Where it is not installed, both fall back
// to a built-in font (Dear ImGui's and stb_easy_font's).
#include "render/gl.hpp"

#include <string>
#include <vector>

namespace sdfgen::render {

// The font file, or "" when it is not installed.
const std::string& uiFontPath();

// The printable ASCII glyphs of a TrueType font rasterised at one pixel height into a GL_R8
// texture (stb_truetype), for text in overlays.
class GlyphAtlas {
public:
    GlyphAtlas() = default;
    ~GlyphAtlas();
    GlyphAtlas(const GlyphAtlas&) = delete;
    GlyphAtlas& operator=(const GlyphAtlas&) = delete;
    // Loads `fontPath` at `pixelHeight` (again only when either changed); false when the font
    // cannot be read.
    bool load(const std::string& fontPath, float pixelHeight);
    bool empty() const { return texture_ == 0; }
    GLuint texture() const { return texture_; }
    float pixelHeight() const { return pixelHeight_; }
    float ascent() const { return ascent_; }

    // One glyph's quad: pixel corners relative to the pen (baseline), texture corners.
    struct Quad {
        float x0, y0, x1, y1, u0, v0, u1, v1;
    };
    // The quads of `text` starting with the pen at (x, baseline); characters outside printable
    // ASCII are skipped.
    std::vector<Quad> layout(const std::string& text, float x, float baseline) const;
    float width(const std::string& text) const;

private:
    static constexpr int kSide = 512, kFirst = 32, kCount = 95;
    GLuint texture_ = 0;
    std::string path_;
    float pixelHeight_ = 0.0f, ascent_ = 0.0f;
    std::vector<unsigned char> glyphData_; // stbtt_bakedchar[kCount]
};

} // namespace sdfgen::render
