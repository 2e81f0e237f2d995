// Acuity and eccentricity model shared verbatim by the GPU (included by shaders) and the CPU
// (sdk/src/vk/acuity.cpp includes this file with small vec2/float shims), so the rate a shader
// computes equals the rate the C++ model computes texel by texel. Keep to scalar/vec2 maths,
// no inout parameters, no GLSL-only built-ins beyond abs/clamp/max/min/sqrt; `precise` on
// every intermediate (a no-op in C++).
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

// atan from +, *, / and a comparison only (max error ~1e-5 rad): the GPU's and the C++ library's
// atan differ in the last bits, which would flip rate thresholds between CPU and GPU. `precise`
// forbids fused multiply-adds, so both sides round every operation the same way.
float fovea_atan(float x) {
    precise float ax = abs(x);
    bool inv = ax > 1.0f;
    precise float z = inv ? 1.0f / ax : ax;
    precise float z2 = z * z;
    precise float p = -0.0117212f;
    p = p * z2 + 0.05265332f;
    p = p * z2 - 0.11643287f;
    p = p * z2 + 0.19354346f;
    p = p * z2 - 0.33262347f;
    p = p * z2 + 0.99997726f;
    precise float r = p * z;
    precise float a = inv ? 1.5707963267948966f - r : r;
    return x < 0.0f ? -a : a;
}

// Stengel Eq. 3 maps each axis through atan(offset / s) with s = (d/2)/tan(a/2). The paper
// writes |p - d/2|; we keep the sign so points on opposite sides of the centre stay apart.
vec2 fovea_view_angles_rad(FoveaDisplay d, vec2 p) {
    precise float sx = d.size_px.x * 0.5f / d.half_tan.x;
    precise float sy = d.size_px.y * 0.5f / d.half_tan.y;
    precise float ux = (p.x - d.size_px.x * 0.5f) / sx;
    precise float uy = (p.y - d.size_px.y * 0.5f) / sy;
    return vec2(fovea_atan(ux), fovea_atan(uy));
}

float fovea_eccentricity_deg(FoveaDisplay d, vec2 p, vec2 g) {
    vec2 a = fovea_view_angles_rad(d, p);
    vec2 b = fovea_view_angles_rad(d, g);
    precise float kx = a.x - b.x;
    precise float ky = a.y - b.y;
    precise float e = sqrt(kx * kx + ky * ky) * 57.29577951308232f;
    return e;
}

// Angular size (degrees) of one pixel at p along x and along y: derivative of atan(x/s).
vec2 fovea_pixel_size_deg_axes(FoveaDisplay d, vec2 p) {
    precise float sx = d.size_px.x * 0.5f / d.half_tan.x;
    precise float sy = d.size_px.y * 0.5f / d.half_tan.y;
    precise float ux = (p.x - d.size_px.x * 0.5f) / sx;
    precise float uy = (p.y - d.size_px.y * 0.5f) / sy;
    precise float dx = 1.0f / (sx * (1.0f + ux * ux)) * 57.29577951308232f;
    precise float dy = 1.0f / (sy * (1.0f + uy * uy)) * 57.29577951308232f;
    return vec2(dx, dy);
}

// Angular size (degrees) of one pixel at p: the larger of both axes.
float fovea_pixel_size_deg(FoveaDisplay d, vec2 p) {
    vec2 a = fovea_pixel_size_deg_axes(d, p);
    return max(a.x, a.y);
}

// Guenter Eq. 1: minimum angle of resolution, degrees per cycle.
float fovea_mar_deg(FoveaAcuity a, float e_deg) {
    precise float w = a.mar_slope * e_deg + a.mar_omega0;
    return w;
}

// Continuous coarse-pixel edge (pixels) at eccentricity e for a pixel of angular size pix_deg:
// two samples per MAR cycle (Nyquist), Patney's piecewise-linear blend from full rate.
float fovea_rate_at(FoveaAcuity a, float e_deg, float pix_deg) {
    precise float e = max(e_deg - a.margin_deg, 0.0f);
    if (!(e > a.foveal_radius_deg)) return 1.0f;  // also catches NaN
    precise float r_mar = max(0.5f * fovea_mar_deg(a, e) / pix_deg, 1.0f);
    precise float t = clamp((e - a.foveal_radius_deg) / max(a.transition_deg, 1e-6f), 0.0f, 1.0f);
    precise float r = 1.0f + (r_mar - 1.0f) * t;
    return r;
}

// Largest power of two <= r, capped at max_rate: 1, 2 or 4.
float fovea_quantize_rate(float r, float max_rate) {
    float q = 1.0f;
    if (r >= 2.0f && max_rate >= 2.0f) q = 2.0f;
    if (r >= 4.0f && max_rate >= 4.0f) q = 4.0f;
    return q;
}

// Rate of the tile [tile_min, tile_max) (pixels): eccentricity at the tile's pixel centre
// nearest the gaze (per-axis angles are monotonic, so clamping gives the minimum), pixel size at
// the pixel centre nearest the display centre (the largest pixel angle). Conservative.
float fovea_tile_rate(FoveaDisplay d, FoveaAcuity a, vec2 tile_min, vec2 tile_max, vec2 gaze_px) {
    precise vec2 lo = tile_min + vec2(0.5f, 0.5f);
    precise vec2 hi = tile_max - vec2(0.5f, 0.5f);
    vec2 pe = clamp(gaze_px, lo, hi);
    vec2 pc = clamp(d.size_px * 0.5f, lo, hi);
    float e = fovea_eccentricity_deg(d, pe, gaze_px);
    return fovea_quantize_rate(fovea_rate_at(a, e, fovea_pixel_size_deg(d, pc)), a.max_rate);
}

// Patney's normalized shading rate S_t: 0 at full rate, 1 at the coarsest rate (4x4).
float fovea_normalized_rate(float rate) {
    if (rate >= 4.0f) return 1.0f;
    if (rate >= 2.0f) return 0.5f;
    return 0.0f;
}

// VK_KHR_fragment_shading_rate attachment texel: (log2 w << 2) | log2 h, isotropic here.
uint fovea_vrs_encode(float rate) {
    uint l = 0u;
    if (rate >= 2.0f) l = 1u;
    if (rate >= 4.0f) l = 2u;
    return (l << 2u) | l;
}
