#version 450 core
// The slice plane: the polygon where the plane cuts the field's box (3 to 6 corners, a fan),
// computed on the CPU for any orientation.
uniform mat4 viewProjection;
uniform vec3 boxMin;
uniform vec3 boxSize;
uniform vec3 corners[6];

out vec3 vUvw; // texture coordinate in the field

void main() {
    vec3 p = corners[gl_VertexID];
    vUvw = (p - boxMin) / boxSize;
    gl_Position = viewProjection * vec4(p, 1.0);
}
