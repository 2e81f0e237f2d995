// Pooled PSNR and SSIM: squared errors summed over every frame before the one log, no cap.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "fovea/metrics/pooling.hpp"

namespace fovea::metrics {
namespace {

TEST(PooledPsnr, OneLogOverSummedErrorsNotAMeanOfDecibels) {
    // Frame A: every sample off by 1 (MSE 1, 48.13 dB); frame B: identical (+inf dB).
    // Pooled MSE is 0.5 -> 51.14 dB; the old mean of capped dB would say (48.13 + 100) / 2.
    const std::vector<uint8_t> ref(3 * 4, 100), off(3 * 4, 101);
    const std::vector<int8_t> labels(4, 0);
    RegionSums sq(1);
    sq.add(squared_error_map({2, 2, off}, {2, 2, ref}), labels);
    sq.add(squared_error_map({2, 2, ref}, {2, 2, ref}), labels);
    EXPECT_NEAR(psnr_db(sq.sum(0), 3 * sq.count(0)), 10 * std::log10(255.0 * 255.0 / 0.5), 1e-9);
}

TEST(PooledPsnr, IdenticalIsInfiniteAndEmptyIsNaN) {
    EXPECT_EQ(psnr_db(0.0, 12.0), INFINITY);
    EXPECT_TRUE(std::isnan(psnr_db(0.0, 0.0)));
    EXPECT_TRUE(std::isnan(psnr_db(5.0, 0.0)));
    EXPECT_NEAR(psnr_db(255.0 * 255.0, 1.0), 0.0, 1e-12);
}

TEST(RegionSums, CountsOnlyLabelledFinitePixels) {
    RegionSums s(2);
    s.add(std::vector<float>{1, 2, 3, NAN, 5}, std::vector<int8_t>{0, 1, -1, 0, 7});
    EXPECT_DOUBLE_EQ(s.sum(0), 1);
    EXPECT_DOUBLE_EQ(s.count(0), 1);
    EXPECT_DOUBLE_EQ(s.mean(1), 2);
    RegionSums empty(1);
    EXPECT_TRUE(std::isnan(empty.mean(0)));
}

TEST(Ssim, IdenticalIsOneAndNoiseLowersIt) {
    std::vector<uint8_t> a(3 * 32 * 16), b;
    for (size_t i = 0; i < a.size(); ++i) a[i] = uint8_t((i * 37) % 251);
    b = a;
    for (size_t i = 0; i < b.size(); i += 7) b[i] = uint8_t(255 - b[i]);
    for (float v : ssim_map({32, 16, a}, {32, 16, a})) EXPECT_NEAR(v, 1.0, 1e-5);
    double mean = 0;
    for (float v : ssim_map({32, 16, b}, {32, 16, a})) mean += v / (32 * 16);
    EXPECT_LT(mean, 0.9);
}

}  // namespace
}  // namespace fovea::metrics
