#version 450 core
// Exact unsigned distance from grid samples to a triangle mesh (src/gpu/gl_device.cpp).
//
// The mesh is a binary BVH flattened into SSBOs: nodes (box, children adjacent or a leaf's
// triangle range) and triangles in leaf order. Each invocation walks it nearest child first with a
// short stack, pruned by its best squared distance so far. Pass `seedPass` = 1 finds the nearest
// triangle of one sample per 4x4x4 brick (its first corner); the main pass starts every sample of
// the brick from the exact distance to that triangle (the field is 1-Lipschitz, so the bound is
// tight and prunes most of the tree). The winner is re-measured in double, as the CPU does.
layout(local_size_x = 64) in;

struct Node {
    vec4 lo; // box minimum; w: first child (interior) or first triangle (leaf), as uint bits
    vec4 hi; // box maximum; w: triangle count (0 for interior nodes), as uint bits
};
struct Triangle {
    vec4 a; // w: the mesh's triangle index, as uint bits
    vec4 b;
    vec4 c;
};

layout(std430, binding = 0) readonly buffer Nodes { Node nodes[]; };
layout(std430, binding = 1) readonly buffer Triangles { Triangle triangles[]; };
// Sample coordinates: x for each i, then y for each j, then z for each k (as the CPU rounds them).
layout(std430, binding = 2) readonly buffer Samples { float samples[]; };
layout(std430, binding = 3) buffer Seeds { uint seeds[]; }; // one triangle (leaf order) per brick of the layer
layout(std430, binding = 4) writeonly buffer Distances { float distances[]; };
layout(std430, binding = 5) writeonly buffer Nearest { uint nearestTriangle[]; };

uniform ivec3 dims;       // the whole grid
uniform int slabZ;        // first z layer of the slab the output buffers hold
uniform int firstBrickZ;  // the layer of bricks this dispatch covers
uniform int seedPass;

const int kStack = 32; // the tree is built at most 30 levels deep (FlatBvh)

float boxDistance2(vec3 p, vec3 lo, vec3 hi) {
    const vec3 d = max(max(lo - p, p - hi), vec3(0.0));
    return dot(d, d);
}

// Squared distance from p to segment s + t d, t in [0, 1].
float segmentDistance2(vec3 p, vec3 s, vec3 d) {
    const float len2 = dot(d, d);
    const float t = len2 > 0.0 ? clamp(dot(p - s, d) / len2, 0.0, 1.0) : 0.0;
    const vec3 q = p - (s + d * t);
    return dot(q, q);
}

// Squared distance from p to triangle (a, b, c), by Voronoi regions (Ericson 5.1.5), in float,
// with the same guards as the double version below so that slivers never give NaN.
float triangleDistance2(vec3 p, vec3 a, vec3 b, vec3 c) {
    const vec3 ab = b - a, ac = c - a, ap = p - a;
    const float d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return dot(ap, ap);
    const vec3 bp = p - b;
    const float d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) return dot(bp, bp);
    const float vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 - d3 > 0.0) {
        const vec3 q = ap - ab * (d1 / (d1 - d3));
        return dot(q, q);
    }
    const vec3 cp = p - c;
    const float d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) return dot(cp, cp);
    const float vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 - d6 > 0.0) {
        const vec3 q = ap - ac * (d2 / (d2 - d6));
        return dot(q, q);
    }
    const float va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 && (d4 - d3) + (d5 - d6) > 0.0) {
        const vec3 q = bp - (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
        return dot(q, q);
    }
    const float sum = va + vb + vc;
    if (sum > 0.0) {
        const vec3 q = ap - ab * (vb / sum) - ac * (vc / sum);
        return dot(q, q);
    }
    // A (nearly) zero-area triangle: its nearest point is on one of its edges.
    return min(segmentDistance2(p, a, ab), min(segmentDistance2(p, b, c - b), segmentDistance2(p, a, ac)));
}

// The CPU's closestPointOnTriangle (src/core/geometry.cpp), in double: the squared distance.
double triangleDistance2Exact(dvec3 p, dvec3 a, dvec3 b, dvec3 c) {
    const dvec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return dot(ap, ap);
    const dvec3 bp = p - b;
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) return dot(bp, bp);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 - d3 > 0.0) {
        const dvec3 q = p - (a + ab * (d1 / (d1 - d3)));
        return dot(q, q);
    }
    const dvec3 cp = p - c;
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) return dot(cp, cp);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 - d6 > 0.0) {
        const dvec3 q = p - (a + ac * (d2 / (d2 - d6)));
        return dot(q, q);
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 && (d4 - d3) + (d5 - d6) > 0.0) {
        const dvec3 q = p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
        return dot(q, q);
    }
    const dvec3 n = cross(ab, ac);
    const double nn = dot(n, n);
    if (nn > 1e-24LF * dot(ab, ab) * dot(ac, ac)) {
        const double along = dot(ap, n) / nn;
        const dvec3 q = n * along;
        return dot(q, q);
    }
    // A (nearly) zero-area triangle: its nearest point is on one of its edges.
    double best = dot(ap, ap);
    const dvec3 corners[3] = dvec3[3](a, b, c);
    for (int e = 0; e < 3; ++e) {
        const dvec3 s = corners[e], d = corners[(e + 1) % 3] - s;
        const double len2 = dot(d, d);
        const double t = len2 > 0.0 ? clamp(dot(p - s, d) / len2, 0.0LF, 1.0LF) : 0.0LF;
        const dvec3 q = p - (s + d * t);
        best = min(best, dot(q, q));
    }
    return best;
}

// Nearest-first walk from the root; `best2` and `best` (a triangle in leaf order) are the bound
// the walk starts from and its result.
void walk(vec3 p, inout float best2, inout uint best) {
    uint stackNode[kStack];
    float stackDistance[kStack];
    int top = 0;
    uint node = 0u;
    if (boxDistance2(p, nodes[0].lo.xyz, nodes[0].hi.xyz) >= best2) return;
    while (true) {
        const Node n = nodes[node];
        const uint count = floatBitsToUint(n.hi.w);
        bool descended = false;
        if (count == 0u) {
            uint near = floatBitsToUint(n.lo.w), far = near + 1u;
            float nearDistance = boxDistance2(p, nodes[near].lo.xyz, nodes[near].hi.xyz);
            float farDistance = boxDistance2(p, nodes[far].lo.xyz, nodes[far].hi.xyz);
            if (farDistance < nearDistance) {
                const uint t = near; near = far; far = t;
                const float d = nearDistance; nearDistance = farDistance; farDistance = d;
            }
            if (nearDistance < best2) {
                if (farDistance < best2) {
                    stackNode[top] = far;
                    stackDistance[top] = farDistance;
                    ++top;
                }
                node = near;
                descended = true;
            }
        } else {
            const uint first = floatBitsToUint(n.lo.w);
            for (uint t = first; t < first + count; ++t) {
                const float d2 = triangleDistance2(p, triangles[t].a.xyz, triangles[t].b.xyz, triangles[t].c.xyz);
                if (d2 < best2) {
                    best2 = d2;
                    best = t;
                }
            }
        }
        if (descended) continue;
        // Pop the nearest pending subtree that can still hold something closer.
        bool found = false;
        while (top > 0) {
            --top;
            if (stackDistance[top] < best2) {
                node = stackNode[top];
                found = true;
                break;
            }
        }
        if (!found) return;
    }
}

vec3 samplePosition(ivec3 s) { return vec3(samples[s.x], samples[dims.x + s.y], samples[dims.x + dims.y + s.z]); }

void main() {
    // Dispatched over one layer of bricks (x, y), layer firstBrickZ.
    const ivec3 bricks = (dims + 3) / 4;
    if (seedPass == 1) {
        const ivec3 b = ivec3(gl_GlobalInvocationID.x, gl_WorkGroupID.y, firstBrickZ);
        if (b.x >= bricks.x) return;
        float best2 = 1.0 / 0.0;
        uint best = 0u;
        walk(samplePosition(min(b * 4, dims - 1)), best2, best);
        seeds[b.x + bricks.x * b.y] = best;
        return;
    }
    // One work group per brick, one invocation per sample.
    const ivec3 b = ivec3(gl_WorkGroupID.x, gl_WorkGroupID.y, firstBrickZ);
    const uint lane = gl_LocalInvocationID.x;
    const ivec3 s = b * 4 + ivec3(lane & 3u, (lane >> 2) & 3u, lane >> 4);
    if (any(greaterThanEqual(s, dims))) return;
    const vec3 p = samplePosition(s);
    uint best = seeds[b.x + bricks.x * b.y];
    float best2 = triangleDistance2(p, triangles[best].a.xyz, triangles[best].b.xyz, triangles[best].c.xyz);
    walk(p, best2, best);
    const Triangle t = triangles[best];
    const double d2 = triangleDistance2Exact(dvec3(p), dvec3(t.a.xyz), dvec3(t.b.xyz), dvec3(t.c.xyz));
    const uint index = uint(s.x) + uint(dims.x) * (uint(s.y) + uint(dims.y) * uint(s.z - slabZ));
    distances[index] = float(sqrt(d2));
    nearestTriangle[index] = floatBitsToUint(t.a.w);
}
