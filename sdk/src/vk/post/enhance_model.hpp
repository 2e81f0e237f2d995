// CPU reference model of Fovea's peripheral enhancement, run after TAA on display-referred
// (gamma-encoded) luminance: Patney 2016's contrast enhancement and Tariq 2022's sparse Gabor
// noise (§4). The GPU passes (shaders/enhance_*.comp) mirror these functions; tests compare them.
// Pure functions, callable from any thread.
//
// Units: σ (the local foveation blur) in pixels, eccentricity in degrees, frequencies in cycles per
// pixel unless a name says cpd; `pixels_per_degree` converts.
#pragma once

#include <cstdint>

#include "image_model.hpp"

namespace fovea::vk::post {

// ---- calibrated parameters (Tariq 2022, Table 2), linear in the blur rate, clamped at the ends --

struct EnhanceCalibration {
    float f_e = 0;  // contrast enhancement strength
    float s_k = 0;  // noise amplitude scale
    float s_f = 0;  // noise bandwidth scale
};
EnhanceCalibration calibration_for_blur_rate(float blur_rate_arcmin_per_deg);

// ---- Thibos et al. 1996 limits (Tariq 2022, Table 3), linearly interpolated --------------------

struct ThibosLimits {
    float low_cpd = 0;   // T_L: resolution (aliasing) limit
    float high_cpd = 0;  // T_H: detection limit
};
ThibosLimits thibos_limits(float eccentricity_deg);

// ---- noise frequency band (Tariq Eqs. 1–5) ------------------------------------------------------

struct NoiseBand {
    float f_low = 0;    // F_L = max(T_L(e), 3/(2πσ)), cycles per pixel
    float f_high = 0;   // F_H = min(T_H(e), Nyquist = 0.5)
    float mu_n = 0;     // log-domain mean
    float sigma_n = 0;  // log-domain standard deviation (scaled by s_f)
    bool empty() const { return !(f_high > f_low); }
};
NoiseBand noise_band(float eccentricity_deg, float sigma_px, float pixels_per_degree, float s_f);
// Frequency for a uniform u in [0, 1): log-normal, truncated to [F_L, F_H] by inverse CDF.
float sample_band_frequency(const NoiseBand& band, float u);

// Shared with GLSL bit for bit in intent: erf (Abramowitz–Stegun 7.1.26) and its inverse (Giles).
float approx_erf(float x);
float approx_erfinv(float x);

// ---- pyramids -----------------------------------------------------------------------------------

// Burt–Adelson: 5-tap binomial blur then decimation by 2 (Vulkan mip sizes), clamp-to-edge.
MipChain gaussian_pyramid(const Image& luma, int levels);
// L_l = G_l − expand(G_{l+1}) (bilinear expand); the last level is the Gaussian residual.
MipChain laplacian_pyramid(const MipChain& gaussian);
// Level l holds the min (max) over its 2^l × 2^l footprint.
MipChain min_pyramid(const Image& luma, int levels);
MipChain max_pyramid(const Image& luma, int levels);

// Laplacian level l_p holding the highest frequency that survives a blur σ with attenuation p.
float laplacian_level_for_blur(float sigma_px, float p);

// ---- contrast enhancement (Patney 2016 §4.3) ---------------------------------------------------

// I_avg: the Gaussian pyramid sampled at LOD = log2(1 + √2·σ): level l read back with bilinear
// filtering is a blur of σ ≈ 2^l/√2 (binomial variance (4^l − 1)/3 plus the bilinear's 4^l/6).
float blur_lod(float sigma_px);
// out = I + f_e(1 + σ)(I − I_avg), clamped to [0, 1]. σ = 0 leaves a pixel untouched.
// Reading the "I_avg + f_e(1 + σ)(I − I_avg)" literally would *remove* detail wherever
// f_e(1 + σ) < 1; Tariq §5 describes f_e as scaling the detail *added*, which this form does.
Image contrast_enhance(const Image& luma, const Image& sigma_px, float f_e);
// The blur a coarse pixel of normalized rate S stands for: edge 4^S pixels (S = 0, ½, 1 →
// 1, 2, 4), σ² = (edge² − 1)/12 (box variance beyond the pixel's own).
float blur_sigma_for_rate(float s);
// Display-referred value of a linear HDR channel: (c/(1 + c))^(1/2.2), and its inverse.
float display_encode(float linear);
float display_decode(float display);

// ---- Gabor noise (Tariq 2022 §4) ---------------------------------------------------------------

struct NoiseParams {
    int impulses_per_kernel = 12;  // 12–64 (Tariq §6.3)
    float s_k = 21.02f;
    float s_f = 2.21f;
    float attenuation_p = 0.25f;
    float kernel_bandwidth = 0.06f;  // Gabor envelope width a in cycles per pixel (Tariq §4.4)
    float pixels_per_degree = 40.0f;
    int minmax_level = 3;
    int orientation_level = 3;
    std::uint32_t seed = 0x9e3779b9u;  // constant: impulse positions never move
};

struct NoiseInputs {
    const Image* luma = nullptr;      // display-referred luminance in [0, 1]
    const Image* sigma_px = nullptr;  // local blur σ per pixel
    const Image* ecc_deg = nullptr;   // eccentricity per pixel
};

// Kernel radius (envelope truncated at 5 %) = cell size, and impulses per cell.
float gabor_radius(float bandwidth);
int impulses_per_cell(int impulses_per_kernel);

// Per-pixel Gabor parameters (4 channels): amplitude K (already limited by the local min/max
// headroom), orientation ω in radians, F_L, F_H. An empty band has K = 0. Exposed for GPU tests.
Image noise_parameters(const NoiseInputs& in, const NoiseParams& p);
// Sparse Gabor convolution over the parameter image (Tariq §4.4): 1 channel, std ≈ K locally.
Image synthesize_gabor_noise(const Image& parameters, const NoiseParams& p);
// noise_parameters() then synthesize_gabor_noise(): the additive noise image.
Image gabor_noise(const NoiseInputs& in, const NoiseParams& p);

// 32-bit integer hash (lowbias32) and its use as a uniform stream; identical in GLSL.
std::uint32_t hash_u32(std::uint32_t x);
float hash_to_unit(std::uint32_t h);

}  // namespace fovea::vk::post
