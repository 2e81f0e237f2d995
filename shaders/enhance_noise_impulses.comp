#version 450
#extension GL_GOOGLE_include_directive : require
// Noise pass 2: one invocation per cell of the sparse-convolution grid (Tariq 2022 §4.4). Each of
// the cell's fixed impulses (positions, weights and frequency quantiles from a constant-seed
// hash) gets its Gabor parameters from the pixel it lands on: band [F_L, F_H] from Thibos'
// limits at that eccentricity and the blur σ of its shading rate, amplitude K = s_k·|L_lp|
// limited by the level-3 min/max headroom, orientation from the Sobel field on G3. Parameters
// are evaluated at impulses only, not per pixel. Mirrors noise_parameters() and the impulse loop
// of synthesize_gabor_noise() in sdk/src/vk/post/enhance_model.cpp.
layout(local_size_x = 64) in;
layout(set = 0, binding = 0, r16f) uniform readonly image2D rate_in;
layout(set = 0, binding = 1, r32f) uniform readonly image2D g0;
layout(set = 0, binding = 2, r32f) uniform readonly image2D g1;
layout(set = 0, binding = 3, r32f) uniform readonly image2D g2;
layout(set = 0, binding = 4, r32f) uniform readonly image2D g3;
layout(set = 0, binding = 5, rgba32f) uniform readonly image2D field;  // gx, gy, min, max (level 3)
layout(std430, set = 0, binding = 6) writeonly buffer Impulses { vec4 impulse[]; };  // ix, iy, kx, ky
layout(std430, set = 0, binding = 7) writeonly buffer Amplitudes { float amplitude[]; };  // K·w
layout(std430, set = 0, binding = 8) writeonly buffer Cells { float cell_peak[]; };  // max |K·w|

#include "enhance_common.glsl"
#include "enhance_noise_common.glsl"
#include "enhance_noise_push.glsl"
#include "fovea_acuity.glsl"

ivec2 g_size(int l) {
    if (l == 0) return imageSize(g0);
    if (l == 1) return imageSize(g1);
    if (l == 2) return imageSize(g2);
    return imageSize(g3);
}

float g_at(int l, ivec2 t) {
    t = clamp(t, ivec2(0), g_size(l) - 1);
    if (l == 0) return imageLoad(g0, t).x;
    if (l == 1) return imageLoad(g1, t).x;
    if (l == 2) return imageLoad(g2, t).x;
    return imageLoad(g3, t).x;
}

// sample_bilinear(): continuous texel coordinates, centres at i + 0.5, clamp-to-edge.
float g_bilinear(int l, vec2 tc) {
    vec2 f = tc - 0.5;
    vec2 b = floor(f);
    vec2 a = f - b;
    ivec2 i = ivec2(b);
    float top = g_at(l, i) * (1.0 - a.x) + g_at(l, i + ivec2(1, 0)) * a.x;
    float bottom = g_at(l, i + ivec2(0, 1)) * (1.0 - a.x) + g_at(l, i + ivec2(1, 1)) * a.x;
    return top * (1.0 - a.y) + bottom * a.y;
}

// Laplacian texel L_l = G_l − expand(G_{l+1}); level 3 is the Gaussian residual.
float lap_at(int l, ivec2 t) {
    ivec2 size = g_size(l);
    t = clamp(t, ivec2(0), size - 1);
    if (l >= 3) return g_at(3, t);
    vec2 coarse = vec2(g_size(l + 1));
    return g_at(l, t) - g_bilinear(l + 1, (vec2(t) + 0.5) / vec2(size) * coarse);
}

float lap_sample(int l, vec2 px, vec2 full) {
    vec2 tc = px / full * vec2(g_size(l));
    vec2 f = tc - 0.5;
    vec2 b = floor(f);
    vec2 a = f - b;
    ivec2 i = ivec2(b);
    float top = lap_at(l, i) * (1.0 - a.x) + lap_at(l, i + ivec2(1, 0)) * a.x;
    float bottom = lap_at(l, i + ivec2(0, 1)) * (1.0 - a.x) + lap_at(l, i + ivec2(1, 1)) * a.x;
    return top * (1.0 - a.y) + bottom * a.y;
}

vec4 field_at(ivec2 t) { return imageLoad(field, clamp(t, ivec2(0), imageSize(field) - 1)); }

float field_bilinear(int c, vec2 tc) {
    vec2 f = tc - 0.5;
    vec2 b = floor(f);
    vec2 a = f - b;
    ivec2 i = ivec2(b);
    float top = field_at(i)[c] * (1.0 - a.x) + field_at(i + ivec2(1, 0))[c] * a.x;
    float bottom = field_at(i + ivec2(0, 1))[c] * (1.0 - a.x) + field_at(i + ivec2(1, 1))[c] * a.x;
    return top * (1.0 - a.y) + bottom * a.y;
}

// Amplitude K (0 outside the band) at pixel q.
float amplitude_at(ivec2 q, vec2 px, vec2 full, vec4 band) {
    if (!(band.y > band.x)) return 0.0;
    float sigma = enh_blur_sigma_for_rate(imageLoad(rate_in, q).x);
    // lp <= 2 keeps l0 + 1 inside the four-level pyramid (S_t <= 1 gives lp < 1.6).
    float lp = min(noise_laplacian_level(sigma, pc.attenuation_p), 2.0);
    int l0 = int(floor(lp));
    float t = lp - float(l0);
    const float kTiny = 1e-6;  // log-domain blend of |L| needs > 0
    float a = log(abs(lap_sample(l0, px, full)) + kTiny);
    float b = log(abs(lap_sample(l0 + 1, px, full)) + kTiny);
    float k = pc.s_k * max(exp(a + (b - a) * t) - kTiny, 0.0);
    // Headroom to black and white in the level-3 neighbourhood; noise std K <= room/3.
    vec2 tc = px / full * vec2(imageSize(field));
    float room = min(1.0 - field_bilinear(3, tc), field_bilinear(2, tc));
    return clamp(k, 0.0, max(room, 0.0) / 3.0);
}

// Orientation: Catmull-Rom upsampling of the G3 Sobel field, then atan2.
float orientation_at(vec2 px, vec2 full) {
    vec2 g = px / full * vec2(imageSize(field)) - 0.5;
    vec2 b = floor(g);
    vec2 t = g - b;
    vec2 t2 = t * t;
    vec2 t3 = t2 * t;
    vec2 w[4] = vec2[4](-0.5 * t3 + t2 - 0.5 * t, 1.5 * t3 - 2.5 * t2 + 1.0,
                        -1.5 * t3 + 2.0 * t2 + 0.5 * t, 0.5 * t3 - 0.5 * t2);
    vec2 v = vec2(0.0);
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i)
            v += w[i].x * w[j].y * field_at(ivec2(b) + ivec2(i - 1, j - 1)).xy;
    return dot(v, v) > 1e-12 ? atan(v.y, v.x) : 0.0;
}

void main() {
    int cell = int(gl_GlobalInvocationID.x);
    if (cell >= pc.cells_x * pc.cells_y) return;
    int ci = cell % pc.cells_x - 1;
    int cj = cell / pc.cells_x - 1;
    ivec2 size = imageSize(rate_in);
    vec2 full = vec2(size);
    FoveaDisplay display = FoveaDisplay(pc.display_size_px, pc.display_half_tan);
    uint st = noise_cell_seed(ci, cj, pc.seed);
    float peak = 0.0;
    for (int k = 0; k < pc.per_cell; ++k) {
        st = noise_hash(st);
        float ix = (float(ci) + noise_unit(st)) * pc.radius;
        st = noise_hash(st);
        float iy = (float(cj) + noise_unit(st)) * pc.radius;
        st = noise_hash(st);
        float weight = 2.0 * noise_unit(st) - 1.0;
        st = noise_hash(st);
        float u = noise_unit(st);
        ivec2 q = clamp(ivec2(int(ix), int(iy)), ivec2(0), size - 1);
        vec2 px = vec2(q) + 0.5;
        float amp = 0.0;
        vec2 kvec = vec2(0.0);
        if (pc.ppd > 0.0) {
            float ecc = fovea_eccentricity_deg(display, px, pc.gaze_px);
            ecc = (isnan(ecc) || isinf(ecc)) ? 1e3 : ecc;
            float sigma = enh_blur_sigma_for_rate(imageLoad(rate_in, q).x);
            vec4 band = noise_band(ecc, sigma, pc.ppd, pc.s_f);
            amp = amplitude_at(q, px, full, band);
            if (amp > 0.0) {
                float f = noise_sample_frequency(band, u);
                float om = orientation_at(px, full);
                kvec = 2.0 * kNoisePi * f * vec2(cos(om), sin(om));
            }
        }
        int slot = cell * pc.per_cell + k;
        impulse[slot] = vec4(ix, iy, kvec);
        amplitude[slot] = amp * weight;
        peak = max(peak, abs(amp * weight));
    }
    cell_peak[cell] = peak;
}
