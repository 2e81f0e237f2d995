// TAA building blocks shared by the taa_*.comp passes; each mirrors a function of
// sdk/src/vk/post/taa_model.cpp (the CPU reference the GPU tests compare against).
#ifndef FOVEA_TAA_COMMON_GLSL
#define FOVEA_TAA_COMMON_GLSL

const float kTaaMaxTonemapped = 0.99999;

// NaN -> 0, negatives -> 0, +inf -> large finite (the model's sanitize()).
float taa_sanitize(float v) {
    if (isnan(v)) return 0.0;
    return clamp(v, 0.0, 3.0e38);
}

vec3 taa_tonemap(vec3 c) {
    c = vec3(taa_sanitize(c.r), taa_sanitize(c.g), taa_sanitize(c.b));
    return c * (1.0 / (1.0 + max(c.r, max(c.g, c.b))));
}

vec3 taa_tonemap_inverse(vec3 t) {
    t = clamp(t, vec3(0.0), vec3(kTaaMaxTonemapped));
    return t * (1.0 / (1.0 - max(t.r, max(t.g, t.b))));
}

vec3 taa_rgb_to_ycocg(vec3 c) {
    return vec3(0.25 * c.r + 0.5 * c.g + 0.25 * c.b, 0.5 * c.r - 0.5 * c.b,
                -0.25 * c.r + 0.5 * c.g - 0.25 * c.b);
}

vec3 taa_ycocg_to_rgb(vec3 c) { return vec3(c.x + c.y - c.z, c.x + c.z, c.x - c.y - c.z); }

vec4 taa_catmull_rom(float t) {
    float t2 = t * t;
    float t3 = t2 * t;
    return vec4(-0.5 * t3 + t2 - 0.5 * t, 1.5 * t3 - 2.5 * t2 + 1.0,
                -1.5 * t3 + 2.0 * t2 + 0.5 * t, 0.5 * t3 - 0.5 * t2);
}

// Moves v toward the box centre until inside (box = centre ± extent).
vec3 taa_clip(vec3 v, vec3 centre, vec3 extent) {
    vec3 d = v - centre;
    vec3 u = abs(d) / max(extent, vec3(1e-7));
    float m = max(u.x, max(u.y, u.z));
    return m > 1.0 ? centre + d / m : v;
}

float taa_saccade_alpha(float s_prev, float s_cur, float alpha, float alpha_max, float beta,
                        bool enabled) {
    if (!enabled) return alpha;
    float w = clamp((s_prev - s_cur) / beta, 0.0, 1.0);
    return w * alpha_max + (1.0 - w) * alpha;
}

#endif
