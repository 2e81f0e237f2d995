// GPU contrast enhancement against the CPU reference, validation layers on. Skips without a
// Vulkan device.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>

#include "enhance_model.hpp"
#include "gpu_harness.hpp"
#include "test_images.hpp"

namespace fovea::vk {
std::unique_ptr<PostPass> make_contrast_pass();
}

namespace fovea::vk::post {
namespace {

using vk::testing::PassRunner;

class GpuContrast : public vk::testing::GpuPassTest {};

TEST_F(GpuContrast, MatchesTheCpuModelAcrossShadingRates) {
    const int w = 64, h = 48;
    PassRunner run(*device_, {uint32_t(w), uint32_t(h)}, {"contrast.blur_rate=0.57"});
    auto pass = make_contrast_pass();
    ASSERT_TRUE(run.init(*pass).ok());
    // Grey linear colour whose display luminance is pink noise; S_t grows left to right.
    const Image target = testing::pink_noise(w, h);
    Image colour(w, h, 3), rate(w, h, 1), sigma(w, h, 1), luma(w, h, 1);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float lin = round_to_half(display_decode(target.at(x, y)));
            for (int c = 0; c < 3; ++c) colour.at(x, y, c) = lin;
            rate.at(x, y) = round_to_half(float(x) / float(w - 1));
            sigma.at(x, y) = blur_sigma_for_rate(rate.at(x, y));
            luma.at(x, y) = display_encode(lin);
        }
    run.set_inputs(colour, Image(w, h, 1, 0.5f), Image(w, h, 2, 0.0f), rate);
    run.run(*pass, 1);
    const Image gpu = run.output();
    const Image cpu = contrast_enhance(luma, sigma, calibration_for_blur_rate(0.57f).f_e);
    float worst = 0;
    double changed = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float g = display_encode(gpu.at(x, y, 1));
            worst = std::max(worst, std::fabs(g - cpu.at(x, y)));
            changed += std::fabs(cpu.at(x, y) - luma.at(x, y));
        }
    std::printf(
        "GPU vs CPU contrast enhancement: max display difference %.5f; mean change by "
        "the enhancement %.5f\n",
        worst, changed / (w * h));
    EXPECT_LT(worst, 2.0f / 255.0f);
    EXPECT_GT(changed / (w * h), 0.5 / 255.0);  // the pass really changed the periphery
    for (int y = 0; y < h; ++y) {  // S_t = 0: untouched (up to the half-float round trip)
        EXPECT_NEAR(display_encode(gpu.at(0, y, 1)), luma.at(0, y), 1.0f / 255.0f);
    }
}

TEST_F(GpuContrast, HdrZerosAndNonFiniteInputStayFinite) {
    const int w = 16, h = 16;
    PassRunner run(*device_, {uint32_t(w), uint32_t(h)}, {});
    auto pass = make_contrast_pass();
    ASSERT_TRUE(run.init(*pass).ok());
    Image colour(w, h, 3, 0.0f);
    for (int x = 0; x < w; ++x) colour.at(x, 3, 0) = colour.at(x, 3, 1) = 1e4f;
    colour.at(5, 5, 0) = NAN;
    colour.at(6, 6, 2) = INFINITY;
    run.set_inputs(colour, Image(w, h, 1, 0.5f), Image(w, h, 2, 0.0f), Image(w, h, 1, 1.0f));
    run.run(*pass, 1);
    const Image out = run.output();
    for (float v : out.data) ASSERT_TRUE(std::isfinite(v));
    EXPECT_EQ(out.at(0, 10, 0), 0.0f);  // black stays black
}

}  // namespace
}  // namespace fovea::vk::post

namespace fovea::vk {
std::unique_ptr<PostPass> make_taa_pass();
std::unique_ptr<PostPass> make_noise_pass();
std::unique_ptr<PostPass> make_copy_pass();
}  // namespace fovea::vk

namespace fovea::vk::post {
namespace {

// Cost of the post chain at 1080p (a measurement, not a pass/fail timing: run with
// FOVEA_POST_COST=1). Prints ms per frame for TAA, contrast and both; medians of 3 batches. S_t
// grows smoothly with the distance from the centre; the TAA and contrast passes are also timed
// with S_t quantized per 16×16 tile to 0, 1/2, 1 as cps writes it. The floor, measured in the
// same run: the copy pass (one rgba16f load and store per pixel), the least a full-screen pass
// costs on this device.
TEST_F(GpuContrast, PostChainCostAt1080p) {
    if (!std::getenv("FOVEA_POST_COST")) GTEST_SKIP() << "set FOVEA_POST_COST=1 to measure";
    const int w = 1920, h = 1080;
    const Image colour = testing::texture(w, h, 1.5f);
    const Image rate = vk::testing::cost_rate_smooth(w, h),
                tile_rate = vk::testing::cost_rate_tiles(w, h);
    double cpu_per_frame = 0;
    auto measure = [&](PostPass& pass, PassRunner& run, const Image& s_t = Image()) {
        run.set_inputs(colour, Image(w, h, 1, 0.5f), Image(w, h, 2, 0.0f),
                       s_t.data.empty() ? rate : s_t);
        const vk::testing::PassCost c = vk::testing::measure_pass_cost(run, pass, 3);
        cpu_per_frame = c.cpu_ms[1];
        return c.wall_ms[1];
    };
    PassRunner r1(*device_, {uint32_t(w), uint32_t(h)}, {});
    auto taa = make_taa_pass();
    ASSERT_TRUE(r1.init(*taa).ok());
    const double taa_ms = measure(*taa, r1);
    const double taa_cpu = cpu_per_frame;
    PassRunner r2(*device_, {uint32_t(w), uint32_t(h)}, {});
    auto con = make_contrast_pass();
    ASSERT_TRUE(r2.init(*con).ok());
    const double con_ms = measure(*con, r2);
    const double con_cpu = cpu_per_frame;
    PassRunner r4(*device_, {uint32_t(w), uint32_t(h)}, {});
    auto taa_tiles = make_taa_pass();
    ASSERT_TRUE(r4.init(*taa_tiles).ok());
    const double taa_tiles_ms = measure(*taa_tiles, r4, tile_rate);
    const double taa_tiles_cpu = cpu_per_frame;
    PassRunner r5(*device_, {uint32_t(w), uint32_t(h)}, {});
    auto con_tiles = make_contrast_pass();
    ASSERT_TRUE(r5.init(*con_tiles).ok());
    const double con_tiles_ms = measure(*con_tiles, r5, tile_rate);
    const double con_tiles_cpu = cpu_per_frame;
    PassRunner r0(*device_, {uint32_t(w), uint32_t(h)}, {});
    auto copy = make_copy_pass();
    ASSERT_TRUE(r0.init(*copy).ok());
    const double copy_ms = measure(*copy, r0);
    const double copy_cpu = cpu_per_frame;
    PassRunner r3(*device_, {uint32_t(w), uint32_t(h)}, {});
    r3.set_display(EyeDisplay::desktop_1080p());
    auto noise = make_noise_pass();
    ASSERT_TRUE(r3.init(*noise).ok());
    const double noise_ms = measure(*noise, r3);
    std::printf(
        "post chain at %dx%d on %s: taa %.1f ms, contrast %.1f ms, taa+contrast %.1f "
        "ms/frame; noise (16 impulses/kernel) %.1f ms\n",
        w, h, device_->name().c_str(), taa_ms, con_ms, taa_ms + con_ms, noise_ms);
    std::printf("process CPU per frame: taa %.1f ms, contrast %.1f ms, noise %.1f ms\n", taa_cpu,
                con_cpu, cpu_per_frame);
    std::printf(
        "S_t per 16x16 tile (0, 1/2, 1): taa %.1f ms, contrast %.1f ms/frame; process "
        "CPU: taa %.1f ms, contrast %.1f ms\n",
        taa_tiles_ms, con_tiles_ms, taa_tiles_cpu, con_tiles_cpu);
    std::printf(
        "floor, the copy pass: %.1f ms/frame, process CPU %.1f ms; taa+contrast = %.1f copies "
        "(CPU)\n",
        copy_ms, copy_cpu, (taa_cpu + con_cpu) / copy_cpu);
}

}  // namespace
}  // namespace fovea::vk::post
