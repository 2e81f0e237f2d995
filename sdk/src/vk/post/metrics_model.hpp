// Image metrics for temporal stability and frequency content (Patney 2016 §4.4): average temporal
// difference, 2D Haar wavelet energy and RMS contrast per eccentricity band, and radial Fourier
// band energy (for the noise band check). CPU functions over images; the bench and tests call
// them from any thread.
#pragma once

#include <cstddef>
#include <vector>

#include "image_model.hpp"

namespace fovea::vk::post {

// Reinhard c/(1 + c) per channel, then Rec. 709 luma: the "post tone-mapping luminance".
Image tonemapped_luminance(const Image& rgb);

struct AtdResult {
    double mean = 0;         // mean |Y_t − back-projected Y_{t−1}|, in tone-mapped units [0, 1]
    std::size_t pixels = 0;  // pixels averaged
    std::size_t skipped = 0;  // back-projection left the screen or a value was not finite
};
// motion: 2 channels, pixels, current − previous position; nullptr = static camera.
AtdResult average_temporal_difference(const Image& prev_y, const Image& cur_y, const Image* motion);

struct EccentricityBands {
    float gaze_x = 0;  // pixels
    float gaze_y = 0;
    float pixels_per_degree = 40;
    std::vector<float> edges_deg{0, 5, 10, 20, 30, 45, 90};  // band b = [edges[b], edges[b+1])
    int band_of(float px, float py) const;                   // −1 outside every band
    std::size_t count() const { return edges_deg.size() - 1; }
};

struct WaveletStats {
    // [level 1..levels][band]; level l covers 2^l × 2^l pixels. Energy = LH² + HL² + HH².
    std::vector<std::vector<double>> mean_energy;
    std::vector<std::vector<double>> max_energy;
};
WaveletStats haar_wavelet_analysis(const Image& luma, const EccentricityBands& bands,
                                   int levels = 5);

// Mean over tile×tile tiles of (std / mean) of luminance, per band (tile centre decides the band).
std::vector<double> rms_contrast_by_eccentricity(const Image& luma, const EccentricityBands& bands,
                                                 int tile = 8);

// Sum of |FFT|² over radial frequencies in [f_lo, f_hi) cycles per pixel, DC excluded.
// Width and height must be powers of two.
double radial_band_energy(const Image& luma, float f_lo, float f_hi);

}  // namespace fovea::vk::post
