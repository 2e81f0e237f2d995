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
    float aa_u1;      // LP columns below this are minified along v (angular spacing < 1 px)
    float pad1;
    vec4 beta[2];     // β1..β8
} kfr;

// Polynomial kernel (1) or power kernel (0). A specialization constant, not a uniform branch:
// llvmpipe evaluates both sides of a branch, so the bisection must not exist for x^p.
layout(constant_id = 0) const int KFR_POLY = 0;

float kfr_beta(int i) { return kfr.beta[(i - 1) / 4][(i - 1) % 4]; }

float kfr_kernel(float x) {
    x = clamp(x, 0.0, 1.0);
    if (KFR_POLY == 0) return x > 0.0 ? pow(x, kfr.exponent) : 0.0;
    float y = 0.0;
    for (int i = kfr.betas; i >= 1; --i) y = y * x + kfr_beta(i);
    return y * x;  // β0 = 0
}

float kfr_kernel_inverse(float y) {
    y = clamp(y, 0.0, 1.0);
    if (KFR_POLY == 0) return y > 0.0 ? pow(y, 1.0 / kfr.exponent) : 0.0;
    float lo = 0.0, hi = 1.0;  // K is increasing on [0, 1] (checked on the CPU)
    for (int i = 0; i < 24; ++i) {
        float mid = 0.5 * (lo + hi);
        if (kfr_kernel(mid) < y) lo = mid; else hi = mid;
    }
    return 0.5 * (lo + hi);
}

// K'(x), for the Jacobian of the forward map.
float kfr_kernel_derivative(float x) {
    x = clamp(x, 1e-6, 1.0);
    if (KFR_POLY == 0) return kfr.exponent * pow(x, kfr.exponent - 1.0);
    float d = 0.0;
    for (int i = kfr.betas; i >= 1; --i) d = d * x + float(i) * kfr_beta(i);
    return d;
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

// Eq. 10 at p with its Jacobian: returns (u, v) and writes d(u, v)/dx and d(u, v)/dy, so
// sub-pixel positions around p map with one evaluation. `radial_px` is the screen extent of one
// LP texel along the radius (the blur scale), `angular_px` along the circle.
vec2 kfr_forward_jacobian(vec2 p, out vec2 duv_dx, out vec2 duv_dy, out float radial_px,
                          out float angular_px) {
    vec2 d = p - kfr.gaze;
    float len = length(d);
    float r = max(len, 1.0);
    float x = kfr_kernel_inverse(log(r) / kfr.log_max_r);
    // du/dr = w / (L r K'(x)): the LP column density along the radius.
    float du_dr = kfr.lp_size.x / (kfr.log_max_r * r * max(kfr_kernel_derivative(x), 1e-6));
    vec2 dir = d / r;
    float dv_dtheta = kfr.lp_size.y / KFR_TWO_PI;
    duv_dx = vec2(du_dr * dir.x, -dv_dtheta * dir.y / r);
    duv_dy = vec2(du_dr * dir.y, dv_dtheta * dir.x / r);
    radial_px = 1.0 / du_dr;
    angular_px = r / dv_dtheta;
    float a = len > 1e-6 ? atan(d.y, d.x) : 0.0;
    if (a < 0.0) a += KFR_TWO_PI;
    float v = a * dv_dtheta;
    if (v >= kfr.lp_size.y) v -= kfr.lp_size.y;
    return vec2(x * kfr.lp_size.x, v);
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
