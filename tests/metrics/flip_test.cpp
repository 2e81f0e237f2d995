// The CPU LDR-FLIP reference against NVIDIA's own numbers (flip_vectors.hpp), its pooling, and
// its behaviour at degenerate inputs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <map>

#include "flip_vectors.hpp"
#include "fovea/metrics/flip.hpp"

namespace fovea::metrics {
namespace {

using testing::flip_vectors;
using testing::kMeanTolerance;
using testing::kPixelTolerance;

TEST(FlipCpu, MatchesNvidiaVectorsForEveryPairAndPpd) {
    const auto& v = flip_vectors();
    if (v.cases.empty()) GTEST_SKIP() << "no FLIP vectors in " << v.dir;
    ASSERT_EQ(v.cases.size(), 21u);
    const Rgb8Image& ref = v.image("ref.png");
    std::map<double, FlipReference> refs;  // the reference filtered once per ppd
    for (const auto& c : v.cases) {
        SCOPED_TRACE(c.pair + " at " + c.ppd_label + " ppd");
        auto it = refs.find(c.ppd);
        if (it == refs.end())
            it = refs.emplace(c.ppd, FlipReference(ref.view(),
                                                   PpdField::uniform(ref.width, ref.height, c.ppd)))
                     .first;
        const std::vector<float> map = it->second.compare(v.image(c.test_file).view());
        const FlipPooled p = pool_flip(map);
        EXPECT_NEAR(p.mean, c.mean, kMeanTolerance);
        EXPECT_NEAR(p.weighted_median, c.weighted_median, kMeanTolerance);
        EXPECT_NEAR(p.weighted_quartile1, c.weighted_q1, kMeanTolerance);
        EXPECT_NEAR(p.weighted_quartile3, c.weighted_q3, kMeanTolerance);
        EXPECT_NEAR(p.max, c.max, kPixelTolerance);
        double worst = 0;
        for (size_t i = 0; i < c.pixels.size(); ++i) {
            const auto& px = c.pixels[i];
            const double got = map[size_t(px.y) * ref.width + px.x];
            if (i < c.listed_pixels) {
                EXPECT_NEAR(got, px.flip, kPixelTolerance) << "pixel " << px.x << "," << px.y;
            }
            worst = std::max(worst, std::fabs(got - px.flip));
        }
        EXPECT_LE(worst, kPixelTolerance) << "worst of the listed and grid pixels";
        std::printf("%-10s %-7s ppd: mean %.6f (NVIDIA %.6f, %+.1e), worst of %zu pixels %.1e\n",
                    c.pair.c_str(), c.ppd_label.c_str(), p.mean, c.mean, p.mean - c.mean,
                    c.pixels.size(), worst);
    }
}

TEST(FlipCpu, FilterRadiiAreThePapersThreeStandardDeviations) {
    // vectors.json derived_parameters: 21x21 colour and radius-9 feature kernels at 67 ppd,
    // 11x11 and radius 4 at 30 ppd.
    EXPECT_EQ(flip_colour_radius(67.0), 10);
    EXPECT_EQ(flip_feature_radius(67.0), 9);
    EXPECT_EQ(flip_colour_radius(kFlipDefaultPpd), 10);
    EXPECT_EQ(flip_colour_radius(30.0), 5);
    EXPECT_EQ(flip_feature_radius(30.0), 4);
    EXPECT_NEAR(kFlipDefaultPpd, 67.02064327658225, 1e-12);
}

TEST(FlipPooling, WeightedPercentileIsTheToolsDefinition) {
    // sorted 1, 2, 3, 4 (sum 10): 50 % = 5 is first reached at 3 (1 + 2 + 3 = 6): (3 + 4) / 2.
    const std::vector<float> m = {4, 1, 3, 2};
    EXPECT_DOUBLE_EQ(weighted_percentile(m, 50), 3.5);
    // 25 % = 2.5 is reached at 2 (1 + 2 = 3): (2 + 3) / 2.
    EXPECT_DOUBLE_EQ(weighted_percentile(m, 25), 2.5);
    // The last value has no successor: it is used twice.
    EXPECT_DOUBLE_EQ(weighted_percentile(m, 100), 4.0);
    const FlipPooled p = pool_flip(m);
    EXPECT_DOUBLE_EQ(p.mean, 2.5);
    EXPECT_DOUBLE_EQ(p.min, 1.0);
    EXPECT_DOUBLE_EQ(p.max, 4.0);
}

TEST(FlipPooling, SkipsNonFiniteValuesAndEmptyMapsAreNaN) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const FlipPooled p = pool_flip(std::vector<float>{nan, 0.5f, INFINITY, 0.25f});
    EXPECT_EQ(p.pixels, 2u);
    EXPECT_DOUBLE_EQ(p.mean, 0.375);
    EXPECT_TRUE(std::isnan(pool_flip(std::vector<float>{}).mean));
    EXPECT_TRUE(std::isnan(pool_flip(std::vector<float>{nan}).weighted_median));
    EXPECT_TRUE(std::isnan(weighted_percentile(std::vector<float>{}, 50)));
}

// Stability on purpose: flat, saturated and single-pixel images, extreme ppd.
TEST(FlipCpu, DegenerateImagesStayFiniteAndInRange) {
    const auto solid = [](uint32_t w, uint32_t h, uint8_t r, uint8_t g, uint8_t b) {
        Rgb8Image img{w, h, {}};
        for (size_t i = 0; i < size_t(w) * h; ++i) img.rgb.insert(img.rgb.end(), {r, g, b});
        return img;
    };
    for (double ppd : {0.05, 1.0, 67.0, 400.0}) {
        SCOPED_TRACE("ppd " + std::to_string(ppd));
        const Rgb8Image black = solid(5, 3, 0, 0, 0), white = solid(5, 3, 255, 255, 255);
        const Rgb8Image green = solid(5, 3, 0, 255, 0), blue = solid(5, 3, 0, 0, 255);
        const PpdField f = PpdField::uniform(5, 3, ppd);
        for (float v : flip_map(black.view(), black.view(), f)) EXPECT_EQ(v, 0.f);
        for (const auto* pair : {&white, &green, &blue}) {
            for (float v : flip_map(black.view(), pair->view(), f)) {
                EXPECT_TRUE(std::isfinite(v));
                EXPECT_GE(v, 0.f);
                EXPECT_LE(v, 1.f);
            }
        }
        // Green against blue is the largest colour distance: FLIP 1 on flat fields.
        for (float v : flip_map(green.view(), blue.view(), f)) EXPECT_NEAR(v, 1.0, 1e-6);
        const Rgb8Image one = solid(1, 1, 200, 10, 10), other = solid(1, 1, 10, 200, 10);
        const std::vector<float> m =
            flip_map(one.view(), other.view(), PpdField::uniform(1, 1, ppd));
        ASSERT_EQ(m.size(), 1u);
        EXPECT_TRUE(std::isfinite(m[0]));
    }
}

TEST(FlipCpu, IsSymmetricInReferenceAndTest) {
    const auto& v = flip_vectors();
    if (v.cases.empty()) GTEST_SKIP() << "no FLIP vectors in " << v.dir;
    // A 96 x 64 crop keeps this fast.
    const auto crop = [](const Rgb8Image& src) {
        Rgb8Image c{96, 64, {}};
        for (uint32_t y = 0; y < 64; ++y)
            for (uint32_t x = 0; x < 96; ++x)
                for (int k = 0; k < 3; ++k)
                    c.rgb.push_back(src.rgb[(size_t(y + 200) * src.width + x + 400) * 3 + k]);
        return c;
    };
    const Rgb8Image a = crop(v.image("ref.png")), b = crop(v.image("test_block4x4.png"));
    const PpdField f = PpdField::uniform(96, 64, 40.0);
    const std::vector<float> ab = flip_map(a.view(), b.view(), f),
                             ba = flip_map(b.view(), a.view(), f);
    for (size_t i = 0; i < ab.size(); ++i) EXPECT_NEAR(ab[i], ba[i], 1e-6);
}

}  // namespace
}  // namespace fovea::metrics
