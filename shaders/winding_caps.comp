#version 450 core
// The winding number's fractional part, step 3 of 3 for meshes with holes (src/gpu/gl_device.cpp):
// w = (the crossings ahead, from winding_prefix.comp) - (the winding number of the fans that close
// the holes, sdfgen/device.hpp's WindingFans), and each sample's side of |w| = 1/2.
//
// As src/core/sign/winding_sign.cpp's WindingCaps::inside, a node of the fans' box tree seen from p at distance
// d is worth at most area / (4π d²): nodes bounded below kSkip are summed into the doubt (up to
// kBudget in all), every other one is opened and its fans measured. The integer part leaves
// |ahead| at least ½ from ½, so the fans must move w by ½ to change a side: a doubt of
// up to 0.4 still decides most samples near the holes, and opens few nodes (on the Stanford bunny at
// res 48, 215 of 92,160 samples are left to the CPU, against 5 with 1e-3 and 0.05, at half the time). A fan's angle is its
// triangles' complex product in double (fanSolidAngle's steps) and its argument, also in double
// (atanDouble: GLSL's atan is float only, with no precision the spec guarantees), all far within
// kFanError per unit of weight. A sample is decided (1 inside, 0 outside) only when
// |w| is farther from ½ than the doubt plus those errors (w that far from both ½ and -½);
// otherwise it is 2 and the CPU measures it in double, so every sign is the CPU's.
layout(local_size_x = 64) in;

layout(std430, binding = 4) readonly buffer Winding { int winding[]; };           // the crossings ahead, per sample of the slab
layout(std430, binding = 6) readonly buffer ExactSamples { double exactSamples[]; };
layout(std430, binding = 7) readonly buffer FanNodes { double fanNodes[]; };      // 8 per node: lo xyz, hi xyz, area, unused
layout(std430, binding = 8) readonly buffer FanLinks { uvec2 fanLinks[]; };       // per node: first child or fan, 1 for leaves
layout(std430, binding = 9) readonly buffer Fans { ivec4 fans[]; };               // first point, loop length, weight, unused
layout(std430, binding = 10) readonly buffer FanPoints { double fanPoints[]; };   // per fan: centre, then its loop; 3 doubles each
layout(std430, binding = 11) writeonly buffer Sides { int sides[]; };             // per sample of the slab

uniform ivec3 dims;
uniform int slabZ;
uniform int firstSample; // of the slab, for this dispatch
uniform int slabSamples;

const double kPi = 3.14159265358979323846LF;
const double kSkip = 0.1;
const double kBudget = 0.4;
const double kFanError = 1e-5;

// atan(t) for |t| <= tan(π/8) by its Taylor series: the 20th term is below 2e-15.
double atanSeries(double t) {
    const double t2 = t * t;
    double term = t, sum = t;
    for (int n = 1; n < 20; ++n) {
        term *= -t2;
        sum += term / double(2 * n + 1);
    }
    return sum;
}

// The argument of x + iy in (-π, π], as atan(y, x), in double: reduced to [0, 1] by symmetry, then
// to [0, tan(π/8)] by atan(a) = π/4 + atan((a - 1) / (a + 1)).
double atanDouble(double y, double x) {
    if (x == 0.0 && y == 0.0) return 0.0;
    const double ax = abs(x), ay = abs(y);
    const bool steep = ay > ax;
    const double a = steep ? ax / ay : ay / ax;
    double angle = a > 0.41421356237309503 ? kPi / 4.0 + atanSeries((a - 1.0) / (a + 1.0)) : atanSeries(a);
    if (steep) angle = kPi / 2.0 - angle;
    if (x < 0.0) angle = kPi - angle;
    return y < 0.0 ? -angle : angle;
}

dvec3 fanPoint(int i) { return dvec3(fanPoints[3 * i], fanPoints[3 * i + 1], fanPoints[3 * i + 2]); }

// The fan's winding number at p (its solid angle over 4π), times its weight: src/core/sign/winding_sign.cpp's
// fanSolidAngle in double up to the final angle. onFan is set where p lies on the fan or within
// rounding of it (src/core/sign/fan_kernel.hpp's onFanTriangle, the same test): the CPU measures there.
const double kOnFanSlack = 1e-10, kOnFanReach = 1e-5;
double fanWinding(dvec3 p, ivec4 fan, inout bool onFan) {
    const dvec3 rc = fanPoint(fan.x) - p;
    const double lc = length(rc);
    const int n = fan.y;
    dvec3 rb = fanPoint(fan.x + 1) - p;
    double lb = length(rb), bc = dot(rb, rc);
    double re = 1.0, im = 0.0;
    int turns = 0;
    for (int i = 0; i < n; ++i) {
        const dvec3 ra = fanPoint(fan.x + 1 + (i + 1) % n) - p;
        const double la = length(ra), ac = dot(ra, rc);
        const double det = dot(ra, cross(rb, rc));
        const double den = la * lb * lc + dot(ra, rb) * lc + bc * la + ac * lb;
        const double slack = kOnFanSlack * (la + kOnFanReach) * (lb + kOnFanReach) * (lc + kOnFanReach);
        if (abs(det) <= slack && den <= slack) {
            onFan = true;
            return 0.0;
        }
        const double nextRe = re * den - im * det, nextIm = re * det + im * den;
        if (det > 0.0 && im >= 0.0 && nextIm < 0.0) ++turns;
        else if (det < 0.0 && im < 0.0 && nextIm >= 0.0) --turns;
        const double scale = max(abs(nextRe), abs(nextIm));
        if (scale == 0.0) {
            onFan = true;
            return 0.0;
        }
        re = nextRe / scale;
        im = nextIm / scale;
        rb = ra;
        lb = la;
        bc = ac;
    }
    const double angle = atanDouble(im, re) + 2.0 * kPi * double(turns);
    return double(fan.z) * 2.0 * angle / (4.0 * kPi);
}

double bound(uint node, dvec3 p) {
    const dvec3 lo = dvec3(fanNodes[8 * node], fanNodes[8 * node + 1], fanNodes[8 * node + 2]);
    const dvec3 hi = dvec3(fanNodes[8 * node + 3], fanNodes[8 * node + 4], fanNodes[8 * node + 5]);
    const double d = length(max(max(lo - p, p - hi), dvec3(0.0)));
    return d > 0.0 ? fanNodes[8 * node + 6] / (4.0 * kPi * d * d) : 1.0 / 0.0;
}

void main() {
    const int index = firstSample + int(gl_GlobalInvocationID.x);
    if (index >= slabSamples) return;
    const int i = index % dims.x, j = (index / dims.x) % dims.y, k = slabZ + index / (dims.x * dims.y);
    const dvec3 p = dvec3(exactSamples[i], exactSamples[dims.x + j], exactSamples[dims.x + dims.y + k]);
    double w = double(winding[index]);
    double doubt = 0.0, error = 1e-9;
    uint stack[64];
    int top = 0;
    stack[top++] = 0u;
    while (top > 0) {
        const uint node = stack[--top];
        const double b = bound(node, p);
        if (b <= 0.0) continue; // no area
        if (b <= kSkip && doubt + b <= kBudget) {
            doubt += b;
            continue;
        }
        const uvec2 link = fanLinks[node];
        if (link.y == 1u) {
            const ivec4 fan = fans[link.x];
            bool onFan = false;
            w -= fanWinding(p, fan, onFan);
            if (onFan) {
                sides[index] = 2;
                return;
            }
            error += abs(double(fan.z)) * kFanError;
        } else {
            stack[top++] = link.x + 1u;
            stack[top++] = link.x;
        }
    }
    const double margin = doubt * (1.0 + 1e-12) + error;
    const double x = abs(w) - 0.5;
    sides[index] = x > margin ? 1 : x < -margin ? 0 : 2;
}
