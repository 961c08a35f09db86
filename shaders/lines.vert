#version 450 core
// Line segments in world space (the field's box, the probe's marker).
layout(location = 0) in vec3 position;
uniform mat4 viewProjection;

void main() { gl_Position = viewProjection * vec4(position, 1.0); }
