#version 450 core
// Infinite grid on the plane y = planeY (under the model): the pixel's ray meets the plane at p; lines are drawn from the
// screen-space derivative of p (constant width at any distance), faded with distance and at
// grazing angles, and the plane's depth is written so that the scene occludes it correctly.
in vec2 vNdc;
out vec4 colour;

uniform mat4 inverseViewProjection;
uniform mat4 viewProjection;
uniform float planeY;
uniform float cell;         // minor line spacing; major lines every 10 cells
uniform float fadeDistance; // beyond about this distance the grid is gone

float lines(vec2 coord) {
    vec2 w = max(fwidth(coord), vec2(1e-6));
    vec2 g = abs(fract(coord - 0.5) - 0.5) / w;
    return 1.0 - min(min(g.x, g.y), 1.0);
}

void main() {
    vec4 nearPoint = inverseViewProjection * vec4(vNdc, -1.0, 1.0);
    vec4 farPoint = inverseViewProjection * vec4(vNdc, 1.0, 1.0);
    vec3 origin = nearPoint.xyz / nearPoint.w; // from the near plane: right for orthographic views too
    vec3 dir = normalize(farPoint.xyz / farPoint.w - origin);
    float t = abs(dir.y) > 1e-7 ? (planeY - origin.y) / dir.y : -1.0;
    vec3 p = origin + max(t, 0.0) * dir;

    // Derivatives are taken before any discard.
    float minor = lines(p.xz / cell);
    float major = lines(p.xz / (cell * 10.0));
    float xAxis = 1.0 - min(abs(p.z) / max(fwidth(p.z) * 1.5, 1e-6), 1.0); // the line z = 0
    float zAxis = 1.0 - min(abs(p.x) / max(fwidth(p.x) * 1.5, 1e-6), 1.0); // the line x = 0

    vec3 rgb = vec3(0.55);
    float alpha = max(minor * 0.25, major * 0.5);
    rgb = mix(rgb, vec3(0.90, 0.25, 0.25), xAxis);
    alpha = max(alpha, xAxis * 0.9);
    rgb = mix(rgb, vec3(0.25, 0.45, 0.95), zAxis);
    alpha = max(alpha, zAxis * 0.9);

    float distanceFade = 1.0 - smoothstep(0.2 * fadeDistance, fadeDistance, t);
    float angleFade = smoothstep(0.0, 0.15, abs(dir.y));
    alpha *= distanceFade * angleFade;
    if (t <= 0.0 || alpha < 0.01) discard;

    colour = vec4(rgb, alpha);
    vec4 clip = viewProjection * vec4(p, 1.0);
    gl_FragDepth = clamp(clip.z / clip.w * 0.5 + 0.5, 0.0, 1.0);
}
