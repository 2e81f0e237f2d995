// Internal to fovea::metrics: the LDR-FLIP constants and 1-D kernels the CPU reference filters
// with, shared with the GPU version (gpu_flip.cpp uploads exactly these).
#pragma once

#include <array>
#include <vector>

namespace fovea::metrics::detail {

using Vec3 = std::array<double, 3>;
using Mat3 = std::array<Vec3, 3>;  // row-major

const Mat3& rgb_to_xyz();  // linear sRGB -> CIE XYZ (D65)
const Mat3& xyz_to_rgb();
const Vec3& white();              // XYZ of linear RGB (1, 1, 1)
double cmax();                    // the green-blue Hunt-adjusted HyAB distance to the power qc
double srgb_to_linear(double v);  // the sRGB transfer function's inverse, v in [0, 1]
inline constexpr double kQc = 0.7, kQf = 0.5;   // colour and feature exponents
inline constexpr double kPc = 0.4, kPt = 0.95;  // redistribution: pc * cmax maps to pt

// One axis of every kernel at one ppd. Y' and Cx: normalised Gaussians. Cz: a sum of two
// Gaussians, kept as its two raw parts (sqrt of each 2-D amplitude times the 1-D Gaussian),
// because the 2-D sum that normalises it couples both axes: divide the filtered Cz by
// cz1_sum(x) cz1_sum(y) + cz2_sum(x) cz2_sum(y). Features: the Gaussian g (sums to 1), its first
// and second derivatives dg, ddg (positive weights sum to +1, negative to -1, per axis as in 2-D).
struct AxisFilters {
    int colour_radius = 0, feature_radius = 0;
    std::vector<double> y, cx, cz1, cz2;  // index i + colour_radius
    double cz1_sum = 0, cz2_sum = 0;
    std::vector<double> g, dg, ddg;  // index i + feature_radius
};
AxisFilters make_axis_filters(double ppd);

}  // namespace fovea::metrics::detail
