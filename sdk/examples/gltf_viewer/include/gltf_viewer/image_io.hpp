// Frames as the viewer writes and compares them: the module's RGBA16F linear HDR read back,
// tone-mapped to display sRGB 8-bit (PNG), PSNR within the fovea and per eccentricity band.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "fovea/vk/acuity.hpp"

namespace gltfv {

struct Rgb8 {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> rgb;
};

// c / (1 + c) per channel (reversible, keeps highlights), then the sRGB curve.
Rgb8 tonemap(const std::vector<uint8_t>& rgba16f, uint32_t width, uint32_t height);
// S_t (R16F) as colours: blue full rate, green 2x2, red 4x4.
Rgb8 rate_colours(const std::vector<uint8_t>& r16f, uint32_t width, uint32_t height);
bool write_png(const std::string& path, const Rgb8& image);

// Non-finite channels and pixels black (all channels 0) of an RGBA16F frame.
struct FrameHealth {
    size_t non_finite = 0;
    size_t black = 0;
};
FrameHealth frame_health(const std::vector<uint8_t>& rgba16f);

struct Psnr {
    double fovea_db = 0.0;                                 // capped at 100 (identical pixels)
    std::array<double, fovea::vk::kBandCount> bands_db{};  // NaN for empty bands
};
// 8-bit PSNR of `test` against `reference`, pixels within foveal_radius_deg of the gaze, and
// per eccentricity band (fovea::vk::kBandEdgesDeg).
Psnr psnr(const Rgb8& test, const Rgb8& reference, const fovea::vk::EyeDisplay& display,
          const fovea::vk::ResolvedGaze& gaze, float foveal_radius_deg);

}  // namespace gltfv
