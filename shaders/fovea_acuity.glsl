// Acuity and eccentricity model shared verbatim by the GPU (included by shaders) and the CPU
// (sdk/src/vk/acuity.cpp includes this file with small vec2/float shims), so the rate a shader
// computes equals the rate the C++ model computes texel by texel. Keep to scalar/vec2 maths,
// no inout parameters, no GLSL-only built-ins beyond atan/clamp/mix/max/min/sqrt/floor.
//
// Model (DESIGN.md §5): Stengel 2016 Eq. 3 eccentricity (signed per axis, see below), Guenter
// 2012 MAR line w = m e + w0, Patney 2016 piecewise-linear rate: full rate inside the foveal
// radius, a linear ramp over the transition width, then the MAR-limited rate; quantized down to
// a power of two (1, 2, 4) so it never undersamples what the line says the eye resolves.

// One eye's display: pixel size and tan of the half field of view per axis.
struct FoveaDisplay {
    vec2 size_px;
    vec2 half_tan;
};

// Acuity parameters; margin_deg is the fovea widening for gaze uncertainty and sample age
// (computed per frame on the CPU by fovea::vk::resolve_gaze). 8 floats: std140 friendly.
struct FoveaAcuity {
    float mar_slope;          // m, degrees of MAR per degree of eccentricity (0.022..0.034)
    float mar_omega0;         // w0, degrees (1/48)
    float foveal_radius_deg;  // full rate inside
    float transition_deg;     // linear ramp width
    float margin_deg;         // subtracted from the eccentricity (>= 0)
    float max_rate;           // 1, 2 or 4: largest coarse pixel edge
    float tile_size;          // pixels per rate tile edge
    float reserved;
};

// Stengel Eq. 3 maps each axis through atan(offset / s) with s = (d/2)/tan(a/2). The paper
// writes |p - d/2|; we keep the sign so points on opposite sides of the centre stay apart.
vec2 fovea_view_angles_rad(FoveaDisplay d, vec2 p) {
    vec2 s = vec2(d.size_px.x * 0.5 / d.half_tan.x, d.size_px.y * 0.5 / d.half_tan.y);
    return vec2(atan((p.x - d.size_px.x * 0.5) / s.x), atan((p.y - d.size_px.y * 0.5) / s.y));
}

float fovea_eccentricity_deg(FoveaDisplay d, vec2 p, vec2 g) {
    vec2 a = fovea_view_angles_rad(d, p);
    vec2 b = fovea_view_angles_rad(d, g);
    vec2 k = a - b;
    return sqrt(k.x * k.x + k.y * k.y) * 57.29577951308232;
}

// Angular size (degrees) of one pixel at p: derivative of atan(x/s), the larger of both axes.
float fovea_pixel_size_deg(FoveaDisplay d, vec2 p) {
    vec2 s = vec2(d.size_px.x * 0.5 / d.half_tan.x, d.size_px.y * 0.5 / d.half_tan.y);
    float ux = (p.x - d.size_px.x * 0.5) / s.x;
    float uy = (p.y - d.size_px.y * 0.5) / s.y;
    float dx = 1.0 / (s.x * (1.0 + ux * ux));
    float dy = 1.0 / (s.y * (1.0 + uy * uy));
    return max(dx, dy) * 57.29577951308232;
}

// Guenter Eq. 1: minimum angle of resolution, degrees per cycle.
float fovea_mar_deg(FoveaAcuity a, float e_deg) {
    return a.mar_slope * e_deg + a.mar_omega0;
}

// Continuous coarse-pixel edge (pixels) at eccentricity e for a pixel of angular size pix_deg:
// two samples per MAR cycle (Nyquist), Patney's piecewise-linear blend from full rate.
float fovea_rate_at(FoveaAcuity a, float e_deg, float pix_deg) {
    float e = max(e_deg - a.margin_deg, 0.0);
    if (!(e > a.foveal_radius_deg)) return 1.0;  // also catches NaN
    float r_mar = max(0.5 * fovea_mar_deg(a, e) / pix_deg, 1.0);
    float t = clamp((e - a.foveal_radius_deg) / max(a.transition_deg, 1e-6), 0.0, 1.0);
    return 1.0 + (r_mar - 1.0) * t;
}

// Largest power of two <= r, capped at max_rate: 1, 2 or 4.
float fovea_quantize_rate(float r, float max_rate) {
    float q = 1.0;
    if (r >= 2.0 && max_rate >= 2.0) q = 2.0;
    if (r >= 4.0 && max_rate >= 4.0) q = 4.0;
    return q;
}

// Rate of the tile [tile_min, tile_max) (pixels): eccentricity at the tile's pixel centre
// nearest the gaze (per-axis angles are monotonic, so clamping gives the minimum), pixel size at
// the pixel centre nearest the display centre (the largest pixel angle). Conservative.
float fovea_tile_rate(FoveaDisplay d, FoveaAcuity a, vec2 tile_min, vec2 tile_max, vec2 gaze_px) {
    vec2 lo = tile_min + vec2(0.5, 0.5);
    vec2 hi = tile_max - vec2(0.5, 0.5);
    vec2 pe = clamp(gaze_px, lo, hi);
    vec2 pc = clamp(d.size_px * 0.5, lo, hi);
    float e = fovea_eccentricity_deg(d, pe, gaze_px);
    return fovea_quantize_rate(fovea_rate_at(a, e, fovea_pixel_size_deg(d, pc)), a.max_rate);
}

// Patney's normalized shading rate S_t: 0 at full rate, 1 at the coarsest rate (4x4).
float fovea_normalized_rate(float rate) {
    if (rate >= 4.0) return 1.0;
    if (rate >= 2.0) return 0.5;
    return 0.0;
}

// VK_KHR_fragment_shading_rate attachment texel: (log2 w << 2) | log2 h, isotropic here.
uint fovea_vrs_encode(float rate) {
    uint l = 0u;
    if (rate >= 2.0) l = 1u;
    if (rate >= 4.0) l = 2u;
    return (l << 2u) | l;
}
