// Reference-model tests for contrast enhancement and Gabor-noise enhancement (no Vulkan).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "enhance_model.hpp"
#include "metrics_model.hpp"
#include "test_images.hpp"

namespace fovea::vk::post {
namespace {

TEST(Calibration, InterpolatesTariqTable2AndClampsOutside) {
    EXPECT_FLOAT_EQ(calibration_for_blur_rate(0.11f).f_e, 0.15f);
    EXPECT_FLOAT_EQ(calibration_for_blur_rate(0.34f).f_e, 0.23f);
    EXPECT_FLOAT_EQ(calibration_for_blur_rate(0.57f).f_e, 0.28f);
    EXPECT_NEAR(calibration_for_blur_rate(0.225f).f_e, 0.19f, 1e-6f);
    EXPECT_FLOAT_EQ(calibration_for_blur_rate(0.0f).f_e, 0.15f);
    EXPECT_FLOAT_EQ(calibration_for_blur_rate(2.0f).f_e, 0.28f);
    EXPECT_FLOAT_EQ(calibration_for_blur_rate(0.34f).s_k, 21.02f);
    EXPECT_FLOAT_EQ(calibration_for_blur_rate(0.57f).s_f, 2.19f);
    EXPECT_FLOAT_EQ(calibration_for_blur_rate(NAN).f_e, 0.15f);
}

TEST(Thibos, InterpolatesTariqTable3) {
    EXPECT_FLOAT_EQ(thibos_limits(0).low_cpd, 60);
    EXPECT_FLOAT_EQ(thibos_limits(10).low_cpd, 10.5f);
    EXPECT_FLOAT_EQ(thibos_limits(10).high_cpd, 26);
    EXPECT_FLOAT_EQ(thibos_limits(12.5f).low_cpd, 9.25f);
    EXPECT_FLOAT_EQ(thibos_limits(27.5f).high_cpd, 20.75f);
    EXPECT_FLOAT_EQ(thibos_limits(80).low_cpd, 4);  // beyond 30°: last measurement
    EXPECT_FLOAT_EQ(thibos_limits(-20).high_cpd, 23);
}

TEST(NoiseBand, FollowsTariqEquations1To4) {
    const NoiseBand b = noise_band(20.0f, 2.0f, 40.0f, 2.21f);
    EXPECT_NEAR(b.f_low, 3.0f / (2.0f * 3.14159265f * 2.0f), 1e-5f);  // blur cut-off dominates
    EXPECT_FLOAT_EQ(b.f_high, 0.5f);                                  // display Nyquist
    EXPECT_NEAR(b.mu_n, 0.5f * (std::log(b.f_low) + std::log(0.5f)), 1e-6f);
    EXPECT_NEAR(b.sigma_n, 0.5f * 2.21f * (b.mu_n - std::log(b.f_low)), 1e-6f);
    const NoiseBand huge = noise_band(20.0f, 1e9f, 40.0f, 2.21f);
    EXPECT_FLOAT_EQ(huge.f_low, 5.5f / 40.0f);  // Thibos T_L dominates
    EXPECT_FALSE(huge.empty());
    EXPECT_TRUE(noise_band(20.0f, 0.0f, 40.0f, 2.21f).empty());  // σ → 0: nothing to restore
    EXPECT_TRUE(noise_band(20.0f, 1e-9f, 40.0f, 2.21f).empty());
    EXPECT_TRUE(noise_band(0.0f, 3.0f, 10.0f, 2.21f).empty());  // T_L above Nyquist
}

TEST(NoiseBand, SampledFrequenciesStayInsideTheBandAndCentreOnTheLogMidpoint) {
    const NoiseBand b = noise_band(20.0f, 2.0f, 40.0f, 2.21f);
    int below_mid = 0;
    for (int i = 0; i < 1000; ++i) {
        const float f = sample_band_frequency(b, (float(i) + 0.5f) / 1000.0f);
        ASSERT_GE(f, b.f_low * 0.9999f);
        ASSERT_LE(f, b.f_high * 1.0001f);
        if (std::log(f) < b.mu_n) ++below_mid;
    }
    EXPECT_NEAR(below_mid, 500, 5);
    EXPECT_EQ(sample_band_frequency(noise_band(5, 0, 40, 2), 0.5f), 0.0f);
}

TEST(ErfApprox, MatchesStdErfAndInverts) {
    for (float x = -3.0f; x <= 3.0f; x += 0.25f) {
        EXPECT_NEAR(approx_erf(x), std::erf(x), 2e-6f);
        if (std::fabs(x) < 2.5f) { EXPECT_NEAR(approx_erfinv(std::erf(x)), x, 2e-3f); }
    }
}

TEST(Pyramids, LaplacianReconstructsAndMinMaxBoundTheFootprint) {
    const Image z = testing::zone_plate(64);
    const MipChain g = gaussian_pyramid(z, 6);
    ASSERT_EQ(g.size(), 6u);
    EXPECT_EQ(g[3].width, 8);
    const MipChain lap = laplacian_pyramid(g);
    // Collapse: G_l = L_l + expand(G_{l+1}) must give back the input.
    Image rec = lap.back();
    for (int l = int(lap.size()) - 2; l >= 0; --l) {
        Image up(lap[std::size_t(l)].width, lap[std::size_t(l)].height, 1);
        for (int y = 0; y < up.height; ++y)
            for (int x = 0; x < up.width; ++x)
                up.at(x, y) = lap[std::size_t(l)].at(x, y) +
                              sample_bilinear(rec, (x + 0.5f) / up.width * rec.width,
                                              (y + 0.5f) / up.height * rec.height);
        rec = std::move(up);
    }
    for (std::size_t i = 0; i < z.data.size(); ++i) ASSERT_NEAR(rec.data[i], z.data[i], 1e-5f);
    const MipChain mn = min_pyramid(z, 4);
    const MipChain mx = max_pyramid(z, 4);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            EXPECT_LE(mn[3].at(0, 0), z.at(x, y));
            EXPECT_GE(mx[3].at(0, 0), z.at(x, y));
        }
}

TEST(LaplacianLevel, CoarserForWiderBlur) {
    EXPECT_EQ(laplacian_level_for_blur(0.0f, 0.25f), 0.0f);
    const float l2 = laplacian_level_for_blur(2.0f, 0.25f);
    const float l4 = laplacian_level_for_blur(4.0f, 0.25f);
    EXPECT_NEAR(l4 - l2, 1.0f, 1e-5f);  // doubling σ halves the frequency: one level
    // f_p = sqrt(−2 ln p)/(2πσ) must equal the level's centre 2^−(l+0.5).
    EXPECT_NEAR(std::pow(2.0f, -(l2 + 0.5f)), std::sqrt(-2 * std::log(0.25f)) / (4 * 3.14159265f),
                1e-5f);
}

TEST(ContrastEnhance, LeavesUnblurredPixelsAlone) {
    const Image sharp = testing::pink_noise(64, 64);
    const Image same = contrast_enhance(sharp, Image(64, 64, 1, 0.0f), 0.28f);
    for (std::size_t i = 0; i < same.data.size(); ++i) ASSERT_FLOAT_EQ(same.data[i], sharp.data[i]);
}

// The foveated periphery of a 4K-class display (48 px/deg, Tariq §5.1): the image patch spans
// 18°–24° eccentricity with the gaze off to its left (off screen), blurred with σ growing by
// the blur rate beyond an 8° fovea (Tariq §5.2). Local RMS contrast over 1/3° (16 px) tiles.
TEST(ContrastEnhance, RestoresPeripheralRmsContrastWithin10Percent) {
    const int n = 256;
    const float ppd = 48.0f;
    const float blur_rate = 0.34f;  // arcmin of σ per degree beyond 8°
    EccentricityBands bands;
    bands.gaze_x = -18.0f * ppd;  // gaze 18° left of the patch: off screen
    bands.gaze_y = n / 2.0f;
    bands.pixels_per_degree = ppd;
    bands.edges_deg = {18, 20, 22, 24};
    const Image sharp = testing::pink_noise(n, n);
    Image sigma(n, n, 1);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const float e = std::hypot(x + 0.5f - bands.gaze_x, y + 0.5f - bands.gaze_y) / ppd;
            sigma.at(x, y) = std::max(0.0f, e - 8.0f) * blur_rate / 60.0f * ppd;
        }
    // Foveated image: per-pixel blur interpolated in a stack of uniformly blurred images.
    std::vector<Image> stack;
    for (int s = 0; s <= 20; ++s) stack.push_back(testing::gaussian_blur(sharp, 0.25f * s));
    Image fov(n, n, 1);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const float s = std::min(sigma.at(x, y) / 0.25f, 20.0f);
            const int a = int(s);
            const int b = std::min(a + 1, 20);
            const float t = s - float(a);
            fov.at(x, y) =
                stack[std::size_t(a)].at(x, y) * (1 - t) + stack[std::size_t(b)].at(x, y) * t;
        }
    const Image enh = contrast_enhance(fov, sigma, calibration_for_blur_rate(blur_rate).f_e);
    const auto c_full = rms_contrast_by_eccentricity(sharp, bands, 16);
    const auto c_fov = rms_contrast_by_eccentricity(fov, bands, 16);
    const auto c_enh = rms_contrast_by_eccentricity(enh, bands, 16);
    for (std::size_t b = 0; b < c_full.size(); ++b) {
        std::printf("%g-%g deg: RMS contrast full %.4f foveated %.4f enhanced %.4f\n",
                    bands.edges_deg[b], bands.edges_deg[b + 1], c_full[b], c_fov[b], c_enh[b]);
        EXPECT_LT(c_fov[b], 0.9 * c_full[b]) << "band " << b << " should have lost contrast";
        EXPECT_NEAR(c_enh[b] / c_full[b], 1.0, 0.10) << "band " << b;
    }
}

TEST(GaborNoise, AddsEnergyOnlyInsideTheBandOnABlurredZonePlate) {
    const int n = 256;
    const float sigma_px = 3.0f;
    const Image fov = testing::gaussian_blur(testing::zone_plate(n, 0.3f), sigma_px);
    const Image sigma(n, n, 1, sigma_px);
    const Image ecc(n, n, 1, 20.0f);
    NoiseParams p;
    p.pixels_per_degree = 40.0f;
    const NoiseBand band = noise_band(20.0f, sigma_px, p.pixels_per_degree, p.s_f);
    const Image noise = gabor_noise({&fov, &sigma, &ecc}, p);
    Image out = fov;
    for (std::size_t i = 0; i < out.data.size(); ++i) out.data[i] += noise.data[i];
    // A Gabor kernel of width a has a Gaussian spectrum of σ_f = a/√(2π): allow 2σ_f of spread.
    const float spread = 2.0f * p.kernel_bandwidth / std::sqrt(2.0f * 3.14159265f);
    const float lo = band.f_low - spread;
    const double below_before = radial_band_energy(fov, 0.0f, lo);
    const double below_after = radial_band_energy(out, 0.0f, lo);
    const double in_before = radial_band_energy(fov, band.f_low, band.f_high);
    const double in_after = radial_band_energy(out, band.f_low, band.f_high);
    std::printf("band [%.3f, %.3f] cpp; below %.3f: %.4g -> %.4g (%.2f %%); in band %.4g -> %.4g\n",
                band.f_low, band.f_high, lo, below_before, below_after,
                100.0 * (below_after - below_before) / below_before, in_before, in_after);
    EXPECT_LT(std::fabs(below_after - below_before) / below_before, 0.05);
    EXPECT_GT(in_after, 2.0 * in_before);  // the noise really adds detail in the band
}

TEST(GaborNoise, ImpulsesAreFixedAndDegenerateBlurIsSafe) {
    const int n = 64;
    const Image fov = testing::gaussian_blur(testing::zone_plate(n, 0.3f), 2.0f);
    const Image ecc(n, n, 1, 20.0f);
    NoiseParams p;
    const Image s2(n, n, 1, 2.0f);
    const Image a = gabor_noise({&fov, &s2, &ecc}, p);
    const Image b = gabor_noise({&fov, &s2, &ecc}, p);
    EXPECT_EQ(a.data, b.data);  // constant seed: same positions, same noise
    double energy = 0;
    for (float v : a.data) energy += double(v) * v;
    EXPECT_GT(energy, 0.0);

    const Image s0(n, n, 1, 0.0f);  // σ → 0: no blur, no noise
    for (float v : gabor_noise({&fov, &s0, &ecc}, p).data) ASSERT_EQ(v, 0.0f);
    Image shuge(n, n, 1, 1e30f);  // huge σ (and a NaN): finite, bounded by the headroom
    shuge.at(3, 3) = NAN;
    for (float v : gabor_noise({&fov, &shuge, &ecc}, p).data) {
        ASSERT_TRUE(std::isfinite(v));
        ASSERT_LT(std::fabs(v), 1.0f);
    }
    for (float v : contrast_enhance(fov, shuge, 0.28f).data) ASSERT_TRUE(std::isfinite(v));
    Image ecc_off(n, n, 1, 500.0f);  // gaze far off screen
    for (float v : gabor_noise({&fov, &s2, &ecc_off}, p).data) ASSERT_TRUE(std::isfinite(v));
}

}  // namespace
}  // namespace fovea::vk::post
