#version 450 core
in vec4 vColour;
in float vValue;
out vec4 colour;

#include "colormap.glsl"

void main() { colour = vValue < -1.5 ? vColour : vec4(colourOf(vValue), 1.0); }
