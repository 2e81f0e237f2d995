// Error maps of two 8-bit RGB images and their pooling over labelled pixels (eccentricity bands,
// the fovea) and over frames. PSNR comes from the squared errors summed over every pixel of every
// frame, then one log (an average of per-frame dB would let one near-lossless frame lift the
// figure); identical images give +inf, never a capped number. SSIM is the mean of its map over
// every pixel of every frame. Pure functions; a RegionSums is used by one thread at a time.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "fovea/metrics/flip.hpp"

namespace fovea::metrics {

// Per pixel, the sum over the 3 channels of (test - reference)^2, in 8-bit code values squared.
std::vector<float> squared_error_map(const Rgb8View& test, const Rgb8View& reference);

// SSIM (Wang, Bovik, Sheikh, Simoncelli 2004) of the luma (Rec. 601 weights, 0..255): Gaussian
// window sd 1.5 (11 taps, clamped borders), K1 = 0.01, K2 = 0.03.
std::vector<float> ssim_map(const Rgb8View& test, const Rgb8View& reference);

// Sums and counts of a per-pixel map over labelled regions, accumulated over frames.
class RegionSums {
public:
    explicit RegionSums(int regions) : sum_(regions, 0.0), count_(regions, 0.0) {}
    // labels[i] in [0, regions) counts values[i] there; other labels and non-finite values are
    // skipped. Both spans have one entry per pixel (asserted).
    void add(std::span<const float> values, std::span<const int8_t> labels);
    int regions() const { return int(sum_.size()); }
    double sum(int region) const { return sum_.at(region); }
    double count(int region) const { return count_.at(region); }
    double mean(int region) const;  // NaN when the region saw no pixel

private:
    std::vector<double> sum_, count_;
};

// 10 log10(peak^2 / (squared_error_sum / samples)): +inf for no error, NaN for no samples.
double psnr_db(double squared_error_sum, double samples, double peak = 255.0);

}  // namespace fovea::metrics
