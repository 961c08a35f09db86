#version 450 core
in vec4 vColour;
in float vValue;
in vec2 vUv;
out vec4 colour;

uniform sampler2D glyphs; // the font's glyph coverage (R8)

#include "colormap.glsl"

void main() {
    if (vValue < -2.5) colour = vec4(vColour.rgb, vColour.a * texture(glyphs, vUv).r); // text
    else colour = vValue < -1.5 ? vColour : vec4(colourOf(vValue), 1.0);
}
