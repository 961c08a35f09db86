#version 450 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;

uniform mat4 viewProjection;

out vec3 vPosition;
out vec3 vNormal;

void main() {
    vPosition = position;
    vNormal = normal;
    gl_Position = viewProjection * vec4(position, 1.0);
}
