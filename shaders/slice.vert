#version 450 core
// The slice plane: a quad across the field's box at `position` (0..1) along `axis`.
uniform mat4 viewProjection;
uniform vec3 boxMin;
uniform vec3 boxSize;
uniform int axis;
uniform float position;

out vec3 vUvw; // texture coordinate in the field

void main() {
    vec2 corner = vec2(float(gl_VertexID & 1), float((gl_VertexID >> 1) & 1));
    vec3 uvw;
    if (axis == 0) uvw = vec3(position, corner.x, corner.y);
    else if (axis == 1) uvw = vec3(corner.x, position, corner.y);
    else uvw = vec3(corner.x, corner.y, position);
    vUvw = uvw;
    gl_Position = viewProjection * vec4(boxMin + uvw * boxSize, 1.0);
}
