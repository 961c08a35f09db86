#version 450 core
// Sphere tracing of the field stored as a 3D texture (trilinear). Outside the field's box the ray
// jumps straight to the box (the distance to the box is exact there); inside, it steps by the
// sampled distance. At a hit: normal from the field's gradient (central differences), Lambert
// light, soft shadows (a second march towards the light, penumbra from the closest approach)
// and ambient occlusion (the field sampled along the normal). Writes the hit's depth. `iso` offsets
// the surface: the level set field = iso. A band field's values beyond the band are the background,
// a lower bound of the distance, so stepping by them never overshoots; maxSteps allows for it.
in vec2 vNdc;
out vec4 colour;

uniform mat4 inverseViewProjection;
uniform mat4 viewProjection;
uniform sampler3D field;
uniform vec3 boxMin;
uniform vec3 boxSize;
uniform float voxel;
uniform int shadows;

uniform vec3 lightDirection; // towards the light
uniform float iso;           // the level set drawn: 0 is the surface, > 0 offset outwards
uniform vec4 cutPlane;       // points with dot(xyz, p) > w are cut away (the slice's cut; (0,0,0,1): none)
uniform int maxSteps;        // 512, more for a band field
uniform float hitDistance;   // a hit: the field under iso + hitDistance voxels
uniform float minStep;       // the shortest step, in voxels
uniform float background;    // > 0: a band field, whose values at +-background only bound the distance
uniform int capCut;          // where the cut enters the solid: a flat cap (else nothing: the slice is there)

vec2 boxHits(vec3 origin, vec3 dir) {
    vec3 inv = 1.0 / dir;
    vec3 a = (boxMin - origin) * inv, b = (boxMin + boxSize - origin) * inv;
    vec3 lo = min(a, b), hi = max(a, b);
    return vec2(max(max(lo.x, lo.y), lo.z), min(min(hi.x, hi.y), hi.z));
}

float sdf(vec3 p) { return texture(field, (p - boxMin) / boxSize).r - iso; }
// Whether the field at p is a band field's background: the distance is only known to be larger.
bool beyondBand(float d) { return background > 0.0 && d + iso >= 0.999 * background; }

vec3 gradient(vec3 p) {
    float h = 0.5 * voxel;
    return vec3(sdf(p + vec3(h, 0, 0)) - sdf(p - vec3(h, 0, 0)),
                sdf(p + vec3(0, h, 0)) - sdf(p - vec3(0, h, 0)),
                sdf(p + vec3(0, 0, h)) - sdf(p - vec3(0, 0, h)));
}

float softShadow(vec3 p, vec3 n) {
    vec3 origin = p + n * (2.0 * voxel);
    vec2 span = boxHits(origin, lightDirection);
    float result = 1.0;
    float t = 0.0;
    for (int i = 0; i < 96 && t < span.y; ++i) {
        float d = sdf(origin + t * lightDirection);
        if (d < 0.1 * voxel) return 0.0;
        if (!beyondBand(d)) result = min(result, 10.0 * d / max(t, voxel)); // no penumbra from a bound
        t += max(d, 0.5 * voxel);
    }
    return clamp(result, 0.0, 1.0);
}

float ambientOcclusion(vec3 p, vec3 n) {
    float occlusion = 0.0, weight = 1.0;
    for (int i = 1; i <= 5; ++i) {
        float h = 1.5 * voxel * float(i * i);
        float d = sdf(p + n * h);
        if (!beyondBand(d)) occlusion += weight * max(h - d, 0.0) / h; // nothing known occludes beyond the band
        weight *= 0.6;
    }
    return clamp(1.0 - 0.8 * occlusion, 0.0, 1.0);
}

void main() {
    vec4 nearPoint = inverseViewProjection * vec4(vNdc, -1.0, 1.0);
    vec4 farPoint = inverseViewProjection * vec4(vNdc, 1.0, 1.0);
    vec3 eye = nearPoint.xyz / nearPoint.w; // rays from the near plane: right for orthographic views too
    vec3 dir = normalize(farPoint.xyz / farPoint.w - eye);
    vec2 span = boxHits(eye, dir);
    if (span.x >= span.y || span.y <= 0.0) discard;
    // The cut: only the part of the ray on the kept side of the plane is marched.
    float towards = dot(cutPlane.xyz, dir), side = cutPlane.w - dot(cutPlane.xyz, eye);
    bool enteredAtCut = false;
    if (towards > 0.0) {
        span.y = min(span.y, side / towards);
    } else if (towards < 0.0 && side / towards > span.x) {
        span.x = side / towards;
        enteredAtCut = true;
    } else if (towards == 0.0 && side < 0.0) {
        discard;
    }
    if (span.x >= span.y || span.y <= 0.0) discard;

    float t = max(span.x, 0.0); // outside the box: jump by the distance to it
    float eps = hitDistance * voxel;
    bool hit = false;
    for (int i = 0; i < maxSteps && t < span.y; ++i) {
        float d = sdf(eye + t * dir);
        if (d < eps) {
            hit = true;
            // Inside the solid where the cut plane enters it: a cap, or the slice shows that section.
            if (i == 0 && enteredAtCut && capCut == 0) discard;
            break;
        }
        t += max(d, minStep * voxel);
    }
    if (!hit) discard;

    vec3 p = eye + t * dir;
    bool cap = enteredAtCut && t == span.x && sdf(p) < 0.0;
    vec3 n = cap ? cutPlane.xyz : normalize(gradient(p) + vec3(1e-9)); // a cap faces the part cut away
    float light = max(dot(n, lightDirection), 0.0);
    float shadow = 1.0, occlusion = 1.0;
    if (shadows != 0 && !cap) { // the field beyond a cap is cut away: no shadow or occlusion from it
        if (light > 0.0) shadow = softShadow(p, n);
        occlusion = ambientOcclusion(p, n);
    }
    vec3 base = vec3(0.72, 0.78, 0.86);
    float sky = 0.5 + 0.5 * n.y;
    colour = vec4(base * (0.05 + 0.8 * light * shadow + 0.35 * sky * occlusion), 1.0); // never black
    // The depth written is a voxel nearer than the hit: the trilinear surface lies within about half
    // a voxel of the mesh, so where both are drawn the ray-marched one wins instead of z-fighting.
    vec4 clip = viewProjection * vec4(p - dir * voxel, 1.0);
    gl_FragDepth = clamp(clip.z / clip.w * 0.5 + 0.5, 0.0, 1.0);
}
