// GPU TAA pass against the CPU reference model, with validation layers on (zero errors), on
// small images. Skips without a Vulkan device.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <vector>

#include "gpu_harness.hpp"
#include "saccade_model.hpp"
#include "taa_model.hpp"
#include "test_images.hpp"

namespace fovea::vk {
std::unique_ptr<PostPass> make_taa_pass();
}

namespace fovea::vk::post {
namespace {

using vk::testing::PassRunner;

class GpuTaa : public vk::testing::GpuPassTest {};

Image quantize_half(Image img) {
    for (float& v : img.data) v = round_to_half(v);
    return img;
}

// Tone-mapped (working-space) view of a linear RGB image, for 1/255-style comparisons.
Image to_working(const Image& rgb) {
    Image t(rgb.width, rgb.height, 3);
    for (int y = 0; y < rgb.height; ++y)
        for (int x = 0; x < rgb.width; ++x) {
            const Vec3 v = tonemap_forward({rgb.at(x, y, 0), rgb.at(x, y, 1), rgb.at(x, y, 2)});
            t.at(x, y, 0) = v.x;
            t.at(x, y, 1) = v.y;
            t.at(x, y, 2) = v.z;
        }
    return t;
}

float max_abs_diff(const Image& a, const Image& b) {
    float m = 0;
    for (std::size_t i = 0; i < a.data.size(); ++i)
        m = std::max(m, std::fabs(a.data[i] - b.data[i]));
    return m;
}

float mean_abs_diff(const Image& a, const Image& b) {
    double s = 0;
    for (std::size_t i = 0; i < a.data.size(); ++i) s += std::fabs(a.data[i] - b.data[i]);
    return float(s / double(a.data.size()));
}

bool all_finite(const Image& img) {
    for (float v : img.data)
        if (!std::isfinite(v)) return false;
    return true;
}

void compare_with_model(const Device& dev, bool half) {
    const int w = 40, h = 24;
    const VkExtent2D e{uint32_t(w), uint32_t(h)};
    PassRunner run(dev, e, {std::string("taa.precision=") + (half ? "half" : "float")});
    auto pass = make_taa_pass();
    ASSERT_TRUE(run.init(*pass).ok());

    // Inputs as the GPU sees them (half-float images), so both sides start from the same values.
    const Image base = testing::texture(w + 8, h, 2.0f);
    Image depth(w, h, 1, 0.5f);
    for (int y = 0; y < h; ++y)
        for (int x = 30; x < w; ++x) depth.at(x, y) = 0.9f;
    // S_t = 0 over the first 8 columns, then growing: the resolve's three 8×8 tile classes (LOD
    // 0 everywhere, some LOD < 1, every LOD ≥ 1) all meet the model.
    Image rate(w, h, 1);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            rate.at(x, y) = round_to_half(float(std::max(x - 8, 0)) / float(w - 9));
    TaaParams params;
    params.half_storage = half;
    TaaHistory hist;
    float worst = 0;
    float worst_mean = 0;
    for (int frame = 0; frame < 12; ++frame) {
        // Pan by a third of a pixel per frame with matching motion vectors; a depth step
        // appears at frame 6 (disocclusion), a camera cut at frame 9.
        const float off = float(frame) / 3.0f;
        Image colour(w, h, 3);
        Image motion(w, h, 2, 0.0f);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const int x0 = int(float(x) + off);
                const float t = float(x) + off - float(x0);
                for (int c = 0; c < 3; ++c)
                    colour.at(x, y, c) = base.at(x0, y, c) * (1 - t) + base.at(x0 + 1, y, c) * t;
                motion.at(x, y, 0) = round_to_half(-1.0f / 3.0f);
            }
        colour = quantize_half(colour);
        const Image& d = frame >= 6 ? depth : Image(w, h, 1, 0.5f);
        const bool cut = frame == 9;
        // The frame's jitter moves the history fetch too (flow = motion + jitter).
        const Jitter j = halton_jitter(std::uint64_t(frame), 8);
        run.set_inputs(colour, d, motion, rate);
        run.set_jitter(j.x, j.y);
        run.run(*pass, 1, cut);
        const Image gpu = run.output();
        const Image cpu = taa_resolve({&colour, &d, &motion, &rate, cut, j}, hist, params);
        const float diff = max_abs_diff(to_working(gpu), to_working(cpu));
        worst = std::max(worst, diff);
        const float mean = mean_abs_diff(to_working(gpu), to_working(cpu));
        worst_mean = std::max(worst_mean, mean);
        if (half) {
            // The GPU's float->half stores may round differently from round-to-nearest-even;
            // where a clamp box is nearly flat that flips single pixels by a few code values.
            EXPECT_LT(mean, 0.25f / 255.0f) << "frame " << frame;
            EXPECT_LT(diff, 8.0f / 255.0f) << "frame " << frame;
        } else {
            EXPECT_LT(diff, 1.0f / 255.0f) << "frame " << frame;
        }
    }
    std::printf(
        "GPU vs CPU model (%s storage) over 12 frames: max %.5f, mean %.6f (working "
        "space)\n",
        half ? "half" : "float", worst, worst_mean);
}

TEST_F(GpuTaa, MatchesTheCpuModelWithFloatStorage) { compare_with_model(*device_, false); }
TEST_F(GpuTaa, MatchesTheCpuModelWithHalfStorage) { compare_with_model(*device_, true); }

// Renders the saccade experiment's CPS frames on the GPU pass; counts frames to 1/255.
int gpu_saccade_frames(const Device& dev, bool saccade_term) {
    const Image sharp = testing::texture(160, 64);
    const SaccadeExperiment e;
    const int w = sharp.width, h = sharp.height;
    PassRunner run(dev, {uint32_t(w), uint32_t(h)},
                   {std::string("taa.saccade=") + (saccade_term ? "1" : "0")});
    auto pass = make_taa_pass();
    EXPECT_TRUE(run.init(*pass).ok());
    const float cy = 0.5f * float(h);
    const float ax = 0.5f * float(w) - 0.5f * e.jump_deg * e.pixels_per_degree;
    const float bx = 0.5f * float(w) + 0.5f * e.jump_deg * e.pixels_per_degree;
    Image rate_a, rate_b;
    const Image fa = quantize_half(render_cps(sharp, ax, cy, e, rate_a));
    const Image fb = quantize_half(render_cps(sharp, bx, cy, e, rate_b));
    const Image depth(w, h, 1, 1.0f);
    const Image motion(w, h, 2, 0.0f);
    run.set_inputs(fa, depth, motion, rate_a);
    run.run(*pass, e.settle_frames);
    run.set_inputs(fb, depth, motion, rate_b);
    constexpr int kMax = 30;
    std::vector<Image> after;
    for (int i = 0; i < kMax; ++i) {
        run.run(*pass, 1);
        after.push_back(to_working(run.output()));
    }
    run.run(*pass, e.converge_frames - kMax);
    const Image conv = to_working(run.output());
    for (int f = 0; f < kMax; ++f) {
        double err = 0;
        int n = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                if (std::hypot(x + 0.5f - bx, y + 0.5f - cy) / e.pixels_per_degree >= e.fovea_deg)
                    continue;
                auto lum = [&](const Image& im) {
                    return luma709(im.at(x, y, 0), im.at(x, y, 1), im.at(x, y, 2));
                };
                err += std::fabs(lum(after[std::size_t(f)]) - lum(conv));
                ++n;
            }
        if (err / n <= e.tolerance) return f + 1;
    }
    return kMax + 1;
}

TEST_F(GpuTaa, SaccadeRecoveryWithinFourFramesAfterA20DegreeJump) {
    const int with = gpu_saccade_frames(*device_, true);
    const int without = gpu_saccade_frames(*device_, false);
    std::printf(
        "GPU saccade recovery (20 deg, 1/255): %d frames with the saccade term, %d "
        "without\n",
        with, without);
    EXPECT_LE(with, 4);
    EXPECT_GT(without, with);
}

int gpu_stress_frames() {
    const char* env = std::getenv("FOVEA_TAA_STRESS_FRAMES");
    return env ? std::max(1, std::atoi(env)) : 100000;
}

// Static HDR view with exact zeros, NaN/inf inputs and the full range of S_t, both precisions:
// many frames per submission; checks finiteness and drift against the early converged image.
TEST_F(GpuTaa, LongRunStaysFiniteAndDoesNotDrift) {
    const int w = 16, h = 12;
    Image converged[2];
    for (bool half : {true, false}) {
        PassRunner run(*device_, {uint32_t(w), uint32_t(h)},
                       {std::string("taa.precision=") + (half ? "half" : "float")});
        auto pass = make_taa_pass();
        ASSERT_TRUE(run.init(*pass).ok());
        Image colour = testing::texture(w, h, 3.0f);
        for (int x = 0; x < w; ++x) {
            colour.at(x, 0, 0) = colour.at(x, 0, 1) = colour.at(x, 0, 2) = 1e4f;  // HDR row
            colour.at(x, 1, 0) = colour.at(x, 1, 1) = colour.at(x, 1, 2) = 0.0f;  // exact zeros
        }
        colour.at(3, 5, 1) = NAN;
        colour.at(4, 5, 2) = INFINITY;
        Image rate(w, h, 1);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) rate.at(x, y) = float(x) / float(w - 1);
        run.set_inputs(colour, Image(w, h, 1, 0.5f), Image(w, h, 2, 0.0f), rate);
        run.run(*pass, 200);
        const Image early = to_working(run.output());
        const int total = gpu_stress_frames();
        constexpr int kBatch = 500;
        for (int done = 200; done < total; done += kBatch) {
            run.run(*pass, std::min(kBatch, total - done));
            const Image out = run.output();
            ASSERT_TRUE(all_finite(out)) << "frame " << done;
        }
        const Image late = to_working(run.output());
        EXPECT_LT(max_abs_diff(early, late), 1.0f / 255.0f) << (half ? "half" : "float");
        EXPECT_EQ(run.output().at(0, 1, 0), 0.0f);
        converged[half ? 1 : 0] = late;
    }
    const float hf = max_abs_diff(converged[0], converged[1]);
    std::printf("converged half vs float storage: max %.5f (working space)\n", hf);
    EXPECT_LT(hf, 1.0f / 255.0f);
}

// Cost of the TAA pass alone at 1080p (a measurement, not a pass/fail timing: run with
// FOVEA_POST_COST=1): PostChainCostAt1080p's inputs and S_t fields, 7 batches of 2 frames, so a
// change to the pass can be timed in seconds rather than with the whole chain. Prints medians
// and the range of the process CPU time (every driver thread: steadier than the wall time on a
// shared machine).
TEST_F(GpuTaa, CostAt1080p) {
    if (!std::getenv("FOVEA_POST_COST")) GTEST_SKIP() << "set FOVEA_POST_COST=1 to measure";
    const int w = 1920, h = 1080;
    const Image colour = testing::texture(w, h, 1.5f);
    const Image smooth = vk::testing::cost_rate_smooth(w, h),
                tiles = vk::testing::cost_rate_tiles(w, h);
    for (const Image* rate : {&smooth, &tiles}) {
        PassRunner run(*device_, {uint32_t(w), uint32_t(h)}, {});
        auto pass = make_taa_pass();
        ASSERT_TRUE(run.init(*pass).ok());
        run.set_inputs(colour, Image(w, h, 1, 0.5f), Image(w, h, 2, 0.0f), *rate);
        const vk::testing::PassCost c = vk::testing::measure_pass_cost(run, *pass, 7);
        std::printf(
            "taa at %dx%d on %s, S_t %s: %.1f ms/frame wall (%.1f..%.1f), process CPU %.1f ms "
            "(%.1f..%.1f)\n",
            w, h, device_->name().c_str(), rate == &smooth ? "smooth" : "per 16x16 tile",
            c.wall_ms[3], c.wall_ms[0], c.wall_ms[6], c.cpu_ms[3], c.cpu_ms[0], c.cpu_ms[6]);
    }
}

}  // namespace
}  // namespace fovea::vk::post
