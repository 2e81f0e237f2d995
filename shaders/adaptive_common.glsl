// Stengel et al. 2016 adaptive sampling: push constants shared by the adaptive passes, the
// sampling-pattern hash (identical to sdk/src/vk/methods/adaptive_model.cpp sample_hash) and the
// feature maps of Eqs. 1–12. Include after fovea_frame.glsl.
#ifndef ADAPTIVE_COMMON_GLSL
#define ADAPTIVE_COMMON_GLSL

// sdk/src/vk/methods/adaptive.cpp AdaptivePush (112 bytes).
layout(push_constant) uniform AdaptivePush {
    vec2 gaze;            // pixels
    vec2 gaze_ahead;      // end of the gaze segment (§4.1.2); = gaze during fixations/jumps
    vec2 eye_motion_px;   // gaze displacement over the frame (0 after a saccadic jump)
    float dt;             // seconds since the previous frame
    float omega0;         // Eq. 2 (normalised eccentricity space)
    float slope;
    float omega_p;        // far-periphery floor, Eq. 1
    float ecc_norm_deg;   // degrees per unit of normalised eccentricity (half vertical FOV)
    float gamma;          // Eq. 8
    float t_dark;         // Eq. 11
    float t_bright;
    float adapt_rate;     // a_r, Eq. 10
    float auto_exposure;  // A
    float gain_depth;     // 1 / relative depth step of a full silhouette
    float gain_normal;    // 1 / (1 - cos) of a full crease
    float gain_albedo;    // 1 / albedo step of a full texture edge (F_O)
    int has_history;      // 0 on the first frame and after a camera cut: S = 1, E kept
    uint seed;            // sampling pattern seed (fixed: temporally stable pattern)
    int level;            // pull/push: destination level; 0 in the last push writes the output
    float features;       // 1: F_O, F_H, F_S on; 0: acuity and motion only (ablation, tests)
    float pad1;
    vec4 light;           // xyz direction towards the light (unit), w intensity (Eq. 8)
} ad;

// PCG-style integer hash (Jarzynski & Olano 2020); same constants as the C++ model.
uint adaptive_hash(uint x, uint y, uint seed) {
    uint v = x * 1664525u + 1013904223u;
    uint w = y * 1664525u + 1013904223u;
    uint z = seed * 1664525u + 1013904223u;
    v += w * z;
    w += z * v;
    z += v * w;
    v ^= v >> 16u;
    w ^= w >> 16u;
    z ^= z >> 16u;
    v += w * z;
    return v;
}

float adaptive_threshold(ivec2 p) {
    return float(adaptive_hash(uint(p.x), uint(p.y), ad.seed) >> 8u) * (1.0 / 16777216.0);
}

// Eq. 1–3 with the gaze as a segment: angular distance from p to the segment gaze..gaze_ahead.
float adaptive_eccentricity_deg(vec2 p) {
    vec2 a = fovea_view_angles_rad(fovea_frame.display, p);
    vec2 g0 = fovea_view_angles_rad(fovea_frame.display, ad.gaze);
    vec2 g1 = fovea_view_angles_rad(fovea_frame.display, ad.gaze_ahead);
    vec2 ab = g1 - g0;
    float len2 = dot(ab, ab);
    float t = len2 > 0.0 ? clamp(dot(a - g0, ab) / len2, 0.0, 1.0) : 0.0;
    return length(a - (g0 + t * ab)) * 57.29577951308232;
}

float adaptive_acuity(vec2 p) {
    float e = adaptive_eccentricity_deg(p) / ad.ecc_norm_deg;
    return clamp(ad.omega0 + ad.slope * e, ad.omega_p, 1.0);
}

// Eq. 5.
float adaptive_motion_gain(float v_deg_s) {
    if (!(v_deg_s > 0.83)) return 1.0;
    if (v_deg_s > 118.0) return 0.002;
    return 0.962 - 0.463 * log(v_deg_s) / log(10.0);
}

float adaptive_luminance(vec3 c) { return dot(vec3(0.299, 0.587, 0.114), c); }  // Eq. 9
// Reinhard; finite for any input (inf -> 1, NaN -> 0).
float adaptive_tonemap(float l, float e) {
    float x = clamp(l * e, 0.0, 1e30);
    return isnan(x) ? 0.0 : x / (1.0 + x);
}

// Eq. 11.
float adaptive_brightness_scale(float l) {
    return clamp(min(1.0, l / ad.t_dark) * min(1.0, (1.0 - l) / (1.0 - ad.t_bright)), 0.0, 1.0);
}

#endif
