// Metric tests: ATD, Haar wavelet energy, RMS contrast and radial band energy on known inputs.
#include <gtest/gtest.h>

#include <cmath>

#include "metrics_model.hpp"
#include "test_images.hpp"

namespace fovea::vk::post {
namespace {

TEST(Atd, ZeroForAPerfectlyBackProjectedPanAndPositiveWithoutIt) {
    const Image tex = testing::texture(48, 16);
    Image prev(32, 16, 3), cur(32, 16, 3);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x)
            for (int c = 0; c < 3; ++c) {
                prev.at(x, y, c) = tex.at(x, y, c);
                cur.at(x, y, c) = tex.at(x + 2, y, c);  // camera moved 2 px right
            }
    Image motion(32, 16, 2, 0.0f);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x) motion.at(x, y, 0) = -2.0f;  // content moved 2 px left
    const Image py = tonemapped_luminance(prev);
    const Image cy = tonemapped_luminance(cur);
    const AtdResult r = average_temporal_difference(py, cy, &motion);
    EXPECT_NEAR(r.mean, 0.0, 1e-6);
    EXPECT_EQ(r.skipped, 16u * 2u);  // the right two columns came from off screen
    EXPECT_GT(average_temporal_difference(py, cy, nullptr).mean, 0.01);
}

TEST(Atd, MeasuresAConstantFlickerExactly) {
    const Image a(8, 8, 3, 1.0f), b(8, 8, 3, 3.0f);  // tone-mapped 0.5 and 0.75
    EXPECT_NEAR(
        average_temporal_difference(tonemapped_luminance(a), tonemapped_luminance(b), nullptr).mean,
        0.25, 1e-6);
}

TEST(HaarWavelet, CheckerboardEnergyLivesAtTheFinestLevel) {
    Image img(64, 64, 1);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) img.at(x, y) = ((x + y) & 1) ? 1.0f : 0.0f;
    EccentricityBands bands;
    bands.gaze_x = bands.gaze_y = 32;
    bands.pixels_per_degree = 1;
    bands.edges_deg = {0, 16, 100};
    const WaveletStats s = haar_wavelet_analysis(img, bands, 5);
    EXPECT_NEAR(s.mean_energy[0][0], 1.0, 1e-6);  // HH = (a − b − c + d)/2 = ±1
    EXPECT_NEAR(s.max_energy[0][1], 1.0, 1e-6);
    for (int l = 1; l < 5; ++l) EXPECT_NEAR(s.max_energy[std::size_t(l)][0], 0.0, 1e-9);
}

TEST(RmsContrast, OfAKnownSquareWave) {
    Image img(64, 64, 1);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) img.at(x, y) = (x & 1) ? 0.75f : 0.25f;
    EccentricityBands bands;
    bands.gaze_x = bands.gaze_y = 32;
    bands.pixels_per_degree = 1;
    bands.edges_deg = {0, 1000};
    EXPECT_NEAR(rms_contrast_by_eccentricity(img, bands, 8)[0], 0.5, 1e-6);
}

TEST(RadialBandEnergy, FindsASinusoidAtItsFrequency) {
    Image img(64, 64, 1);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) img.at(x, y) = std::cos(2 * 3.14159265f * 8 * x / 64.0f);
    const double in = radial_band_energy(img, 0.12f, 0.13f);  // 8/64 = 0.125 cpp
    const double all = radial_band_energy(img, 0.0f, 1.0f);
    EXPECT_NEAR(in / all, 1.0, 1e-6);
    EXPECT_EQ(radial_band_energy(Image(48, 64, 1), 0, 1), -1.0);
}

}  // namespace
}  // namespace fovea::vk::post

#include "bench_metrics.hpp"

namespace fovea::vk::post {
namespace {

TEST(BenchMetrics, AtdAccumulatorAndRecoveryCounterOnKnownFrames) {
    AtdAccumulator atd;
    const Image a(8, 8, 3, 1.0f), b(8, 8, 3, 3.0f);
    atd.add_frame(a, nullptr);
    atd.add_frame(b, nullptr);
    atd.add_frame(a, nullptr);
    EXPECT_EQ(atd.frames(), 2);
    EXPECT_NEAR(atd.mean(), 0.25, 1e-6);
    RecoveryCounter rc(4, 4, 3);
    rc.add_frame(b);
    rc.add_frame(Image(8, 8, 3, 1.01f));
    rc.add_frame(a);
    EXPECT_EQ(rc.frames(a), 2);  // 1.01 is within 1/255 in tone-mapped luminance
    std::vector<std::uint8_t> bytes(2 * 2 * 2 * 2, 0);
    bytes[1] = 0x3c;  // 1.0 in half
    const Image h = decode_half_image(bytes, 2, 2, 2, 1);
    EXPECT_EQ(h.at(0, 0), 1.0f);
    EXPECT_EQ(h.at(1, 0), 0.0f);
}

}  // namespace
}  // namespace fovea::vk::post
