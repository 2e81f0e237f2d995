// CPU reference model of Fovea's temporal anti-aliasing (Patney 2016 §4.2–4.3, variance sampling
// after Karis 2014 / Salvi 2016). The GPU pass (shaders/taa_*.comp) follows these functions step
// for step; tests compare the two. Pure functions, callable from any thread.
//
// Working space: colour is range-compressed with the reversible tone map T(c) = c / (1 + max(c))
// before anything is accumulated, so HDR values up to 10^4 keep the moments (squares!) finite in
// half precision and 1/255 means the same thing in bright and dark regions.
#pragma once

#include <array>
#include <cstdint>

#include "image_model.hpp"

namespace fovea::vk::post {

struct Vec3 {
    float x = 0, y = 0, z = 0;
};

// ---- jitter ----------------------------------------------------------------------------------

// Radical inverse of `index` in `base` (Halton). index 0 gives 0.
float halton(std::uint32_t index, std::uint32_t base);

// Sub-pixel jitter in pixels, in [-0.5, 0.5)², from Halton(2,3) indices 1..length, repeating.
struct Jitter {
    float x = 0;
    float y = 0;
};
Jitter halton_jitter(std::uint64_t frame, std::uint32_t length);

// ---- colour spaces ---------------------------------------------------------------------------

Vec3 rgb_to_ycocg(Vec3 rgb);
Vec3 ycocg_to_rgb(Vec3 ycocg);
// Reversible tone map; negative and non-finite inputs are treated as 0 (NaN) or clamped (inf).
Vec3 tonemap_forward(Vec3 rgb);
Vec3 tonemap_inverse(Vec3 t);

// ---- moments and the clamp box ---------------------------------------------------------------

struct Moments {
    Vec3 m1;  // mean
    Vec3 m2;  // mean of squares
};
// First two raw moments over the 3×3 window around (x, y), clamp-to-edge. `img` has ≥ 3 channels.
Moments moments_3x3(const Image& img, int x, int y);

struct ClampBox {
    Vec3 centre;
    Vec3 extent;  // γσ per component, σ = sqrt(max(m2 − m1², 0))
};
ClampBox clamp_box(const Moments& m, float gamma);
// Grows the box to contain the current sample: otherwise a pixel outside μ ± γσ (a thin feature)
// would be pulled toward its neighbourhood mean forever and never converge to itself.
ClampBox include_sample(const ClampBox& box, Vec3 sample);
// Moves `v` along the line to the box centre until it lies inside the box (Playdead's clip).
Vec3 clip_toward_centre(Vec3 v, const ClampBox& box);

// ---- history filter and blend factor ---------------------------------------------------------

// Catmull-Rom weights for taps at −1, 0, +1, +2 relative to floor(position), t in [0, 1).
std::array<float, 4> catmull_rom_weights(float t);

// Catmull-Rom resampling of all channels of `img` at continuous position (x, y) (texel centres
// at integer + 0.5, clamp to edge), as Jimenez's 5-tap approximation (Filmic SMAA, SIGGRAPH
// 2016) that the GPU runs with bilinear fetches: the middle taps of each axis merge into one
// bilinear fetch and the four corner taps of the 4×4 kernel are dropped, weights renormalized.
// Up to 4 channels.
std::array<float, 4> catmull_rom_5tap(const Image& img, float x, float y);

struct SaccadeParams {
    float alpha = 0.1f;
    float alpha_max = 1.0f / 3.0f;
    float beta = 0.25f;
    bool enabled = true;
};
// α' = ω·α_max + (1 − ω)·α, ω = clamp((S_{t−1} − S_t)/β, 0, 1): only fovea-ward changes speed up.
float saccade_alpha(float s_prev, float s_cur, const SaccadeParams& p);

// ---- the whole pass --------------------------------------------------------------------------

struct TaaParams {
    SaccadeParams saccade;
    float gamma = 1.0f;             // clamp box half-size in σ
    float depth_tolerance = 0.05f;  // relative depth change that counts as a disocclusion
    int moment_levels = 5;          // LOD = 4·S_t needs levels 0..4
    bool half_storage = false;      // round moments and history to IEEE half (rgba16f path)
};

// One frame's inputs. motion: 2 channels, pixels, current − previous (the G-buffer contract):
// from the pixel's unjittered centre to the previous position of the surface its jittered
// sample hit, so the flow of the pixel centre is motion + jitter (as cps and layers read it).
struct TaaFrame {
    const Image* colour = nullptr;  // ≥ 3 channels, linear, HDR allowed
    const Image* depth = nullptr;   // 1 channel (any monotonic depth; compared relatively)
    const Image* motion = nullptr;  // 2 channels; nullptr = static
    const Image* rate = nullptr;    // 1 channel, normalized shading rate S_t in [0, 1]
    bool camera_cut = false;        // drop all history
    Jitter jitter{};                // this frame's sub-pixel jitter (pixels)
};

// Persistent state between frames: tone-mapped RGB + accumulated S (4 ch) and depth.
struct TaaHistory {
    Image colour;
    Image depth;
    bool valid = false;
};

// Moments of the tone-mapped YCoCg colour (6 channels: m1.xyz, m2.xyz), pre-filtered into a chain.
MipChain taa_moment_chain(const Image& colour, int levels, bool half_storage);

// Resolves one frame, updates `history`, returns linear RGB (3 channels).
Image taa_resolve(const TaaFrame& frame, TaaHistory& history, const TaaParams& params);

// The converged output in the working space (tone-mapped RGB), for drift and recovery checks.
Image taa_history_tonemapped(const TaaHistory& history);

}  // namespace fovea::vk::post
