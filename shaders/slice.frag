#version 450 core
// Signed distance on the slice through the colour map (colormap.glsl), thin iso-distance contours
// every `spacing`, and a bold zero contour (the surface).
in vec3 vUvw;
out vec4 colour;

uniform sampler3D field;
uniform float spacing; // distance between contour lines
uniform vec2 range;    // distances at which the colour map saturates, inside (< 0) and outside

#include "colormap.glsl"

void main() {
    float d = texture(field, vUvw).r;
    vec3 rgb = colourOf(scaled(d, range));
    float level = d / spacing;
    float contour = 1.0 - smoothstep(0.0, 1.2, abs(fract(level - 0.5) - 0.5) / max(fwidth(level), 1e-6));
    rgb = mix(rgb, rgb * 0.55, contour);
    float zero = 1.0 - smoothstep(1.0, 2.5, abs(d) / max(fwidth(d), 1e-9));
    rgb = mix(rgb, vec3(0.02), zero);
    colour = vec4(rgb, 1.0);
}
