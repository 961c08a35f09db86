// Colour maps shared by the slice, the volume and the colour bar. s is the signed distance over the
// colour range, clamped to -1..1 (negative inside); scaled(d, range) maps a distance into it.
uniform int colormap; // 0: diverging (red inside, white at the surface, blue outside); 1: viridis; 2: grey

vec3 viridis(float t) {
    // Polynomial fit of matplotlib's viridis (Matt Zucker's fit, max error about 1/255).
    const vec3 c0 = vec3(0.2777273272234177, 0.005407344544966578, 0.3340998053353061);
    const vec3 c1 = vec3(0.1050930431085774, 1.404613529898575, 1.384590162594685);
    const vec3 c2 = vec3(-0.3308618287255563, 0.214847559468213, 0.09509516302823659);
    const vec3 c3 = vec3(-4.634230498983486, -5.799100973351585, -19.33244095627987);
    const vec3 c4 = vec3(6.228269936347081, 14.17993336680509, 56.69055260068105);
    const vec3 c5 = vec3(4.776384997670288, -13.74514537774601, -65.35303263337234);
    const vec3 c6 = vec3(-5.435455855934631, 4.645852612178535, 26.3124352495832);
    return c0 + t * (c1 + t * (c2 + t * (c3 + t * (c4 + t * (c5 + t * c6)))));
}

vec3 colourOf(float s) {
    s = clamp(s, -1.0, 1.0);
    if (colormap == 1) return clamp(viridis(0.5 + 0.5 * s), 0.0, 1.0);
    if (colormap == 2) return vec3(0.5 + 0.45 * s);
    vec3 outside = vec3(0.23, 0.30, 0.75), inside = vec3(0.71, 0.02, 0.15), middle = vec3(0.87);
    return s > 0.0 ? mix(middle, outside, sqrt(s)) : mix(middle, inside, sqrt(-s));
}

// A distance over the range [range.x < 0, range.y > 0]: each side scaled on its own, so that 0
// (the surface) stays in the middle of the map however lopsided the range.
float scaled(float d, vec2 range) { return d < 0.0 ? d / -range.x : d / range.y; }
