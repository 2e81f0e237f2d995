// fovea bench: Pareto front, percentile and ATD back-projection (pure), and the quick bench's
// JSON on a 64x36 frame carrying every method with the keys issues 5-8 require.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "../support/vk_test_device.hpp"
#include "bench_analysis.hpp"
#include "bench_scene.hpp"
#include "fovea/vk/device.hpp"
#include "fovea/vk/foveator.hpp"

namespace fovea::bench {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(ParetoFront, KeepsOnlyUndominatedPointsByIncreasingCost) {
    // cost (ms), error (mean FLIP)
    const std::vector<CostError> p = {
        {10, 0.30},  // 0: front (cheapest)
        {20, 0.35},  // 1: dominated by 0
        {30, 0.20},  // 2: dominated by 4
        {30, 0.25},  // 3: same cost as 2, worse
        {25, 0.20},  // 4: front: cheaper than 2, as good
        {50, 0.15},  // 5: front (lowest error)
        {5, kNaN},   // 6: not finite, never on the front
        {60, 0.15},  // 7: dominated by 5 (same error, dearer)
    };
    EXPECT_EQ(pareto_front(p), (std::vector<size_t>{0, 4, 5}));
}

TEST(ParetoFront, DuplicatesKeepTheFirstAndEmptyInputGivesEmptyFront) {
    EXPECT_EQ(pareto_front({{1, 2}, {1, 2}, {2, 1}}), (std::vector<size_t>{0, 2}));
    EXPECT_TRUE(pareto_front({}).empty());
    EXPECT_TRUE(pareto_front({{kNaN, 1}, {1, INFINITY}, {2, kNaN}}).empty());
    // -inf (minus the PSNR of an identical image) is the best error there is.
    EXPECT_EQ(pareto_front({{2, -INFINITY}, {1, -40}, {3, -50}}), (std::vector<size_t>{1, 0}));
}

TEST(ParetoFront, SinglePointAndMonotoneTradeOffAreAllOnTheFront) {
    EXPECT_EQ(pareto_front({{3, 7}}), (std::vector<size_t>{0}));
    EXPECT_EQ(pareto_front({{4, 0.1}, {1, 0.4}, {3, 0.2}, {2, 0.3}}),
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
    const vk::test::TestDevice probe = vk::test::make_test_device();
    FOVEA_ASSERT_TEST_DEVICE(probe);
    const auto dir =
        std::filesystem::temp_directory_path() / ("fovea_bench_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string cmd = std::string(FOVEA_BINARY_DIR) + "/tools/fovea bench --quick --json " +
                            (vk::test::kValidation ? "--validation " : "") +
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
    int methods_with_error = 0;
    for (const auto& name : vk::Foveator::methods()) {
        SCOPED_TRACE(name);
        ASSERT_TRUE(j["methods"].contains(name));
        const auto& m = j["methods"][name];
        for (const char* key :
             {"ms_per_frame", "ms_p95", "shaded_fraction", "flip_mean", "flip_bands",
              "flip_mean_67ppd", "flip_bands_67ppd", "psnr_bands_pooled", "psnr_db",
              "psnr_fovea_db", "ssim_bands", "atd", "atd_no_taa", "atd_full_taa", "tflip",
              "temporal", "skipped_tiles", "reused_tiles"})
            EXPECT_TRUE(m.contains(key)) << key;
        for (const char* key : {"method_gpu_ms", "gbuffer_gpu_ms"})
            EXPECT_TRUE(m.contains(key)) << key;
        // The demo host times its G-buffer (the cost floor under every method).
        EXPECT_GT(m["gbuffer_gpu_ms"].get<double>(), 0.0);
        EXPECT_GT(m["ms_per_frame"].get<double>(), 0.0);
        EXPECT_GT(m["shaded_fraction"].get<double>(), 0.0);
        EXPECT_EQ(m["flip_bands"].size(), size_t(vk::kBandCount));
        EXPECT_EQ(m["psnr_bands_pooled"].size(), size_t(vk::kBandCount));
        EXPECT_EQ(m["ssim_bands"].size(), size_t(vk::kBandCount));
        EXPECT_TRUE(m["atd"].is_number());
        EXPECT_TRUE(m["atd_no_taa"].is_number());
        EXPECT_TRUE(m["temporal"]["taa"]["atd_settled"].is_number());
        EXPECT_TRUE(m["temporal"]["no_taa"]["tflip_cut"].is_number());
        EXPECT_FALSE(m.contains("psnr_bands_db")) << "the frame-averaged dB figure is gone";
        const double flip = m["flip_mean"].get<double>();
        EXPECT_GE(flip, 0.0);
        EXPECT_LT(flip, 1.0);
        if (name == "full") {
            EXPECT_EQ(flip, 0.0);                 // the reference itself
            EXPECT_TRUE(m["psnr_db"].is_null());  // +inf: identical, not capped
        }
        if (flip > 0) {
            ++methods_with_error;
            EXPECT_TRUE(m["psnr_db"].is_number()) << "FLIP saw a difference, PSNR must too";
        }
    }
    // 64x36 pixels cover ~1.3 ppd: cps shades all of it at full rate, the others do not.
    EXPECT_GE(methods_with_error, 2);
    EXPECT_EQ(j["methods"]["full"]["shaded_fraction"], 1.0);
    EXPECT_TRUE(j["methods"]["cps"]["saccade_recovery_frames"].is_number());
    EXPECT_FALSE(j.contains("model")) << "--no-model";
    // every method with and without TAA, and the two temporal runs; fronts drawn from them
    EXPECT_EQ(j["variants"].size(), 4 * vk::Foveator::methods().size());
    EXPECT_FALSE(j["pareto_front"].empty());
    EXPECT_FALSE(j["pareto_front_psnr"].empty());
    EXPECT_GT(std::filesystem::file_size(dir / "b.png"), 1000u);
    EXPECT_GT(std::filesystem::file_size(dir / "b_psnr.png"), 1000u);
    std::filesystem::remove_all(dir);
    // With --validation, fovea bench exits 1 on any validation error (checked by pclose above).
    if (!vk::test::kValidation) GTEST_SKIP() << vk::test::kValidationOff;
}

// The forward paths' reference goes in once, before the first of them (bench_sweep pairs
// results[k] with {"full"} + methods).
TEST(SceneBench, ForwardReferenceBeforeTheFirstForwardPathOnly) {
    using V = std::vector<std::string>;
    EXPECT_EQ(SceneBench::with_references({"cps", "layers"}), (V{"cps", "layers"}));
    EXPECT_EQ(SceneBench::with_references({"cps", "forward-layers", "kfr", "post-only"}),
              (V{"cps", "full-forward", "forward-layers", "kfr", "post-only"}));
    EXPECT_EQ(SceneBench::with_references({"post-only", "full-forward"}),
              (V{"full-forward", "post-only"}));
}

// --scene: the same sweep through the glTF viewer's host code on the real sample models: every
// method on the deferred path and the viewer's forward paths, each against its full-rate frame.
TEST(BenchCli, SceneQuickJsonCarriesEveryPathAgainstItsFullRateFrame) {
    const std::string data = FOVEA_SHARED_DATA_DIR;
    if (!std::filesystem::exists(data + "/scenes/WaterBottle/glTF/WaterBottle.gltf"))
        GTEST_SKIP() << "no sample models under " << data << "/scenes";
    const vk::test::TestDevice probe = vk::test::make_test_device();
    FOVEA_ASSERT_TEST_DEVICE(probe);
    const auto dir = std::filesystem::temp_directory_path() /
                     ("fovea_bench_scene_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string cmd =
        std::string(FOVEA_BINARY_DIR) + "/tools/fovea bench --quick --json " +
        (vk::test::kValidation ? "--validation " : "") + "--scene " + FOVEA_SOURCE_DIR +
        "/sdk/examples/gltf_viewer/scenes/sample_models.toml --data-dir " + data +
        " --resolution 128x72 --no-model --csv " + (dir / "s.csv").string() + " --png " +
        (dir / "s.png").string() + " 2>/dev/null";
    FILE* p = popen(cmd.c_str(), "r");
    ASSERT_NE(p, nullptr);
    std::string out;
    char buf[4096];
    while (size_t n = fread(buf, 1, sizeof(buf), p)) out.append(buf, n);
    ASSERT_EQ(pclose(p), 0) << cmd;
    const nlohmann::json j = nlohmann::json::parse(out);
    EXPECT_EQ(j["resolution"], nlohmann::json({128, 72}));
    EXPECT_NE(j["header"].dump().find("sample_models.toml: 7 models"), std::string::npos);
    // path 1's methods against "full", the forward paths against "full-forward"
    for (const char* name : {"full", "full-forward"}) {
        ASSERT_TRUE(j["methods"].contains(name)) << name;
        EXPECT_EQ(j["methods"][name]["shaded_fraction"], 1.0) << name;
    }
    std::vector<std::string> names = vk::Foveator::methods();
    names.insert(names.end(), {"forward-layers", "post-only"});
    for (const auto& name : names) {
        SCOPED_TRACE(name);
        ASSERT_TRUE(j["methods"].contains(name));
        const auto& m = j["methods"][name];
        EXPECT_GT(m["ms_per_frame"].get<double>(), 0.0);
        EXPECT_TRUE(m["atd"].is_number());
        EXPECT_EQ(m["psnr_bands_pooled"].size(), size_t(vk::kBandCount));
        EXPECT_EQ(m["flip_bands"].size(), size_t(vk::kBandCount));
        EXPECT_GE(m["flip_mean"].get<double>(), 0.0);
        EXPECT_LE(m["flip_mean"].get<double>(), 1.0);
    }
    // (on a frame this small the layers' texels outnumber the pixels: shaded_fraction > 1)
    EXPECT_GT(j["methods"]["forward-layers"]["shaded_fraction"].get<double>(), 0.0);
    // pooled over the frames; null = +inf, the fovea identical to the full-rate frame
    for (const char* name : {"forward-layers", "cps"}) {
        const auto& fovea_db = j["methods"][name]["psnr_fovea_db"];
        EXPECT_TRUE(fovea_db.is_null() || fovea_db.get<double>() > 40.0) << name << fovea_db;
    }
    EXPECT_LT(j["methods"]["cps"]["shaded_fraction"].get<double>(), 1.0);
    // rate-image runs where the device has VRS, else says why
    EXPECT_TRUE(j["methods"].contains("rate-image") || j["errors"].contains("rate-image"));
    std::filesystem::remove_all(dir);
    // With --validation, fovea bench exits 1 on any validation error (checked by pclose above).
    if (!vk::test::kValidation) GTEST_SKIP() << vk::test::kValidationOff;
}

}  // namespace
}  // namespace fovea::bench
