#version 450 core
// 2D overlays in pixels from the top left (the colour bar and its labels).
layout(location = 0) in vec2 pixel;
layout(location = 1) in vec4 vertexColour;
layout(location = 2) in float value; // -1..1 along the colour bar; -2 plain colour; -3 text
layout(location = 3) in vec2 uv;     // text: where in the glyph texture
uniform vec2 viewport;

out vec4 vColour;
out float vValue;
out vec2 vUv;

void main() {
    vColour = vertexColour;
    vValue = value;
    vUv = uv;
    gl_Position = vec4(pixel.x / viewport.x * 2.0 - 1.0, 1.0 - pixel.y / viewport.y * 2.0, 0.0, 1.0);
}
