// fovea bench: Pareto front, percentile and ATD back-projection (pure), and the quick bench's
// JSON on a 64x36 frame carrying every method with the keys issues 5-8 require.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "bench_analysis.hpp"
#include "fovea/vk/device.hpp"
#include "fovea/vk/foveator.hpp"

namespace fovea::bench {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(ParetoFront, KeepsOnlyUndominatedPointsByIncreasingCost) {
    // cost (ms), quality (dB)
    const std::vector<CostQuality> p = {
        {10, 30},   // 0: front (cheapest)
        {20, 25},   // 1: dominated by 0
        {30, 40},   // 2: front
        {30, 35},   // 3: same cost as 2, worse
        {25, 40},   // 4: dominates 2 (cheaper, as good)
        {50, 45},   // 5: front (best quality)
        {5, kNaN},  // 6: not finite, never on the front
        {60, 45},   // 7: dominated by 5 (same quality, dearer)
    };
    EXPECT_EQ(pareto_front(p), (std::vector<size_t>{0, 4, 5}));
}

TEST(ParetoFront, DuplicatesKeepTheFirstAndEmptyInputGivesEmptyFront) {
    EXPECT_EQ(pareto_front({{1, 1}, {1, 1}, {2, 2}}), (std::vector<size_t>{0, 2}));
    EXPECT_TRUE(pareto_front({}).empty());
    EXPECT_TRUE(pareto_front({{kNaN, 1}, {1, INFINITY}}).empty());
}

TEST(ParetoFront, SinglePointAndMonotoneTradeOffAreAllOnTheFront) {
    EXPECT_EQ(pareto_front({{3, 7}}), (std::vector<size_t>{0}));
    EXPECT_EQ(pareto_front({{4, 40}, {1, 10}, {3, 30}, {2, 20}}),
              (std::vector<size_t>{1, 3, 2, 0}));
}

TEST(Percentile, NearestRank) {
    std::vector<double> v;
    for (int i = 1; i <= 20; ++i) v.push_back(21 - i);  // unsorted 20..1
    EXPECT_EQ(percentile(v, 95), 19);
    EXPECT_EQ(percentile(v, 50), 10);
    EXPECT_EQ(percentile(v, 100), 20);
    EXPECT_EQ(percentile(v, 0), 1);
    EXPECT_TRUE(std::isnan(percentile({}, 50)));
}

// A horizontal ramp moved right by 3 pixels: with the motion vectors the back-projected previous
// frame matches exactly; without them every pixel differs by the ramp's step times 3.
TEST(TemporalDifference, BackProjectionCancelsKnownMotion) {
    const uint32_t w = 32, h = 8;
    std::vector<float> prev(w * h), cur(w * h), motion(2 * w * h, 0.f), still(2 * w * h, 0.f);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            prev[y * w + x] = 0.01f * float(x);
            cur[y * w + x] = 0.01f * (float(x) - 3.f);
            motion[2 * (y * w + x)] = 3.f;
        }
    EXPECT_NEAR(temporal_difference(prev, cur, motion, w, h), 0.0, 1e-6);
    EXPECT_NEAR(temporal_difference(prev, cur, still, w, h), 0.03, 1e-6);
    // Everything moved in from outside the previous frame: nothing to compare.
    std::vector<float> far(2 * w * h, 1000.f);
    EXPECT_TRUE(std::isnan(temporal_difference(prev, cur, far, w, h)));
}

TEST(TemporalDifference, HalfPixelMotionSamplesBilinearly) {
    const uint32_t w = 4, h = 1;
    const std::vector<float> prev = {0.f, 1.f, 0.f, 1.f}, cur = {0.5f, 0.5f, 0.5f, 0.5f};
    std::vector<float> motion(2 * w * h, 0.f);
    for (uint32_t x = 0; x < w; ++x) motion[2 * x] = 0.5f;  // came from half a pixel left
    // pixel 0 back-projects outside; pixels 1..3 sample the midpoints, all 0.5
    EXPECT_NEAR(temporal_difference(prev, cur, motion, w, h), 0.0, 1e-6);
}

TEST(Luminance, Rec709OnDisplayValues) {
    const std::vector<uint8_t> rgb = {255, 255, 255, 255, 0, 0, 0, 0, 0};
    const auto l = luminance(rgb, 3, 1);
    EXPECT_NEAR(l[0], 1.0, 1e-5);
    EXPECT_NEAR(l[1], 0.2126, 1e-5);
    EXPECT_EQ(l[2], 0.f);
}

TEST(BenchCli, QuickJsonCarriesEveryMethodAndKey) {
    if (!vk::Device::create_headless({}))
        GTEST_SKIP() << "no Vulkan device (install mesa-vulkan-drivers)";
    const auto dir = std::filesystem::temp_directory_path() / ("fovea_bench_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string cmd = std::string(FOVEA_BINARY_DIR) + "/tools/fovea bench --quick --json "
                            "--resolution 64x36 --no-model --csv " + (dir / "b.csv").string() +
                            " --png " + (dir / "b.png").string() + " 2>/dev/null";
    FILE* p = popen(cmd.c_str(), "r");
    ASSERT_NE(p, nullptr);
    std::string out;
    char buf[4096];
    while (size_t n = fread(buf, 1, sizeof(buf), p)) out.append(buf, n);
    ASSERT_EQ(pclose(p), 0) << cmd;
    const nlohmann::json j = nlohmann::json::parse(out);  // exactly one object, nothing else
    EXPECT_EQ(j["resolution"], nlohmann::json({64, 36}));
    EXPECT_EQ(j["frames"], 2);
    for (const auto& name : vk::Foveator::methods()) {
        SCOPED_TRACE(name);
        ASSERT_TRUE(j["methods"].contains(name));
        const auto& m = j["methods"][name];
        for (const char* key : {"ms_per_frame", "ms_p95", "shaded_fraction", "psnr_fovea_db",
                                "psnr_bands_db", "ssim_bands", "atd", "atd_no_taa",
                                "atd_full_taa", "skipped_tiles", "reused_tiles"})
            EXPECT_TRUE(m.contains(key)) << key;
        EXPECT_GT(m["ms_per_frame"].get<double>(), 0.0);
        EXPECT_GT(m["shaded_fraction"].get<double>(), 0.0);
        EXPECT_EQ(m["psnr_bands_db"].size(), size_t(vk::kBandCount));
        EXPECT_EQ(m["ssim_bands"].size(), size_t(vk::kBandCount));
        EXPECT_TRUE(m["atd"].is_number());
        EXPECT_TRUE(m["atd_no_taa"].is_number());
    }
    EXPECT_EQ(j["methods"]["full"]["shaded_fraction"], 1.0);
    // every method with and without TAA, and a front drawn from them
    EXPECT_EQ(j["variants"].size(), 2 * vk::Foveator::methods().size());
    EXPECT_FALSE(j["pareto_front"].empty());
    EXPECT_GT(std::filesystem::file_size(dir / "b.png"), 1000u);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace fovea::bench
