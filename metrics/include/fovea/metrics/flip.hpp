// LDR-FLIP (Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström, Fairchild 2020, "FLIP: A
// Difference Evaluator for Alternating Images", with NVIDIA's erratum: the achromatic channel is
// normalised by division by 116): the CPU reference, in double precision. The GPU version
// (gpu_flip.hpp, shaders/flip_*.comp) is tested against it, and both against the authors' vectors
// (../shared/data/flip/vectors.json).
//
// Pixels per degree may differ per column and per row (PpdField): the filters are separable, so
// filtering each row at ppd_x of its column and each column at ppd_y of its row is exactly the
// 2-D kernel of a pixel seen at (ppd_x, ppd_y). With a uniform field this is the paper's metric.
// All functions are pure and thread-safe; a FlipReference may be shared by threads.
#pragma once

#include <cstdint>
#include <numbers>
#include <span>
#include <vector>

namespace fovea::metrics {

// The FLIP tool's default: a 0.7 m wide 3840-pixel monitor seen from 0.7 m (67.02 ppd, which the
// tool prints as "67").
inline constexpr double kFlipDefaultPpd = 0.7 * (3840.0 / 0.7) * std::numbers::pi / 180.0;

// RGB images of sRGB-encoded (display) values, 3 interleaved channels, row-major, origin top
// left. 8-bit: 0..255; float: 0..1 (clamped).
struct Rgb8View {
    uint32_t width = 0, height = 0;
    std::span<const uint8_t> rgb;
};
struct RgbFloatView {
    uint32_t width = 0, height = 0;
    std::span<const float> rgb;
};

// Pixels per degree per column (x: `width` values) and per row (y: `height` values), each > 0.
struct PpdField {
    std::vector<double> x, y;
    static PpdField uniform(uint32_t width, uint32_t height, double ppd);
    double max() const;
};

// Filter radii (pixels) the paper derives from the ppd: the colour (CSF) kernels reach 3 standard
// deviations of the widest Gaussian, the edge and point kernels 3 sd of w = 0.082 degrees / 2.
int flip_colour_radius(double ppd);
int flip_feature_radius(double ppd);

// The reference image filtered once (colour and feature pipelines), compared with any number of
// test images of the same size.
class FlipReference {
public:
    FlipReference(const RgbFloatView& reference, PpdField ppd);
    FlipReference(const Rgb8View& reference, PpdField ppd);
    uint32_t width() const { return width_; }
    uint32_t height() const { return height_; }
    // The per-pixel LDR-FLIP map in [0, 1], row-major. The size must match (asserted).
    std::vector<float> compare(const RgbFloatView& test) const;
    std::vector<float> compare(const Rgb8View& test) const;

    // Per pixel after both pipelines: Hunt-adjusted L*a*b* of the CSF-filtered colour, and the
    // edge and point detector magnitudes of the achromatic channel.
    struct Filtered {
        double l, a, b, edge, point;
    };

private:
    uint32_t width_ = 0, height_ = 0;
    PpdField ppd_;
    std::vector<Filtered> filtered_;
};

// One-shot convenience: FlipReference(reference, ppd).compare(test).
std::vector<float> flip_map(const Rgb8View& reference, const Rgb8View& test, const PpdField& ppd);

// The FLIP tool's pooled values. Weighted percentiles follow the tool's definition (each value
// weighted by itself): sort to s_i; find the first i whose running sum reaches p % of the total;
// the mean of s_i and s_i+1. Non-finite values are skipped; all NaN for an empty map.
struct FlipPooled {
    double mean = 0, weighted_median = 0, weighted_quartile1 = 0, weighted_quartile3 = 0;
    double min = 0, max = 0;
    size_t pixels = 0;  // finite values pooled
};
FlipPooled pool_flip(std::span<const float> map);
double weighted_percentile(std::span<const float> map, double percent);

}  // namespace fovea::metrics
