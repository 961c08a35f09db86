#version 450 core
out vec4 colour;
uniform vec4 lineColour;

void main() { colour = lineColour; }
