// Pure analysis behind `fovea bench`: the Pareto front of time against error, percentiles, and
// Patney 2016's average temporal difference (ATD) of consecutive tone-mapped frames after
// back-projecting the previous one with the G-buffer's motion vectors. No Vulkan, unit-tested in
// tests/bench.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace fovea::bench {

// One benchmarked variant: cost (ms/frame) and error (mean FLIP; -dB for PSNR), both lower-better.
struct CostError {
    double cost = 0.0;
    double error = 0.0;
};

// Indices of the points no other point dominates (cost <= and error <=, one strictly), ordered
// by increasing cost. Points with a non-finite cost, a NaN or +inf error are never on the front
// (-inf is the best error: -PSNR of an identical image); of exact duplicates only the first
// index is kept.
std::vector<size_t> pareto_front(const std::vector<CostError>& points);

// Nearest-rank percentile (p in [0, 100]) of v; NaN for an empty v.
double percentile(std::vector<double> v, double p);

// Mean of the finite values of v; NaN when there are none.
double finite_mean(const std::vector<double>& v);

// Display luminance (Rec. 709 weights on the tone-mapped 8-bit values, 0..1) of packed RGB8.
std::vector<float> luminance(const std::vector<uint8_t>& rgb, uint32_t width, uint32_t height);

// The same display luminance from RGBA16F linear pixels as read back, before 8-bit rounding:
// ATD under TAA sits near 1/4 code value, where the rounding of each frame would dominate it.
std::vector<float> luminance_rgba16f(const std::vector<uint8_t>& rgba16f, uint32_t width,
                                     uint32_t height);

// R16G16_SFLOAT pixels as read back (Device::read_image) -> two floats per pixel.
std::vector<float> decode_rg16f(const std::vector<uint8_t>& rg16f);

// ATD between two consecutive frames: mean over the pixels of `current` whose back-projected
// position (pixel centre minus motion, motion = current - previous position in pixels) lies
// inside the previous frame of |L_current - L_previous(back-projected)|, the previous frame
// sampled bilinearly. NaN when no pixel back-projects inside.
double temporal_difference(const std::vector<float>& previous_luma,
                           const std::vector<float>& current_luma,
                           const std::vector<float>& motion_px, uint32_t width, uint32_t height);

}  // namespace fovea::bench
