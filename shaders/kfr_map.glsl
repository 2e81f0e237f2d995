// Meng et al. 2018 kernel log-polar map (Eqs. 10–13), the GLSL twin of
// sdk/src/vk/methods/kfr_model.cpp, and the push constants all kfr passes share.
#ifndef KFR_MAP_GLSL
#define KFR_MAP_GLSL

const float KFR_TWO_PI = 6.28318530717958647692;

// Push constants of every kfr pass (sdk/src/vk/methods/kfr.cpp KfrPush, 64 bytes).
layout(push_constant) uniform KfrPush {
    vec2 gaze;        // screen pixels, clamped to the screen
    vec2 lp_size;     // LP buffer w, h
    vec2 screen;      // W, H
    float log_max_r;  // L, Eq. 12
    float exponent;   // K(x) = x^exponent when betas == 0
    int betas;        // polynomial degree k (β1..βk used); 0 = power kernel
    float blur_u0;    // first LP column of the peripheral 3x3 Gaussian
    float pad0;
    float pad1;
    vec4 beta[2];     // β1..β8
} kfr;

float kfr_beta(int i) { return kfr.beta[(i - 1) / 4][(i - 1) % 4]; }

float kfr_kernel(float x) {
    x = clamp(x, 0.0, 1.0);
    if (kfr.betas == 0) return x > 0.0 ? pow(x, kfr.exponent) : 0.0;
    float y = 0.0;
    for (int i = kfr.betas; i >= 1; --i) y = y * x + kfr_beta(i);
    return y * x;  // β0 = 0
}

float kfr_kernel_inverse(float y) {
    y = clamp(y, 0.0, 1.0);
    if (kfr.betas == 0) return y > 0.0 ? pow(y, 1.0 / kfr.exponent) : 0.0;
    float lo = 0.0, hi = 1.0;  // K is increasing on [0, 1] (checked on the CPU)
    for (int i = 0; i < 24; ++i) {
        float mid = 0.5 * (lo + hi);
        if (kfr_kernel(mid) < y) lo = mid; else hi = mid;
    }
    return 0.5 * (lo + hi);
}

// Eq. 10: screen point -> (u, v), u in [0, w], v in [0, h). Finite everywhere: r < 1 pixel maps
// to u = 0 and atan(0, 0), undefined in GLSL, is never evaluated.
vec2 kfr_forward(vec2 p) {
    vec2 d = p - kfr.gaze;
    float r = length(d);
    float u = kfr_kernel_inverse(log(max(r, 1.0)) / kfr.log_max_r) * kfr.lp_size.x;
    float a = r > 1e-6 ? atan(d.y, d.x) : 0.0;
    if (a < 0.0) a += KFR_TWO_PI;  // the [y' < 0]·2π term
    float v = a * kfr.lp_size.y / KFR_TWO_PI;
    if (v >= kfr.lp_size.y) v -= kfr.lp_size.y;
    return vec2(u, v);
}

// Inverse of Eq. 10: (u, v) -> screen point; v is periodic.
vec2 kfr_inverse(vec2 lp) {
    float r = exp(kfr.log_max_r * kfr_kernel(lp.x / kfr.lp_size.x));
    float a = lp.y * KFR_TWO_PI / kfr.lp_size.y;
    return kfr.gaze + r * vec2(cos(a), sin(a));
}

// Screen pixels one LP texel spans at column u: the larger of the radial (dr/du) and the
// angular (2πr/h) spacing. The shade's footprint and the normalized rate S_t follow from it.
float kfr_texel_footprint(float u) {
    float x = clamp(u / kfr.lp_size.x, 1e-4, 1.0 - 1e-4);
    float r = exp(kfr.log_max_r * kfr_kernel(x));
    float dk = (kfr_kernel(x + 1e-4) - kfr_kernel(x - 1e-4)) / 2e-4;
    float radial = r * kfr.log_max_r * dk / kfr.lp_size.x;
    float angular = KFR_TWO_PI * r / kfr.lp_size.y;
    return max(radial, angular);
}

#endif
