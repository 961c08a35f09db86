#version 450 core
// The winding number's integer part, step 1 of 2 (src/gpu/gl_device.cpp): each closed-surface
// triangle's signed crossings with the rows of samples (lines parallel to x) it covers.
//
// This reproduces src/core/sign/winding_sign.cpp's crossing test operation for operation, in double, with no
// fused multiply-adds (`precise`; the CPU file is compiled with -ffp-contract=off): a robust 2D
// point-in-triangle test with symbolic tie-breaking, so that a row through a shared edge or
// vertex crosses exactly one of the triangles, and the crossing's x from barycentric weights. A
// crossing ahead of a sample (x greater than the sample's) adds its orientation times the
// triangle's weight (its copies; a cap shared by equal loops) to the sample's winding number: it is added to counts[row][n], n = how many samples of the row lie before it,
// and winding_prefix.comp sums them.
layout(local_size_x = 8, local_size_y = 4) in;

layout(std430, binding = 0) readonly buffer Corners { double corners[]; };  // 9 per triangle
layout(std430, binding = 5) readonly buffer Weights { int weights[]; };     // how often each triangle counts
// One per work group: the triangle and the first row (j, k) of its 8x4 tile of candidate rows;
// w: the last candidate row, j in the low 16 bits, k in the high 16 bits.
layout(std430, binding = 1) readonly buffer Tiles { uvec4 tiles[]; };
// Sample coordinates in the mesh's local units, x per i, y per j, z per k, in double: rows pass
// through the samples' own (y, z), as on the CPU, and a crossing is ahead of a sample by x.
layout(std430, binding = 6) readonly buffer ExactSamples { double exactSamples[]; };
layout(std430, binding = 3) buffer Counts { int counts[]; };               // (dims.x + 1) per row of the slab

uniform ivec3 dims;
uniform int slabZ;
uniform int firstTile;

// orientation2d of src/core/mesh/geometry.cpp.
int orientation2d(dvec2 u, dvec2 v, out double area) {
    precise double left = u.y * v.x;
    precise double right = u.x * v.y;
    precise double difference = left - right;
    area = difference;
    if (left > right) return 1;
    if (left < right) return -1;
    if (v.y > u.y) return 1;
    if (v.y < u.y) return -1;
    if (u.x > v.x) return 1;
    if (u.x < v.x) return -1;
    return 0;
}

void main() {
    const uvec4 tile = tiles[firstTile + int(gl_WorkGroupID.x)];
    const int j = int(tile.y) + int(gl_LocalInvocationID.x), k = int(tile.z) + int(gl_LocalInvocationID.y);
    if (j > int(tile.w & 0xffffu) || k > int(tile.w >> 16)) return;
    const int t = int(tile.x) * 9;
    const dvec3 a = dvec3(corners[t], corners[t + 1], corners[t + 2]);
    const dvec3 b = dvec3(corners[t + 3], corners[t + 4], corners[t + 5]);
    const dvec3 c = dvec3(corners[t + 6], corners[t + 7], corners[t + 8]);
    const dvec2 q = dvec2(exactSamples[dims.x + j], exactSamples[dims.x + dims.y + k]);
    // pointInTriangle2d of src/core/mesh/geometry.cpp, for q in the (y, z) projection.
    precise dvec2 pa = a.yz - q;
    precise dvec2 pb = b.yz - q;
    precise dvec2 pc = c.yz - q;
    double wa, wb, wc;
    const int sa = orientation2d(pb, pc, wa);
    if (sa == 0) return;
    if (orientation2d(pc, pa, wb) != sa) return;
    if (orientation2d(pa, pb, wc) != sa) return;
    precise double sum = wa + wb + wc;
    if (sum == 0.0) return;
    precise double ua = wa / sum;
    precise double ub = wb / sum;
    precise double uc = wc / sum;
    precise double x = ua * a.x + ub * b.x + uc * c.x;
    // How many samples of the row lie before the crossing (x increases with i).
    int lo = 0, hi = dims.x;
    while (lo < hi) {
        const int mid = (lo + hi) / 2;
        if (exactSamples[mid] < x) lo = mid + 1;
        else hi = mid;
    }
    if (lo == 0) return;
    atomicAdd(counts[((k - slabZ) * dims.y + j) * (dims.x + 1) + lo], -sa * weights[int(tile.x)]);
}
