// Exact distance from grid samples to a triangle mesh (src/gpu/gl_device.cpp), in the mesh's local
// coordinates (samples at localPosition), scaled to world units at the end.
//
// The mesh is a binary BVH flattened into SSBOs (src/gpu/flat_bvh.hpp): nodes (box, children
// adjacent or a leaf's triangle range) and triangles in leaf order, each set up by FlatBvh for this
// search's own float distance (`precise`: no fused multiply-adds, the order of operations as
// written). Each invocation walks the tree nearest child first with a short
// stack, pruned by its best squared distance so far; as on the CPU, ties are explored and go to the
// lower triangle index, so the answer does not depend on the seeds or the order. Pass `seedPass` =
// 1 finds the nearest triangle of one sample per 4x4x4 brick (its first corner); the main pass
// starts every sample of the brick from the distance to that triangle (the field is 1-Lipschitz,
// so the bound is tight and prunes most of the tree). The winner is re-measured in double as
// src/core/mesh/geometry.cpp's closestPointOnTriangle measures it (`precise`: no fused multiply-adds,
// as that file is compiled). Where the GPU's float and double operations are IEEE, as on Mesa's
// llvmpipe, the distances and nearest triangles are the CPU's bit for bit.
//
// Included by nearest.comp (unsigned) and nearest_signed.comp, which set SIGN_BY_PSEUDONORMAL: the
// signed variant's extra work is compiled only into it. There the distance is negated inside by the angle-weighted pseudonormal of
// the closest feature, as the CPU signs (sdfgen/device.hpp, PseudonormalSign). The CPU's 8-wide
// search computes its float distances otherwise (in each triangle's own frame), so of nearly equal
// triangles it may keep another one: the walk then also opens every triangle within `tie` (2^-17
// of the coordinates' magnitude, far above both searches' rounding) of the nearest and notes the
// side each one's closest feature tells, and the sample is signed only when all of them tell the
// same side, each by more than the rounding of its product; otherwise it is NaN and the CPU
// decides it.
layout(local_size_x = 64) in;

struct Node {
    vec4 lo; // box minimum; w: first child (interior) or first triangle (leaf), as uint bits
    vec4 hi; // box maximum; w: triangle count (0 for interior nodes), as uint bits
};
// A triangle set up for the float distance (FlatBvh::Triangle), plus the corners for the double re-measure.
struct Triangle {
    vec4 a;      // corner a; w: 1 / |ab|² (0 for a zero-length edge)
    vec4 ab;     // b - a; w: 1 / |bc|²
    vec4 ac;     // c - a; w: 1 / |ca|²
    vec4 normal; // unit face normal; w: the mesh's triangle index, as uint bits
    vec4 inAB;   // in-plane normals of the edges, pointing inwards (w unused)
    vec4 inBC;
    vec4 inCA;
    vec4 b;      // corners b and c (w unused)
    vec4 c;
};

layout(std430, binding = 0) readonly buffer Nodes { Node nodes[]; };
layout(std430, binding = 1) readonly buffer Triangles { Triangle triangles[]; };
// Sample coordinates: x for each i, then y for each j, then z for each k, in float (as the CPU
// rounds them for the search) and in double (for the re-measure).
layout(std430, binding = 2) readonly buffer Samples { float samples[]; };
layout(std430, binding = 6) readonly buffer ExactSamples { double exactSamples[]; };
layout(std430, binding = 3) buffer Seeds { uint seeds[]; }; // one triangle (leaf order) per brick of the layer
layout(std430, binding = 4) writeonly buffer Distances { float distances[]; };
// 7 pseudonormals per mesh triangle (face, edges AB, BC, CA, vertices A, B, C), 3 doubles each.
layout(std430, binding = 5) readonly buffer Pseudonormals { double pseudonormals[]; };

uniform ivec3 dims;       // the whole grid
uniform int slabZ;        // first z layer of the slab the output buffers hold
uniform int firstBrickZ;  // the layer of bricks this dispatch covers
uniform int seedPass;
uniform double unit;      // world units per local unit
const bool kSign = SIGN_BY_PSEUDONORMAL != 0;
uniform int flipped;      // the mesh is inside out: inside and outside swap
uniform float meshMagnitude; // the largest |coordinate| of the mesh (local units)

const int kStack = 32; // the tree is built at most 30 levels deep (FlatBvh)

float boxDistance2(vec3 p, vec3 lo, vec3 hi) {
    precise vec3 d = max(max(lo - p, p - hi), vec3(0.0));
    precise float d2 = d.x * d.x + d.y * d.y + d.z * d.z;
    return d2;
}

float dot3(vec3 u, vec3 v) {
    precise float d = u.x * v.x + u.y * v.y + u.z * v.z;
    return d;
}

float segmentDistance2(vec3 q, vec3 e, float invLength2) {
    precise float s = clamp(dot3(q, e) * invLength2, 0.0, 1.0);
    precise vec3 d = q - s * e;
    precise float d2 = d.x * d.x + d.y * d.y + d.z * d.z;
    return d2;
}

// The squared distance in float: the height above the plane inside the prism over the face, else
// the nearest of the three edges.
float triangleDistance2(vec3 p, uint t) {
    const Triangle tri = triangles[t];
    precise vec3 pa = p - tri.a.xyz;
    precise vec3 pb = pa - tri.ab.xyz;
    precise vec3 pc = pa - tri.ac.xyz;
    if (dot3(pa, tri.inAB.xyz) >= 0.0 && dot3(pb, tri.inBC.xyz) >= 0.0 && dot3(pc, tri.inCA.xyz) >= 0.0) {
        precise float height = dot3(pa, tri.normal.xyz);
        precise float h2 = height * height;
        return h2;
    }
    precise vec3 bc = tri.ac.xyz - tri.ab.xyz;
    return min(segmentDistance2(pa, tri.ab.xyz, tri.a.w),
               min(segmentDistance2(pb, bc, tri.ab.w), segmentDistance2(pc, -tri.ac.xyz, tri.ac.w)));
}

double dot3(dvec3 u, dvec3 v) {
    precise double d = u.x * v.x + u.y * v.y + u.z * v.z;
    return d;
}

double distance2To(dvec3 p, dvec3 q) {
    precise dvec3 d = p - q;
    return dot3(d, d);
}

double distance2To(dvec3 p, dvec3 q, out dvec3 closest) {
    closest = q;
    return distance2To(p, q);
}

// src/core/mesh/geometry.cpp's closestPointOnTriangle, operation for operation: the squared distance,
// the closest point q and its feature (as TriangleFeature: 0 face, 1-3 edges AB, BC, CA, 4-6
// vertices A, B, C).
double closestOnTriangle(dvec3 p, dvec3 a, dvec3 b, dvec3 c, out dvec3 q, out int feature) {
    precise dvec3 ab = b - a;
    precise dvec3 ac = c - a;
    precise dvec3 ap = p - a;
    const double d1 = dot3(ab, ap), d2 = dot3(ac, ap);
    feature = 4;
    if (d1 <= 0.0 && d2 <= 0.0) return distance2To(p, a, q);
    precise dvec3 bp = p - b;
    const double d3 = dot3(ab, bp), d4 = dot3(ac, bp);
    feature = 5;
    if (d3 >= 0.0 && d4 <= d3) return distance2To(p, b, q);
    precise double vc = d1 * d4 - d3 * d2;
    precise double d1d3 = d1 - d3;
    feature = 1;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1d3 > 0.0) {
        precise dvec3 onAB = a + ab * (d1 / d1d3);
        return distance2To(p, onAB, q);
    }
    precise dvec3 cp = p - c;
    const double d5 = dot3(ab, cp), d6 = dot3(ac, cp);
    feature = 6;
    if (d6 >= 0.0 && d5 <= d6) return distance2To(p, c, q);
    precise double vb = d5 * d2 - d1 * d6;
    precise double d2d6 = d2 - d6;
    feature = 3;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2d6 > 0.0) {
        precise dvec3 onCA = a + ac * (d2 / d2d6);
        return distance2To(p, onCA, q);
    }
    precise double va = d3 * d6 - d5 * d4;
    precise double d4d3 = d4 - d3;
    precise double d5d6 = d5 - d6;
    precise double both = d4d3 + d5d6;
    feature = 2;
    if (va <= 0.0 && d4d3 >= 0.0 && d5d6 >= 0.0 && both > 0.0) {
        precise dvec3 onBC = b + (c - b) * (d4d3 / both);
        return distance2To(p, onBC, q);
    }
    // glm::cross: (y z' - y' z, z x' - z' x, x y' - x' y).
    precise dvec3 n = dvec3(ab.y * ac.z - ac.y * ab.z, ab.z * ac.x - ac.z * ab.x, ab.x * ac.y - ac.x * ab.y);
    const double nn = dot3(n, n);
    precise double small = 1e-24LF * dot3(ab, ab) * dot3(ac, ac);
    feature = 0;
    if (nn > small) {
        precise dvec3 onFace = p - n * (dot3(ap, n) / nn);
        return distance2To(p, onFace, q);
    }
    // A (nearly) zero-area triangle: its nearest point is on one of its edges.
    feature = 4;
    double best = distance2To(p, a, q);
    const dvec3 corners[3] = dvec3[3](a, b, c);
    const int edges[3] = int[3](1, 2, 3);
    for (int e = 0; e < 3; ++e) {
        const dvec3 s = corners[e];
        precise dvec3 d = corners[(e + 1) % 3] - s;
        const double len2 = dot3(d, d);
        precise dvec3 ps = p - s;
        const double t = len2 > 0.0 ? clamp(dot3(ps, d) / len2, 0.0LF, 1.0LF) : 0.0LF;
        precise dvec3 onEdge = s + d * t;
        const double candidate = distance2To(p, onEdge);
        if (candidate < best) {
            best = candidate;
            q = onEdge;
            feature = edges[e];
        }
    }
    return best;
}

uint meshIndex(uint t) { return floatBitsToUint(triangles[t].normal.w); }

vec3 samplePosition(ivec3 s) { return vec3(samples[s.x], samples[dims.x + s.y], samples[dims.x + dims.y + s.z]); }
dvec3 exactSamplePosition(ivec3 s) {
    return dvec3(exactSamples[s.x], exactSamples[dims.x + s.y], exactSamples[dims.x + dims.y + s.z]);
}

double maxAbs(dvec3 v) { return max(abs(v.x), max(abs(v.y), abs(v.z))); }

// The side of p that triangle t's closest feature tells: 1 inside ((p - q)·n < 0, swapped when
// flipped), -1 outside, 0 when the product is within its rounding (a CPU's fused multiply-adds, a
// device's doubles) of zero. Sets d2 to the exact squared distance.
int pseudonormalSide(dvec3 p, uint t, out double d2) {
    const Triangle tri = triangles[t];
    dvec3 q;
    int feature;
    d2 = closestOnTriangle(p, dvec3(tri.a.xyz), dvec3(tri.b.xyz), dvec3(tri.c.xyz), q, feature);
    const int base = int(meshIndex(t)) * 21 + feature * 3;
    const dvec3 n = dvec3(pseudonormals[base], pseudonormals[base + 1], pseudonormals[base + 2]);
    precise dvec3 d = p - q;
    const double product = dot3(d, n);
    precise double rounding = 1e-12LF * (maxAbs(p) + maxAbs(q)) * (abs(n.x) + abs(n.y) + abs(n.z));
    if (abs(product) <= rounding) return 0;
    return ((product < 0.0) != (flipped != 0)) ? 1 : -1;
}

// The pruning bound for a best squared distance so far: best2 itself, or with `tie` >= 0 (signing)
// everything within tie of it, widened by a few ulps for its own rounding.
float reachOf(float best2, float tie) {
    if (tie < 0.0) return best2;
    precise float r = sqrt(best2) + tie;
    precise float r2 = r * r * 1.000001;
    return r2;
}

// Nearest-first walk from the root; `best2` and `best` (a triangle in leaf order) are the bound
// the walk starts from and its result. Boxes as near as the bound are still opened, and a
// triangle as near as the best replaces it when its mesh index is lower (the CPU's tie rule).
// With `tie` >= 0 (signing) the walk also opens everything within tie of the best and, for each triangle
// there, notes the side its closest feature tells: `sideNearest` holds the least float squared
// distance of a triangle telling inside (x), outside (y) and undecided (z).
void walk(vec3 p, dvec3 exactP, float tie, inout float best2, inout uint best, inout vec3 sideNearest) {
    uint stackNode[kStack];
    float stackDistance[kStack];
    int top = 0;
    uint node = 0u;
    uint bestIndex = meshIndex(best);
    float bound = reachOf(best2, tie);
    if (boxDistance2(p, nodes[0].lo.xyz, nodes[0].hi.xyz) > bound) return;
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
            if (nearDistance <= bound) {
                if (farDistance <= bound) {
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
                const float d2 = triangleDistance2(p, t);
                if (d2 > bound) continue;
                if (d2 <= best2) {
                    const uint index = meshIndex(t);
                    if (d2 < best2 || index < bestIndex) {
                        best2 = d2;
                        best = t;
                        bestIndex = index;
                        bound = reachOf(best2, tie);
                    }
                }
                if (kSign && tie >= 0.0 && d2 < max(sideNearest.x, max(sideNearest.y, sideNearest.z))) {
                    double exactD2;
                    const int side = pseudonormalSide(exactP, t, exactD2);
                    if (side == 1) sideNearest.x = min(sideNearest.x, d2);
                    else if (side == -1) sideNearest.y = min(sideNearest.y, d2);
                    else sideNearest.z = min(sideNearest.z, d2);
                }
            }
        }
        if (descended) continue;
        // Pop the nearest pending subtree that can still hold something within the bound.
        bool found = false;
        while (top > 0) {
            --top;
            if (stackDistance[top] <= bound) {
                node = stackNode[top];
                found = true;
                break;
            }
        }
        if (!found) return;
    }
}

void main() {
    // Dispatched over one layer of bricks (x, y), layer firstBrickZ.
    const ivec3 bricks = (dims + 3) / 4;
    vec3 sideNearest = vec3(1.0 / 0.0);
    if (seedPass == 1) {
        const ivec3 b = ivec3(gl_GlobalInvocationID.x, gl_WorkGroupID.y, firstBrickZ);
        if (b.x >= bricks.x) return;
        const ivec3 corner = min(b * 4, dims - 1);
        float best2 = 1.0 / 0.0;
        uint best = 0u;
        walk(samplePosition(corner), exactSamplePosition(corner), -1.0, best2, best, sideNearest);
        seeds[b.x + bricks.x * b.y] = best;
        return;
    }
    // One work group per brick, one invocation per sample.
    const ivec3 b = ivec3(gl_WorkGroupID.x, gl_WorkGroupID.y, firstBrickZ);
    const uint lane = gl_LocalInvocationID.x;
    const ivec3 s = b * 4 + ivec3(lane & 3u, (lane >> 2) & 3u, lane >> 4);
    if (any(greaterThanEqual(s, dims))) return;
    const vec3 p = samplePosition(s);
    const dvec3 exactP = exactSamplePosition(s);
    uint best = seeds[b.x + bricks.x * b.y];
    // The seed is a real triangle, so its distance bounds the search; widened by a few ulps (as on
    // the CPU) so that its rounding never hides a nearer triangle.
    precise float best2 = triangleDistance2(p, best) * 1.000001;
    // 2^-17 of the coordinates' magnitude: the rounding of both sides' float distances is far below.
    const float tie = kSign ? 7.62939453125e-6 * max(meshMagnitude, max(abs(p.x), max(abs(p.y), abs(p.z)))) : -1.0;
    walk(p, exactP, tie, best2, best, sideNearest);
    const Triangle t = triangles[best];
    dvec3 q;
    int feature;
    const double d2 = closestOnTriangle(exactP, dvec3(t.a.xyz), dvec3(t.b.xyz), dvec3(t.c.xyz), q, feature);
    precise double world = sqrt(d2) * unit;
    float value = float(world);
    if (kSign) {
        const float reach = reachOf(best2, tie);
        const bool inside = sideNearest.x <= reach, outside = sideNearest.y <= reach, unsure = sideNearest.z <= reach;
        if (inside && !outside && !unsure) value = -value;
        else if (!outside || inside || unsure) value = uintBitsToFloat(0x7fc00000u); // NaN: left to the CPU
    }
    distances[uint(s.x) + uint(dims.x) * (uint(s.y) + uint(dims.y) * uint(s.z - slabZ))] = value;
}
