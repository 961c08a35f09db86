#version 450 core
// 2D overlays in pixels from the top left (the colour bar and its labels).
layout(location = 0) in vec2 pixel;
layout(location = 1) in vec4 vertexColour;
layout(location = 2) in float value; // -1..1 along the colour bar; below -1.5 for plain colour
uniform vec2 viewport;

out vec4 vColour;
out float vValue;

void main() {
    vColour = vertexColour;
    vValue = value;
    gl_Position = vec4(pixel.x / viewport.x * 2.0 - 1.0, 1.0 - pixel.y / viewport.y * 2.0, 0.0, 1.0);
}
