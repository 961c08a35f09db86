#version 450 core
// The winding number's integer part, step 2 of 2: per row, each sample's winding number is the
// sum of the crossings ahead of it (winding_rows.comp put each crossing at the count of samples
// before it). One invocation per row of the slab, a suffix sum along x.
layout(local_size_x = 64) in;

layout(std430, binding = 3) readonly buffer Counts { int counts[]; };
layout(std430, binding = 4) writeonly buffer Winding { int winding[]; };

uniform ivec3 dims;
uniform int rows; // rows in the slab

void main() {
    const int row = int(gl_GlobalInvocationID.x);
    if (row >= rows) return;
    const int in0 = row * (dims.x + 1), out0 = row * dims.x;
    int ahead = 0;
    for (int i = dims.x - 1; i >= 0; --i) {
        ahead += counts[in0 + i + 1];
        winding[out0 + i] = ahead;
    }
}
