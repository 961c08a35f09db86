#version 450 core
// SDF colour volume: march each pixel's ray through the field's box and accumulate colour front to
// back: the colour is the colour bar's map of the signed distance d (colormap.glsl); the opacity is
// high in a shell where |d| is small, moderate inside (d < 0), and a faint haze fading outside. The ray stops at the
// opaque scene depth, so the volume sits correctly around the mesh and the other views.
in vec2 vNdc;
out vec4 colour; // premultiplied

uniform mat4 inverseViewProjection;
uniform sampler3D field;
uniform sampler2D sceneDepth;
uniform vec3 boxMin;
uniform vec3 boxSize;
uniform float voxel;
uniform float band;    // the shell's length scale
uniform float density; // overall opacity scale
uniform vec2 range;    // distances at which the colour map saturates, inside (< 0) and outside
uniform float background; // > 0: a band field, whose values at +-background only tell the side

#include "colormap.glsl"

vec2 boxHits(vec3 origin, vec3 dir) {
    vec3 inv = 1.0 / dir;
    vec3 a = (boxMin - origin) * inv, b = (boxMin + boxSize - origin) * inv;
    vec3 lo = min(a, b), hi = max(a, b);
    return vec2(max(max(lo.x, lo.y), lo.z), min(min(hi.x, hi.y), hi.z));
}

void main() {
    vec4 nearPoint = inverseViewProjection * vec4(vNdc, -1.0, 1.0);
    vec4 farPoint = inverseViewProjection * vec4(vNdc, 1.0, 1.0);
    vec3 eye = nearPoint.xyz / nearPoint.w; // rays from the near plane: right for orthographic views too
    vec3 dir = normalize(farPoint.xyz / farPoint.w - eye);
    vec2 span = boxHits(eye, dir);
    span.x = max(span.x, 0.0);

    // Stop at what is already drawn opaque.
    float depth = texelFetch(sceneDepth, ivec2(gl_FragCoord.xy), 0).r;
    if (depth < 1.0) {
        vec4 hit = inverseViewProjection * vec4(vNdc, depth * 2.0 - 1.0, 1.0);
        span.y = min(span.y, dot(hit.xyz / hit.w - eye, dir));
    }
    if (span.x >= span.y) discard;

    // Steps of 0.75 voxel through the shell and inside; far outside, where only the faint haze
    // contributes, steps grow with the distance (up to 8x), each weighted by its own length.
    float stepLength = 0.75 * voxel;
    float longest = max(max(boxSize.x, boxSize.y), boxSize.z);
    vec3 sum = vec3(0.0);
    float alpha = 0.0;
    float t = span.x;
    for (int i = 0; i < 2048 && t < span.y && alpha < 0.98; ++i) {
        float d = texture(field, (eye + (t + 0.5 * stepLength) * dir - boxMin) / boxSize).r;
        float ds = min(d > 0.0 ? clamp(0.5 * (d - 3.0 * band), stepLength, 8.0 * stepLength) : stepLength, span.y - t);
        float shell = exp(-(d * d) / (band * band));
        vec3 rgb = colourOf(scaled(d, range)); // the colour bar's map
        float sigma; // extinction per unit length
        if (d < 0.0) {
            sigma = mix(6.0, 14.0, shell) / longest;
        } else if (background > 0.0 && d >= 0.999 * background) {
            sigma = 0.0; // beyond the band outside: the distance is unknown, nothing drawn
        } else {
            float haze = exp(-d / (0.08 * longest));
            sigma = (14.0 * shell + 1.5 * haze) / longest;
        }
        float a = 1.0 - exp(-sigma * density * ds);
        sum += (1.0 - alpha) * a * rgb;
        alpha += (1.0 - alpha) * a;
        t += ds;
    }
    colour = vec4(sum, alpha);
}
