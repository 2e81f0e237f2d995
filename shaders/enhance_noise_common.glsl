// Gabor-noise helpers shared by the enhance_noise_*.comp passes (Tariq 2022 §4). A line-by-line
// mirror of the noise half of sdk/src/vk/post/enhance_model.cpp: the tables below duplicate its
// kEcc/kTl/kTh constants, and tests/vk_taa/noise_gpu_test.cpp compares the GPU pass with the CPU
// model across eccentricities, so a table edited on one side only fails that test.
#ifndef FOVEA_ENHANCE_NOISE_COMMON_GLSL
#define FOVEA_ENHANCE_NOISE_COMMON_GLSL

const float kNoisePi = 3.14159265358979;

// Tariq 2022 Table 3 (Thibos et al. 1996), cycles per degree.
const float kThibosEcc[7] = float[7](0.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0);
const float kThibosLow[7] = float[7](60.0, 27.0, 10.5, 8.0, 5.5, 4.8, 4.0);
const float kThibosHigh[7] = float[7](60.0, 40.0, 26.0, 24.0, 23.0, 21.0, 20.5);

// Piecewise-linear in eccentricity, held beyond the ends (NaN reads the first entry).
vec2 noise_thibos_limits(float e) {
    e = abs(e);
    if (!(e > kThibosEcc[0])) return vec2(kThibosLow[0], kThibosHigh[0]);
    for (int i = 1; i < 7; ++i) {
        if (e <= kThibosEcc[i]) {
            float t = (e - kThibosEcc[i - 1]) / (kThibosEcc[i] - kThibosEcc[i - 1]);
            return vec2(kThibosLow[i - 1] + (kThibosLow[i] - kThibosLow[i - 1]) * t,
                        kThibosHigh[i - 1] + (kThibosHigh[i] - kThibosHigh[i - 1]) * t);
        }
    }
    return vec2(kThibosLow[6], kThibosHigh[6]);
}

// x = F_L, y = F_H (cycles per pixel), z = μ_n, w = σ_n; empty when !(y > x).
vec4 noise_band(float ecc, float sigma_px, float ppd, float s_f) {
    vec2 t = noise_thibos_limits(ecc);
    float cutoff = sigma_px > 1e-6 ? 3.0 / (2.0 * kNoisePi * sigma_px) : 3.0e38;
    float lo = max(t.x / ppd, cutoff);
    float hi = min(t.y / ppd, 0.5);
    if (!(hi > lo)) return vec4(lo, hi, 0.0, 0.0);
    float mu = 0.5 * (log(lo) + log(hi));
    return vec4(lo, hi, mu, 0.5 * s_f * (mu - log(lo)));
}

float noise_erf(float x) {
    float s = x < 0.0 ? -1.0 : 1.0;
    x = abs(x);
    float t = 1.0 / (1.0 + 0.3275911 * x);
    float y = 1.0 - (((((1.061405429 * t - 1.453152027) * t) + 1.421413741) * t - 0.284496736) * t +
                     0.254829592) * t * exp(-x * x);
    return s * y;
}

float noise_erfinv(float x) {
    x = clamp(x, -0.999999, 0.999999);
    float w = -log((1.0 - x) * (1.0 + x));
    float p;
    if (w < 5.0) {
        w -= 2.5;
        p = 2.81022636e-08;
        p = 3.43273939e-07 + p * w;
        p = -3.5233877e-06 + p * w;
        p = -4.39150654e-06 + p * w;
        p = 0.00021858087 + p * w;
        p = -0.00125372503 + p * w;
        p = -0.00417768164 + p * w;
        p = 0.246640727 + p * w;
        p = 1.50140941 + p * w;
    } else {
        w = sqrt(w) - 3.0;
        p = -0.000200214257;
        p = 0.000100950558 + p * w;
        p = 0.00134934322 + p * w;
        p = -0.00367342844 + p * w;
        p = 0.00573950773 + p * w;
        p = -0.0076224613 + p * w;
        p = 0.00943887047 + p * w;
        p = 1.00167406 + p * w;
        p = 2.83297682 + p * w;
    }
    return p * x;
}

// Log-normal frequency truncated to [F_L, F_H] by inverse CDF, u uniform in [0, 1).
float noise_sample_frequency(vec4 band, float u) {
    if (!(band.y > band.x)) return 0.0;
    float lo = log(band.x);
    float hi = log(band.y);
    if (!(band.w > 1e-6)) return exp(band.z);
    const float r2 = 1.41421356;
    float e_lo = noise_erf((lo - band.z) / (band.w * r2));
    float e_hi = noise_erf((hi - band.z) / (band.w * r2));
    float z = noise_erfinv(e_lo + (e_hi - e_lo) * u) * r2;
    return exp(clamp(band.z + band.w * z, lo, hi));
}

// Laplacian level whose centre frequency a blur σ attenuates to p (Tariq Eq. 6).
float noise_laplacian_level(float sigma_px, float p) {
    if (!(sigma_px > 1e-6)) return 0.0;
    float f_p = sqrt(-2.0 * log(p)) / (2.0 * kNoisePi * sigma_px);
    return max(0.0, -log2(f_p) - 0.5);
}

// lowbias32 and its uniform stream, bit-identical to hash_u32()/hash_to_unit().
uint noise_hash(uint x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

float noise_unit(uint h) { return float(h >> 8) * (1.0 / 16777216.0); }

uint noise_cell_seed(int ci, int cj, uint seed) {
    return noise_hash((uint(ci) * 73856093u) ^ (uint(cj) * 19349663u) ^ seed);
}

#endif
