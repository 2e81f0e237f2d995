// The GPU LDR-FLIP (shaders/flip_*.comp) against NVIDIA's vectors and against the CPU reference:
// uniform ppd, a wide-FOV display's per-axis ppd, the demo's HDR display transform and the
// back-projected temporal FLIP. Validation layers on; skips without a Vulkan device.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <random>

#include "flip_vectors.hpp"
#include "fovea/demo/demo.hpp"
#include "fovea/metrics/flip.hpp"
#include "fovea/metrics/gpu_flip.hpp"
#include "gpu.hpp"
#include "vk_test_util.hpp"

namespace fovea::metrics {
namespace {

using testing::flip_vectors;
using testing::kMeanTolerance;
using testing::kPixelTolerance;

vk::Image upload_rgb8(const vk::Device& d, const Rgb8View& img) {
    vk::Image out(d, {img.width, img.height}, VK_FORMAT_R8G8B8A8_UNORM, VK_IMAGE_USAGE_SAMPLED_BIT);
    std::vector<uint8_t> rgba(size_t(img.width) * img.height * 4, 255);
    for (size_t i = 0; i < size_t(img.width) * img.height; ++i)
        std::memcpy(&rgba[4 * i], &img.rgb[3 * i], 3);
    vk::upload_image(d, out.ref(), rgba);
    return out;
}

vk::Image upload_rgba16f(const vk::Device& d, uint32_t w, uint32_t h,
                         const std::vector<float>& rgba) {
    vk::Image out(d, {w, h}, VK_FORMAT_R16G16B16A16_SFLOAT, VK_IMAGE_USAGE_SAMPLED_BIT);
    std::vector<uint8_t> bytes(rgba.size() * 2);
    for (size_t i = 0; i < rgba.size(); ++i) {
        const uint16_t h16 = fovea::half_bits(rgba[i]);
        std::memcpy(&bytes[2 * i], &h16, 2);
    }
    vk::upload_image(d, out.ref(), bytes);
    return out;
}

std::vector<float> gpu_compare(const vk::Device& d, GpuFlip& flip, const vk::ImageRef& ref,
                               const vk::ImageRef& test, FlipInput kind) {
    d.submit_and_wait([&](VkCommandBuffer cmd) {
        flip.record_reference(cmd, ref, kind);
        flip.record_compare(cmd, test, kind);
    });
    return {flip.map().begin(), flip.map().end()};
}

struct MapDiff {
    double max = 0, mean = 0;
};
MapDiff diff(const std::vector<float>& a, const std::vector<float>& b) {
    MapDiff d;
    double sa = 0, sb = 0;
    size_t n = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        if (std::isnan(a[i]) != std::isnan(b[i])) return {INFINITY, INFINITY};
        if (std::isnan(a[i])) continue;
        d.max = std::max(d.max, double(std::fabs(a[i] - b[i])));
        sa += a[i];
        sb += b[i];
        ++n;
    }
    d.mean = n ? std::fabs(sa - sb) / double(n) : 0.0;
    return d;
}

Rgb8Image crop(const Rgb8Image& src, uint32_t x0, uint32_t y0, uint32_t w, uint32_t h) {
    Rgb8Image c{w, h, {}};
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x)
            for (int k = 0; k < 3; ++k)
                c.rgb.push_back(src.rgb[(size_t(y + y0) * src.width + x + x0) * 3 + k]);
    return c;
}

TEST(FlipGpu, MatchesNvidiaVectorsForEveryPairAndPpd) {
    FOVEA_REQUIRE_DEVICE();
    const auto& v = flip_vectors();
    if (v.cases.empty()) GTEST_SKIP() << "no FLIP vectors in " << v.dir;
    const Rgb8Image& ref = v.image("ref.png");
    const vk::Image ref_gpu = upload_rgb8(*device, ref.view());
    std::map<std::string, vk::Image> tests;
    for (const auto& c : v.cases)
        if (!tests.count(c.test_file))
            tests.emplace(c.test_file, upload_rgb8(*device, v.image(c.test_file).view()));
    std::map<double, GpuFlip> flips;
    for (const auto& c : v.cases) {
        SCOPED_TRACE(c.pair + " at " + c.ppd_label + " ppd");
        auto it = flips.find(c.ppd);
        if (it == flips.end()) {
            auto f = GpuFlip::create(*device, ref.width, ref.height,
                                     {PpdField::uniform(ref.width, ref.height, c.ppd)});
            ASSERT_TRUE(f) << f.error().message;
            it = flips.emplace(c.ppd, std::move(*f)).first;
        }
        const std::vector<float> map = gpu_compare(*device, it->second, ref_gpu.ref(),
                                                   tests.at(c.test_file).ref(), FlipInput::kSrgb);
        const FlipPooled p = pool_flip(map);
        EXPECT_NEAR(p.mean, c.mean, kMeanTolerance);
        EXPECT_NEAR(p.weighted_median, c.weighted_median, kMeanTolerance);
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
        std::printf(
            "%-10s %-7s ppd: GPU mean %.6f (NVIDIA %.6f, %+.1e), worst of %zu pixels %.1e\n",
            c.pair.c_str(), c.ppd_label.c_str(), p.mean, c.mean, p.mean - c.mean, c.pixels.size(),
            worst);
    }
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

// A 98 x 104 degree eye on 256 x 160 pixels: ppd differs per column and per row block.
TEST(FlipGpu, AgreesWithTheCpuReferenceAtAWideFovDisplaysPpd) {
    FOVEA_REQUIRE_DEVICE();
    const auto& v = flip_vectors();
    if (v.cases.empty()) GTEST_SKIP() << "no FLIP vectors in " << v.dir;
    const Rgb8Image a = crop(v.image("ref.png"), 300, 150, 256, 160);
    const Rgb8Image b = crop(v.image("test_noise0.02.png"), 300, 150, 256, 160);
    const vk::EyeDisplay display = vk::EyeDisplay::from_fov(256, 160, 98.0, 104.0);
    PpdField field = display_ppd_field(display, 256, 160);
    for (double& p : field.x) p *= 15;  // 29 ppd at the centre, as if 15x the pixels
    for (double& p : field.y) p *= 15;
    double lo = 1e9, hi = 0;
    for (double p : field.x) lo = std::min(lo, p), hi = std::max(hi, p);
    EXPECT_GT(hi / lo, 1.8) << "the field should vary: " << lo << " .. " << hi;
    const std::vector<float> cpu = flip_map(a.view(), b.view(), field);
    auto flip = GpuFlip::create(*device, 256, 160, {field});
    ASSERT_TRUE(flip) << flip.error().message;
    const vk::Image ga = upload_rgb8(*device, a.view()), gb = upload_rgb8(*device, b.view());
    const MapDiff d = diff(gpu_compare(*device, *flip, ga.ref(), gb.ref(), FlipInput::kSrgb), cpu);
    EXPECT_LE(d.max, kPixelTolerance);
    EXPECT_LE(d.mean, kMeanTolerance);
    // And the field is not a no-op: at one uniform ppd the map differs.
    const std::vector<float> uniform =
        flip_map(a.view(), b.view(), PpdField::uniform(256, 160, lo));
    EXPECT_GT(diff(uniform, cpu).max, 0.01);
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

// Linear HDR whose display values (demo::tonemap) sit mid-way between 8-bit codes, so the GPU's
// and the CPU's exp/pow, a few ulp apart, round to the same code: smooth structure plus noise,
// from black to highlights above 1.
std::vector<float> random_hdr(uint32_t w, uint32_t h, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> noise(-12, 12);
    std::vector<float> rgba(size_t(w) * h * 4);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x)
            for (int k = 0; k < 4; ++k) {
                const float s = 0.5f + 0.5f * std::sin(0.21f * x + 0.13f * y + 1.7f * k);
                const int code = std::clamp(int(250 * s * s) + noise(rng), 0, 254);
                const double e = code / 255.0;  // display value -> tone-mapped t -> radiance
                const double t = e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4);
                rgba[(size_t(y) * w + x) * 4 + k] = k == 3 ? 1.f : float(-std::log(1.0 - t));
            }
    return rgba;
}

demo::Rgb8 tonemapped(const std::vector<float>& rgba, uint32_t w, uint32_t h) {
    std::vector<uint8_t> bytes(rgba.size() * 2);
    for (size_t i = 0; i < rgba.size(); ++i) {
        const uint16_t h16 = fovea::half_bits(rgba[i]);
        std::memcpy(&bytes[2 * i], &h16, 2);
    }
    return demo::tonemap(bytes, w, h);
}

TEST(FlipGpu, DemoDisplayTransformIsDemoTonemap) {
    FOVEA_REQUIRE_DEVICE();
    constexpr uint32_t w = 96, h = 64;
    const std::vector<float> ra = random_hdr(w, h, 1), rb = random_hdr(w, h, 2);
    const demo::Rgb8 ta = tonemapped(ra, w, h), tb = tonemapped(rb, w, h);
    const PpdField field = PpdField::uniform(w, h, 40.0);
    const std::vector<float> cpu = flip_map({w, h, ta.rgb}, {w, h, tb.rgb}, field);
    auto flip = GpuFlip::create(*device, w, h, {field});
    ASSERT_TRUE(flip) << flip.error().message;
    const vk::Image ga = upload_rgba16f(*device, w, h, ra), gb = upload_rgba16f(*device, w, h, rb);
    const MapDiff d =
        diff(gpu_compare(*device, *flip, ga.ref(), gb.ref(), FlipInput::kDemoDisplay), cpu);
    EXPECT_LE(d.max, kPixelTolerance);
    EXPECT_LE(d.mean, kMeanTolerance);
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

// The temporal FLIP: the previous frame back-projected along the motion (bilinear between texel
// centres, both neighbours inside, like bench::temporal_difference) against the current one.
TEST(FlipGpu, BackProjectedReferenceFollowsTheMotionAndDropsPixelsThatLeave) {
    FOVEA_REQUIRE_DEVICE();
    constexpr uint32_t w = 80, h = 48;
    const std::vector<float> prev = random_hdr(w, h, 3), cur = random_hdr(w, h, 4);
    std::vector<float> motion(size_t(w) * h * 2);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            motion[2 * (size_t(y) * w + x)] = 2.25f + 0.02f * y;  // moved right and down
            motion[2 * (size_t(y) * w + x) + 1] = 0.5f;
        }
    motion[2 * (10 * w + 40)] = NAN;  // no history for one pixel
    const demo::Rgb8 tp = tonemapped(prev, w, h), tc = tonemapped(cur, w, h);
    std::vector<float> warped(size_t(w) * h * 3);
    std::vector<bool> valid(size_t(w) * h);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            const size_t i = size_t(y) * w + x;
            const float px = float(x) - motion[2 * i], py = float(y) - motion[2 * i + 1];
            valid[i] = std::isfinite(px) && px >= 0 && py >= 0 && px <= w - 1 && py <= h - 1;
            for (int k = 0; k < 3; ++k) {
                if (!valid[i]) {
                    warped[3 * i + k] = tc.rgb[3 * i + k] / 255.f;
                    continue;
                }
                const uint32_t x0 = uint32_t(px), y0 = uint32_t(py);
                const uint32_t x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
                const float fx = px - x0, fy = py - y0;
                const auto at = [&](uint32_t xx, uint32_t yy) {
                    return tp.rgb[(size_t(yy) * w + xx) * 3 + k] / 255.f;
                };
                warped[3 * i + k] = (at(x0, y0) * (1 - fx) + at(x1, y0) * fx) * (1 - fy) +
                                    (at(x0, y1) * (1 - fx) + at(x1, y1) * fx) * fy;
            }
        }
    const PpdField field = PpdField::uniform(w, h, 30.0);
    std::vector<float> cpu =
        FlipReference(RgbFloatView{w, h, warped}, field).compare(Rgb8View{w, h, tc.rgb});
    size_t dropped = 0;
    for (size_t i = 0; i < cpu.size(); ++i)
        if (!valid[i]) {
            cpu[i] = NAN;
            ++dropped;
        }
    EXPECT_GT(dropped, size_t(w)) << "row 0 and the left columns leave the frame";
    auto flip = GpuFlip::create(*device, w, h, {field});
    ASSERT_TRUE(flip) << flip.error().message;
    const vk::Image gp = upload_rgba16f(*device, w, h, prev),
                    gc = upload_rgba16f(*device, w, h, cur);
    flip->set_motion(motion);
    device->submit_and_wait([&](VkCommandBuffer cmd) {
        flip->record_back_projected_reference(cmd, gp.ref(), gc.ref());
        flip->record_compare(cmd, gc.ref(), FlipInput::kDemoDisplay);
    });
    const MapDiff d = diff({flip->map().begin(), flip->map().end()}, cpu);
    EXPECT_LE(d.max, kPixelTolerance);
    EXPECT_LE(d.mean, kMeanTolerance);
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

// A bench sweep renders each configuration into new images: forgetting the inputs between
// configurations keeps the cached input sets from running out (64) or outliving their views.
TEST(FlipGpu, InputsForgottenBetweenConfigurationsNeverRunOutOfSets) {
    FOVEA_REQUIRE_DEVICE();
    constexpr uint32_t w = 32, h = 32;
    const std::vector<float> ra = random_hdr(w, h, 5), rb = random_hdr(w, h, 6);
    auto flip = GpuFlip::create(*device, w, h, {PpdField::uniform(w, h, 40.0)});
    ASSERT_TRUE(flip) << flip.error().message;
    std::vector<float> first;
    for (int config = 0; config < 80; ++config) {
        const vk::Image ga = upload_rgba16f(*device, w, h, ra),
                        gb = upload_rgba16f(*device, w, h, rb);
        const std::vector<float> map =
            gpu_compare(*device, *flip, ga.ref(), gb.ref(), FlipInput::kDemoDisplay);
        if (config == 0) first = map;
        ASSERT_EQ(std::memcmp(map.data(), first.data(), map.size() * sizeof(float)), 0)
            << "configuration " << config;
        flip->forget_inputs();
    }
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

TEST(FlipGpu, RejectsFieldsItCannotRun) {
    FOVEA_REQUIRE_DEVICE();
    PpdField bumpy = PpdField::uniform(32, 32, 40.0);
    bumpy.x[3] = 41.0;  // not constant over the first 16-pixel block
    auto a = GpuFlip::create(*device, 32, 32, {bumpy});
    ASSERT_FALSE(a);
    EXPECT_NE(a.error().message.find("blocks"), std::string::npos);
    EXPECT_FALSE(GpuFlip::create(*device, 32, 32, {PpdField::uniform(32, 32, 2000.0)}));
    EXPECT_FALSE(GpuFlip::create(*device, 32, 32, {PpdField::uniform(32, 32, 0.0)}));
    EXPECT_FALSE(GpuFlip::create(*device, 0, 32, {PpdField::uniform(0, 32, 40.0)}));
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

}  // namespace
}  // namespace fovea::metrics
