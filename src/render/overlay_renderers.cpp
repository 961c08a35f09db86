// Line segments and the colour bar (2D, with text in the interface font, else stb_easy_font).
#include "render/font.hpp"
#include "render/renderers.hpp"

#include <stb/stb_easy_font.h>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <string>

namespace sdfgen::render {

LineRenderer::LineRenderer() : program_("lines.vert", "lines.frag") {
    glCreateVertexArrays(1, &vao_);
    glCreateBuffers(1, &vbo_);
    glVertexArrayVertexBuffer(vao_, 0, vbo_, 0, sizeof(glm::vec3));
    glEnableVertexArrayAttrib(vao_, 0);
    glVertexArrayAttribFormat(vao_, 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao_, 0, 0);
}

LineRenderer::~LineRenderer() {
    glDeleteBuffers(1, &vbo_);
    glDeleteVertexArrays(1, &vao_);
}

void LineRenderer::draw(const FrameInfo& frame, const std::vector<glm::vec3>& segments, glm::vec4 colour) {
    if (segments.empty()) return;
    glNamedBufferData(vbo_, GLsizeiptr(segments.size() * sizeof(glm::vec3)), segments.data(), GL_STREAM_DRAW);
    program_.use();
    program_.set("viewProjection", frame.viewProjection);
    program_.set("lineColour", colour);
    glBindVertexArray(vao_);
    glDrawArrays(GL_LINES, 0, GLsizei(segments.size()));
}

namespace {

// One overlay vertex: pixel position from the top left, colour, the colour-map value (-1..1) or
// kPlain for a plain colour or kText for a glyph, and the glyph texture's coordinates.
struct OverlayVertex {
    float x, y;
    float r, g, b, a;
    float value;
    float u, v;
};
constexpr float kPlain = -2.0f, kText = -3.0f;

void addRect(std::vector<OverlayVertex>& out, float x0, float y0, float x1, float y1, glm::vec4 c, float v0 = kPlain,
             float v1 = kPlain) {
    const OverlayVertex a{x0, y0, c.r, c.g, c.b, c.a, v0, 0, 0}, b{x1, y0, c.r, c.g, c.b, c.a, v0, 0, 0};
    const OverlayVertex d{x0, y1, c.r, c.g, c.b, c.a, v1, 0, 0}, e{x1, y1, c.r, c.g, c.b, c.a, v1, 0, 0};
    out.insert(out.end(), {a, b, e, a, e, d});
}

// Text at (x, y) (top left) in the atlas's font, with a dark shadow.
void addText(std::vector<OverlayVertex>& out, const GlyphAtlas& atlas, float x, float y, const std::string& text) {
    for (const auto& [offset, c] : {std::pair{1.0f, glm::vec4(0.0f, 0.0f, 0.0f, 0.8f)}, std::pair{0.0f, glm::vec4(0.95f)}}) {
        for (const GlyphAtlas::Quad& q : atlas.layout(text, x + offset, y + offset + atlas.ascent())) {
            const OverlayVertex a{q.x0, q.y0, c.r, c.g, c.b, c.a, kText, q.u0, q.v0}, b{q.x1, q.y0, c.r, c.g, c.b, c.a, kText, q.u1, q.v0};
            const OverlayVertex d{q.x0, q.y1, c.r, c.g, c.b, c.a, kText, q.u0, q.v1}, e{q.x1, q.y1, c.r, c.g, c.b, c.a, kText, q.u1, q.v1};
            out.insert(out.end(), {a, b, e, a, e, d});
        }
    }
}

// The built-in fallback: `scale` times stb_easy_font's 7-pixel glyphs, with a dark shadow.
void addEasyText(std::vector<OverlayVertex>& out, float x, float y, float scale, const std::string& text) {
    static char quads[64 * 1024];
    std::string copy = text;
    const int count = stb_easy_font_print(0.0f, 0.0f, copy.data(), nullptr, quads, sizeof(quads));
    for (const auto& [offset, colour] : {std::pair{1.0f, glm::vec4(0.0f, 0.0f, 0.0f, 0.8f)}, std::pair{0.0f, glm::vec4(0.95f)}}) {
        for (int q = 0; q < count; ++q) {
            const float* v = reinterpret_cast<const float*>(quads + q * 64); // 4 vertices of x, y, z, rgba8
            addRect(out, x + offset + v[0] * scale, y + offset + v[1] * scale, x + offset + v[8] * scale, y + offset + v[9] * scale,
                    colour);
        }
    }
}

float easyTextWidth(const std::string& text, float scale) {
    std::string copy = text;
    return float(stb_easy_font_width(copy.data())) * scale;
}

std::string label(float value) {
    char text[32];
    std::snprintf(text, sizeof(text), "%+.3g", double(value));
    return value == 0.0f ? "0" : text;
}

} // namespace

ColourBarRenderer::ColourBarRenderer() : program_("overlay.vert", "overlay.frag") {
    glCreateVertexArrays(1, &vao_);
    glCreateBuffers(1, &vbo_);
    glVertexArrayVertexBuffer(vao_, 0, vbo_, 0, sizeof(OverlayVertex));
    const GLuint sizes[4] = {2, 4, 1, 2};
    const GLuint offsets[4] = {offsetof(OverlayVertex, x), offsetof(OverlayVertex, r), offsetof(OverlayVertex, value), offsetof(OverlayVertex, u)};
    for (GLuint a = 0; a < 4; ++a) {
        glEnableVertexArrayAttrib(vao_, a);
        glVertexArrayAttribFormat(vao_, a, GLint(sizes[a]), GL_FLOAT, GL_FALSE, offsets[a]);
        glVertexArrayAttribBinding(vao_, a, 0);
    }
}

ColourBarRenderer::~ColourBarRenderer() {
    glDeleteBuffers(1, &vbo_);
    glDeleteVertexArrays(1, &vao_);
}

void ColourBarRenderer::draw(glm::ivec2 size, const std::vector<ColourBar>& bars, int colormap, const char* units) {
    // Each bar is 45% of the height, the first at the right edge and each next one left of the
    // last one's values; marks and text larger on big frames.
    const float scale = size.y >= 400 ? 2.0f : 1.0f;
    const float margin = 10.0f * scale, width = 8.0f * scale;
    const float height = 0.45f * float(size.y);
    const float y0 = 0.5f * (float(size.y) - height), y1 = y0 + height;
    const bool font = !uiFontPath().empty() && atlas_.load(uiFontPath(), std::clamp(std::round(float(size.y) / 42.0f), 11.0f, 26.0f));
    const float lineHeight = font ? atlas_.pixelHeight() : 9.0f * scale;
    auto textWidth = [&](const std::string& line) { return font ? atlas_.width(line) : easyTextWidth(line, scale); };
    auto text = [&](std::vector<OverlayVertex>& out, float right, float top, const std::string& line) {
        if (font) addText(out, atlas_, right - atlas_.width(line), top, line);
        else addEasyText(out, right - easyTextWidth(line, scale), top + scale, scale, line);
    };
    std::vector<OverlayVertex> vertices;
    // The heading over the first bar; the bars' names (when they are named) on the line below it;
    // a third of a line clear of the top value's label, which the heading touched on small frames.
    const bool named = std::any_of(bars.begin(), bars.end(), [](const ColourBar& b) { return b.name != nullptr; });
    const float headingTop = y0 - (named ? 4.0f : 2.9f) * lineHeight;
    const float right = float(size.x) - margin;
    text(vertices, right, headingTop, "signed distance");
    text(vertices, right, headingTop + 1.1f * lineHeight, units);
    float x1 = right;
    for (const ColourBar& bar : bars) {
        const float x0 = x1 - width;
        addRect(vertices, x0 - 1.0f, y0 - 1.0f, x1 + 1.0f, y1 + 1.0f, glm::vec4(0.0f, 0.0f, 0.0f, 0.8f));
        addRect(vertices, x0, y0, x1, y1, glm::vec4(1.0f), 1.0f, -1.0f); // top outside (range.y), bottom inside (range.x)
        const float ticks[3] = {bar.range.y, 0.0f, bar.range.x};
        float widest = 0.0f;
        for (int t = 0; t < 3; ++t) {
            if (t == 2 && bar.range.x == 0.0f) continue; // nothing inside: the bottom is 0, as the middle
            const float y = y0 + height * float(t) / 2.0f;
            addRect(vertices, x0 - 3.0f * scale, y - 0.5f * scale, x0, y + 0.5f * scale, glm::vec4(0.95f));
            text(vertices, x0 - 5.0f * scale, y - 0.5f * lineHeight, label(ticks[t]));
            widest = std::max(widest, textWidth(label(ticks[t])));
        }
        if (bar.name) text(vertices, x1, y0 - 1.8f * lineHeight, bar.name);
        x1 = x0 - 5.0f * scale - std::max(widest, bar.name ? textWidth(bar.name) - width : 0.0f) - 2.0f * margin;
    }
    glNamedBufferData(vbo_, GLsizeiptr(vertices.size() * sizeof(OverlayVertex)), vertices.data(), GL_STREAM_DRAW);
    program_.use();
    program_.set("viewport", glm::vec2(size));
    program_.set("colormap", colormap);
    if (font) {
        glBindTextureUnit(0, atlas_.texture());
        program_.set("glyphs", 0);
    }
    glBindVertexArray(vao_);
    glDrawArrays(GL_TRIANGLES, 0, GLsizei(vertices.size()));
}

} // namespace sdfgen::render
