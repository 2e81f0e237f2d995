// GPU tests of the issue-6 methods (layers, kfr, adaptive) on a small frame with the pixel
// density of a 1080p desktop monitor: validation layers on, zero validation errors, skipped
// cleanly without a Vulkan device.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "../support/vk_test_device.hpp"
#include "method_harness.hpp"
#include "methods/adaptive_model.hpp"
#include "methods/layers_model.hpp"

namespace fovea::vk::test {
namespace {

constexpr uint32_t kW = 320;
constexpr uint32_t kH = 180;

test::TestDevice& shared() {
    static test::TestDevice d = test::make_test_device(/*prefer_software=*/false);
    return d;
}

#define REQUIRE_DEVICE()                 \
    FOVEA_ASSERT_TEST_DEVICE(shared());  \
    Device* dev = shared().device.get(); \
    const uint64_t errors_before = dev->validation_errors()

// At 320 px with a 1080p monitor's pixel density the frame spans only ±4°, where Guenter's
// slope (0.022) needs no layers at all (the model says full rate) and the default 5-degree
// full-rate fovea covers the whole frame; a steeper slope and pure §4.3 radii exercise the
// layer machinery at this size. The 1080p numbers come from `fovea bench`.
std::vector<std::string> options_for(const std::string& method) {
    if (method == "layers") return {"layers.slope=0.08", "layers.fovea_deg=0"};
    return {};
}

class MethodGpu : public ::testing::TestWithParam<const char*> {};

TEST_P(MethodGpu, ShadesFewerSamplesAndKeepsTheFoveaOfTheFullRateFrame) {
    REQUIRE_DEVICE();
    MethodHarness full(*dev, kW, kH, "full");
    MethodHarness m(*dev, kW, kH, GetParam(), options_for(GetParam()));
    ASSERT_TRUE(full.ok()) << full.error();
    ASSERT_TRUE(m.ok()) << m.error();
    const float gx = 0.4f, gy = 0.55f;
    Frame ref, out;
    for (uint64_t f = 0; f < 4; ++f) {  // a few frames: history-based passes settle
        ref = full.render(f, gx, gy);
        out = m.render(f, gx, gy);
    }
    ASSERT_TRUE(out.finite());
    const EyeDisplay& d = m.foveator().config().display;
    const double fovea = psnr_band(out, ref, d, gx * kW, gy * kH, 0.0, 2.0);
    const double all = psnr_band(out, ref, d, gx * kW, gy * kH, 0.0, 1e9);
    std::printf("%s: shaded %.3f, foveal (0-2 deg) PSNR %.1f dB, whole frame %.1f dB\n", GetParam(),
                out.stats.shaded_fraction, fovea, all);
    EXPECT_LT(out.stats.shaded_fraction, 0.9);
    EXPECT_GT(out.stats.shaded_fraction, 0.02);
    EXPECT_GE(fovea, 40.0);
    EXPECT_GE(all, 20.0);  // the periphery is approximate, but the frame is the same picture
    FOVEA_EXPECT_NO_VALIDATION_ERRORS_SINCE(*dev, errors_before);
}

INSTANTIATE_TEST_SUITE_P(Methods, MethodGpu, ::testing::Values("layers", "kfr", "adaptive"),
                         [](const auto& p) { return std::string(p.param); });

// Error of `out` against `ref` (mean over rgb) in pixels selected by `pick`.
template <typename Pick>
double mean_error(const Frame& out, const Frame& ref, Pick pick) {
    double sum = 0;
    int n = 0;
    for (uint32_t y = 0; y < out.height; ++y)
        for (uint32_t x = 0; x < out.width; ++x) {
            if (!pick(double(x) + 0.5, double(y) + 0.5)) continue;
            for (int c = 0; c < 3; ++c) {
                const std::size_t i = (std::size_t(y) * out.width + x) * 4 + std::size_t(c);
                sum += std::abs(double(out.rgba[i]) - double(ref.rgba[i]));
            }
            ++n;
        }
    return n ? sum / (3.0 * n) : 0.0;
}

TEST(KfrGpu, NoWrapArtefactAlongTheSeamRay) {
    // The LP buffer's v wraps where the angle crosses 0/2π: the ray to the right of the gaze.
    // Its error against the full-rate frame must match that of the ray straight up (mid-buffer).
    REQUIRE_DEVICE();
    MethodHarness full(*dev, kW, kH, "full");
    MethodHarness m(*dev, kW, kH, "kfr");
    ASSERT_TRUE(m.ok()) << m.error();
    const double gx = 0.5 * kW, gy = 0.5 * kH;
    const Frame ref = full.render(0, 0.5f, 0.5f);
    const Frame out = m.render(0, 0.5f, 0.5f);
    auto seam = [&](double x, double y) {
        return x > gx + 10 && x < gx + 80 && std::abs(y - gy) < 1.0;
    };
    auto side = [&](double x, double y) {
        return y < gy - 10 && y > gy - 80 && std::abs(x - gx) < 1.0;
    };
    auto below = [&](double x, double y) {
        return y > gy + 10 && y < gy + 80 && std::abs(x - gx) < 1.0;
    };
    const double e_seam = mean_error(out, ref, seam);
    const double e_ref = std::max(mean_error(out, ref, side), mean_error(out, ref, below));
    std::printf("kfr seam error %.4f vs %.4f on the vertical rays\n", e_seam, e_ref);
    EXPECT_LE(e_seam, 1.5 * e_ref + 0.01);
    FOVEA_EXPECT_NO_VALIDATION_ERRORS_SINCE(*dev, errors_before);
}

TEST(KfrGpu, PolynomialKernelAndBadOptions) {
    REQUIRE_DEVICE();
    // The general kernel of Eq. 9 (compiled in through the KFR_POLY specialization constant).
    MethodHarness full(*dev, kW, kH, "full");
    MethodHarness poly(*dev, kW, kH, "kfr", {"kfr.betas=0.1,0,0.4,0.5"});
    ASSERT_TRUE(poly.ok()) << poly.error();
    const Frame ref = full.render(0, 0.6f, 0.4f);
    const Frame out = poly.render(0, 0.6f, 0.4f);
    ASSERT_TRUE(out.finite());
    const EyeDisplay& d = poly.foveator().config().display;
    EXPECT_GE(psnr_band(out, ref, d, 0.6f * kW, 0.4f * kH, 0.0, 1e9), 25.0);
    // A kernel that is not increasing, or K(1) != 1, is refused with a message.
    MethodHarness bad(*dev, kW, kH, "kfr", {"kfr.betas=0.5,-0.5"});
    EXPECT_FALSE(bad.ok());
    MethodHarness bad_sigma(*dev, kW, kH, "kfr", {"kfr.sigma=0.5"});
    EXPECT_FALSE(bad_sigma.ok());
    FOVEA_EXPECT_NO_VALIDATION_ERRORS_SINCE(*dev, errors_before);
}

TEST(LayersGpu, NoHolesAndNoSeamAtTheLayerBoundaries) {
    REQUIRE_DEVICE();
    MethodHarness full(*dev, kW, kH, "full");
    MethodHarness m(*dev, kW, kH, "layers", options_for("layers"));
    ASSERT_TRUE(m.ok()) << m.error();
    Frame ref, out;
    for (uint64_t f = 0; f < 3; ++f) {
        ref = full.render(f, 0.5f, 0.5f);
        out = m.render(f, 0.5f, 0.5f);
    }
    // No pixel is left uncovered: the sky and the scene are never black.
    for (std::size_t i = 0; i < out.rgba.size(); i += 4)
        ASSERT_GT(out.rgba[i] + out.rgba[i + 1] + out.rgba[i + 2], 0.01f) << "hole at " << i / 4;
    // Error grows outwards smoothly: the ring across each blend is no worse than the coarser
    // layer just outside it (a seam would be a spike at the boundary).
    const double cx = 0.5 * kW, cy = 0.5 * kH;
    auto ring = [&](double r0, double r1) {
        return [=](double x, double y) {
            const double r = std::hypot(x - cx, y - cy);
            return r >= r0 && r < r1;
        };
    };
    const double e_in = mean_error(out, ref, ring(0, 15));
    const double e_mid = mean_error(out, ref, ring(15, 60));
    const double e_out = mean_error(out, ref, ring(60, 200));
    std::printf("layers ring errors %.4f %.4f %.4f\n", e_in, e_mid, e_out);
    EXPECT_LE(e_in, e_mid + 1e-3);
    EXPECT_LE(e_mid, e_out * 1.5 + 1e-3);
    FOVEA_EXPECT_NO_VALIDATION_ERRORS_SINCE(*dev, errors_before);
}

// The views (layer crops) the method asks the host to render for this frame and gaze.
std::vector<ViewRequest> requested_views(MethodHarness& m, uint64_t frame, float gx, float gy) {
    FrameInputs in;
    in.gaze.x = gx;
    in.gaze.y = gy;
    return m.foveator().views(frame, in);
}

TEST(LayersGpu, GazeAtTheCornerKeepsFullRateFoveaWithCropsOnScreen) {
    REQUIRE_DEVICE();
    MethodHarness full(*dev, kW, kH, "full");
    MethodHarness m(*dev, kW, kH, "layers", options_for("layers"));
    ASSERT_TRUE(m.ok()) << m.error();
    const float gx = 0.02f, gy = 0.97f;
    const std::vector<ViewRequest> views = requested_views(m, 0, gx, gy);
    ASSERT_GE(views.size(), 2u);
    // Inner layers are shifted onto the display; the outer one covers it whole (its last texel
    // may overhang by less than one layer texel: ceil(W / s) texels).
    for (std::size_t i = 0; i + 1 < views.size(); ++i) {
        const ViewRequest& v = views[i];
        EXPECT_GE(v.crop[0], 0.0f);
        EXPECT_GE(v.crop[1], 0.0f);
        EXPECT_LE(v.crop[2], 1.0f + 1e-6f);
        EXPECT_LE(v.crop[3], 1.0f + 1e-6f);
    }
    const Frame ref = full.render(0, gx, gy);
    const Frame out = m.render(0, gx, gy);
    const EyeDisplay& d = m.foveator().config().display;
    EXPECT_GE(psnr_band(out, ref, d, gx * kW, gy * kH, 0.0, 1.0), 40.0);
    FOVEA_EXPECT_NO_VALIDATION_ERRORS_SINCE(*dev, errors_before);
}

// Mask radii (display pixels) of the inner layers the method asks for this frame: half the
// side of each square crop.
std::vector<double> inner_radii(MethodHarness& m, uint64_t frame, float gx, float gy) {
    const std::vector<ViewRequest> views = requested_views(m, frame, gx, gy);
    const double width = m.foveator().config().extent.width;
    std::vector<double> r;
    for (std::size_t i = 0; i + 1 < views.size(); ++i)
        r.push_back(0.5 * (views[i].crop[2] - views[i].crop[0]) * width);
    return r;
}

TEST(LayersGpu, InnerLayerIsTheFullRateFrameWhereItIsCompositedAlone) {
    // Inside 60 % of its radius the inner layer has weight 1: s = 1, the frame's own jitter, no
    // history, texel-aligned crop; the pixels must be the full-rate frame's, not just close.
    REQUIRE_DEVICE();
    MethodHarness full(*dev, kW, kH, "full");
    MethodHarness m(*dev, kW, kH, "layers", options_for("layers"));
    ASSERT_TRUE(m.ok()) << m.error();
    const float gaze[][2] = {{0.5f, 0.5f},   {0.4137f, 0.5521f}, {0.9f, 0.1f},
                             {0.02f, 0.97f}, {0.3f, 0.3f},       {0.6663f, 0.4049f}};
    for (uint64_t f = 0; f < 6; ++f) {
        const float gx = gaze[f][0], gy = gaze[f][1];
        const std::vector<double> r = inner_radii(m, f, gx, gy);
        ASSERT_FALSE(r.empty());
        const Frame ref = full.render(f, gx, gy);
        const Frame out = m.render(f, gx, gy);
        const double cx = gx * kW, cy = gy * kH, alone = 0.6 * r[0] - 1.0;
        double worst = 0;
        int n = 0;
        for (uint32_t y = 0; y < kH; ++y)
            for (uint32_t x = 0; x < kW; ++x) {
                if (std::hypot(x + 0.5 - cx, y + 0.5 - cy) >= alone) continue;
                ++n;
                for (int c = 0; c < 3; ++c) {
                    const std::size_t i = (std::size_t(y) * kW + x) * 4 + std::size_t(c);
                    worst = std::max(worst, double(std::abs(out.rgba[i] - ref.rgba[i])));
                }
            }
        EXPECT_GT(n, 100) << f;
        EXPECT_LE(worst, 2e-3) << "frame " << f << ", gaze " << gx << "," << gy;
    }
    FOVEA_EXPECT_NO_VALIDATION_ERRORS_SINCE(*dev, errors_before);
}

TEST(LayersGpu, CoarseLayersAreRegisteredWithTheDisplay) {
    // Where a coarser layer is composited alone, the output matches the reference best without
    // any shift: a layer misplaced by a texel (origin, half-texel or jitter convention) would
    // match a shifted reference better. The checkered wall's edges make the minimum sharp.
    REQUIRE_DEVICE();
    MethodHarness full(*dev, kW, kH, "full");
    MethodHarness m(*dev, kW, kH, "layers", options_for("layers"));
    ASSERT_TRUE(m.ok()) << m.error();
    const float gx = 0.5f, gy = 0.5f;
    const std::vector<double> r = inner_radii(m, 0, gx, gy);
    ASSERT_FALSE(r.empty());
    Frame ref, out;
    for (uint64_t f = 0; f < 3; ++f) {
        ref = full.render(f, gx, gy);
        out = m.render(f, gx, gy);
    }
    const double cx = gx * kW, cy = gy * kH;
    for (std::size_t layer = 1; layer <= r.size(); ++layer) {
        const double lo = r[layer - 1], hi = layer < r.size() ? 0.6 * r[layer] : 1e9;
        double best = 1e9, unshifted = 0;
        int best_dx = 0, best_dy = 0;
        for (int dy = -2; dy <= 2; ++dy)
            for (int dx = -2; dx <= 2; ++dx) {
                double sum = 0;
                int n = 0;
                for (int y = 2; y < int(kH) - 2; ++y)
                    for (int x = 2; x < int(kW) - 2; ++x) {
                        const double d = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
                        if (d < lo || d >= hi) continue;
                        for (int c = 0; c < 3; ++c)
                            sum += std::abs(out.rgba[(std::size_t(y) * kW + x) * 4 + c] -
                                            ref.rgba[(std::size_t(y + dy) * kW + x + dx) * 4 + c]);
                        ++n;
                    }
                ASSERT_GT(n, 200) << "layer " << layer;
                const double e = sum / n;
                if (dx == 0 && dy == 0) unshifted = e;
                if (e < best) {
                    best = e;
                    best_dx = dx;
                    best_dy = dy;
                }
            }
        EXPECT_EQ(best_dx, 0) << "layer " << layer << " error " << unshifted << " vs " << best;
        EXPECT_EQ(best_dy, 0) << "layer " << layer << " error " << unshifted << " vs " << best;
    }
    FOVEA_EXPECT_NO_VALIDATION_ERRORS_SINCE(*dev, errors_before);
}

TEST(LayersGpu, PortraitFrameIsFoveatedLikeTheLandscapeOne) {
    // Guenter's model is written for landscape displays (fn. 8); an HMD eye is portrait.
    REQUIRE_DEVICE();
    MethodHarness full(*dev, kH, kW, "full");
    MethodHarness m(*dev, kH, kW, "layers", options_for("layers"));
    MethodHarness landscape(*dev, kW, kH, "layers", options_for("layers"));
    ASSERT_TRUE(m.ok()) << m.error();
    ASSERT_TRUE(landscape.ok()) << landscape.error();
    const float gx = 0.55f, gy = 0.4f;
    Frame ref, out, wide;
    for (uint64_t f = 0; f < 3; ++f) {
        ref = full.render(f, gx, gy);
        out = m.render(f, gx, gy);
        wide = landscape.render(f, gy, gx);
    }
    ASSERT_TRUE(out.finite());
    for (std::size_t i = 0; i < out.rgba.size(); i += 4)
        ASSERT_GT(out.rgba[i] + out.rgba[i + 1] + out.rgba[i + 2], 0.01f) << "hole at " << i / 4;
    const EyeDisplay& d = m.foveator().config().display;
    EXPECT_GE(psnr_band(out, ref, d, gx * kH, gy * kW, 0.0, 2.0), 40.0);
    EXPECT_GE(psnr_band(out, ref, d, gx * kH, gy * kW, 0.0, 1e9), 20.0);
    // The same panel turned on its side gets the same layers: the same work.
    EXPECT_NEAR(out.stats.shaded_fraction, wide.stats.shaded_fraction,
                0.05 * wide.stats.shaded_fraction);
    EXPECT_LT(out.stats.shaded_fraction, 0.9);
    FOVEA_EXPECT_NO_VALIDATION_ERRORS_SINCE(*dev, errors_before);
}

TEST(LayersGpu, QualityBOn1080pDesktopShadesAtMostAnEighthAtHalfRate) {
    // Guenter's study geometry (a 1080p monitor spanning about ±23.5°), m = 0.022, pure §4.3
    // radii, outer layers at half rate: the GPU path shades what the model plans, <= 1/8.
    REQUIRE_DEVICE();
    const std::vector<std::string> opts = {"layers.slope=0.022", "layers.fovea_deg=0",
                                           "layers.half_rate=1"};
    MethodHarness m(*dev, 1920, 1080, "layers", opts, 8, kTestShading, /*native_display=*/true);
    ASSERT_TRUE(m.ok()) << m.error();
    m.render(0, 0.5f, 0.5f);  // every layer renders once to start its history
    double shaded = 0;
    for (uint64_t f = 1; f <= 2; ++f) {  // then the outer layers alternate
        const Frame out = m.render(f, 0.45f + 0.05f * f, 0.5f);
        ASSERT_TRUE(out.finite());
        shaded += 0.5 * out.stats.shaded_fraction;
    }
    const EyeDisplay& d = m.foveator().config().display;
    methods::LayerOptions o;
    o.slope = 0.022;
    o.half_rate_outer = true;
    const auto plan = methods::optimise_layers(
        methods::layer_display_for(1920, 1080, d.fov_h_deg, d.fov_v_deg), o);
    ASSERT_TRUE(plan.ok());
    std::printf("layers quality B, half rate, 1920x1080: GPU shaded %.4f (1/%.1f), model %.4f\n",
                shaded, 1.0 / shaded, plan->shaded_fraction());
    EXPECT_LE(shaded, 1.0 / 8.0);
    EXPECT_NEAR(shaded, plan->shaded_fraction(), 0.03 * plan->shaded_fraction());
    FOVEA_EXPECT_NO_VALIDATION_ERRORS_SINCE(*dev, errors_before);
}

// Gaze sweeping and jumping with the reference alongside: at every layer's edge the error is no
// worse than that of the coarser layer just outside it (a seam would be a spike there).
// FOVEA_LONG_RUN=1 runs the 10^4 frames of the issue; CI runs 30.
TEST(LayersGpu, GazeSweepAndJumpsLeaveNoSeamBetweenLayers) {
    REQUIRE_DEVICE();
    const int frames = std::getenv("FOVEA_LONG_RUN") ? 10000 : 30;
    MethodHarness full(*dev, kW, kH, "full");
    MethodHarness m(*dev, kW, kH, "layers", options_for("layers"));
    ASSERT_TRUE(m.ok()) << m.error();
    int seams = 0, checked = 0, bad_frames = 0, outside_crop = 0;
    for (int f = 0; f < frames; ++f) {
        float gx = 0.5f + 0.45f * std::sin(f * 0.21f), gy = 0.5f + 0.4f * std::cos(f * 0.13f);
        if (f % 7 == 6) {  // a saccade to a far point
            gx = (f % 3) * 0.45f + 0.05f;
            gy = ((f / 3) % 3) * 0.45f + 0.05f;
        }
        const std::vector<double> r = inner_radii(m, uint64_t(f), gx, gy);
        const Frame ref = full.render(uint64_t(f), gx, gy);
        const Frame out = m.render(uint64_t(f), gx, gy);
        bool bad = !out.finite();
        for (std::size_t i = 0; i < out.rgba.size() && !bad; i += 4)
            bad = out.rgba[i] + out.rgba[i + 1] + out.rgba[i + 2] <= 0.0f;
        bad_frames += bad;
        const double cx = std::clamp(gx, 0.0f, 1.0f) * kW, cy = std::clamp(gy, 0.0f, 1.0f) * kH;
        auto ring = [&](double r0, double r1) {
            return [=](double x, double y) {
                const double d = std::hypot(x - cx, y - cy);
                return d >= r0 && d < r1;
            };
        };
        for (double ri : r) {
            const double edge = mean_error(out, ref, ring(ri - 2.0, ri + 2.0));
            const double outside = mean_error(out, ref, ring(ri + 2.0, ri + 14.0));
            if (edge == 0.0 || outside == 0.0) continue;  // the edge is off screen
            ++checked;
            // The slack absorbs content: a silhouette crossing the edge ring but not the one
            // outside it (seen near the corners in the 10^4-frame run: 0.006 against 0.0018).
            if (edge > 2.0 * outside + 4e-3) {
                ++seams;
                std::printf("frame %d gaze %.2f,%.2f: edge r=%.0f error %.4f, outside %.4f\n", f,
                            gx, gy, ri, edge, outside);
            }
        }
        // Every on-screen pixel an inner layer's mask reaches lies inside that layer's crop (else
        // the composite would smear the crop's border texels), up to the half texel by which the
        // crop snaps to its texel grid (where the mask weight is ~0): the crops follow the gaze
        // to the display's edges and corners.
        const std::vector<ViewRequest> views = requested_views(m, uint64_t(f), gx, gy);
        for (std::size_t i = 0; i < r.size(); ++i) {
            const auto& c = views[i].crop;
            const double slack = 0.5 * (c[2] - c[0]) * kW / views[i].gbuffer.extent.width + 1e-3;
            const double x0 = std::max(0.0, cx - r[i]), x1 = std::min(double(kW), cx + r[i]);
            const double y0 = std::max(0.0, cy - r[i]), y1 = std::min(double(kH), cy + r[i]);
            if (x0 < c[0] * kW - slack || x1 > c[2] * kW + slack || y0 < c[1] * kH - slack ||
                y1 > c[3] * kH + slack)
                ++outside_crop;
        }
    }
    std::printf("layers sweep: %d layer edges checked over %d frames\n", checked, frames);
    EXPECT_GT(checked, frames / 2);
    EXPECT_EQ(seams, 0);
    EXPECT_EQ(outside_crop, 0) << "layer masks reaching past their crops";
    EXPECT_EQ(bad_frames, 0) << "frames with NaN/inf or uncovered pixels";
    FOVEA_EXPECT_NO_VALIDATION_ERRORS_SINCE(*dev, errors_before);
}

TEST(AdaptiveGpu, SamplingPatternIsTemporallyStable) {
    REQUIRE_DEVICE();
    {
        // Without brightness adaptation and jitter P depends only on gaze and G-buffer: a
        // fixation on a static scene picks exactly the same samples every frame.
        MethodHarness m(*dev, kW, kH, "adaptive", {"adaptive.brightness=0"}, 0);
        ASSERT_TRUE(m.ok()) << m.error();
        const Frame a = m.render(0, 0.3f, 0.6f);
        const Frame b = m.render(1, 0.3f, 0.6f);
        const Frame c = m.render(2, 0.3f, 0.6f);
        EXPECT_EQ(a.stats.shaded_samples, b.stats.shaded_samples);
        EXPECT_EQ(b.stats.shaded_samples, c.stats.shaded_samples);
        EXPECT_LT(mean_error(b, c, [](double, double) { return true; }), 0.01);
    }
    {
        // With it, S follows the previous frame; once settled the count moves by < 1 %.
        MethodHarness m(*dev, kW, kH, "adaptive", {}, 0);
        ASSERT_TRUE(m.ok()) << m.error();
        Frame prev = m.render(0, 0.3f, 0.6f);
        for (uint64_t f = 1; f < 8; ++f) {
            const Frame cur = m.render(f, 0.3f, 0.6f);
            std::printf("adaptive frame %d: %llu samples\n", int(f),
                        static_cast<unsigned long long>(cur.stats.shaded_samples));
            if (f >= 4) {
                EXPECT_NEAR(double(cur.stats.shaded_samples), double(prev.stats.shaded_samples),
                            0.01 * double(prev.stats.shaded_samples))
                    << f;
            }
            prev = cur;
        }
    }
    FOVEA_EXPECT_NO_VALIDATION_ERRORS_SINCE(*dev, errors_before);
}

TEST(AdaptiveGpu, ConstantProbabilityPicksTheSamplesOfTheCpuPattern) {
    // With every feature but acuity off and a flat acuity line, P = 0.3 everywhere: the GPU must
    // shade exactly the pixels whose CPU-model threshold (same hash) is below 0.3.
    REQUIRE_DEVICE();
    MethodHarness m(*dev, kW, kH, "adaptive",
                    {"adaptive.features=0", "adaptive.brightness=0", "adaptive.omega0=0.3",
                     "adaptive.slope=0", "adaptive.omega_p=0.3", "adaptive.seed=7"},
                    0);
    ASSERT_TRUE(m.ok()) << m.error();
    const Frame out = m.render(0, 0.5f, 0.5f);
    uint64_t expected = 0;
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) expected += methods::sample_threshold(x, y, 7) < 0.3;
    EXPECT_EQ(out.stats.shaded_samples, expected);
    EXPECT_NEAR(double(expected) / (kW * kH), 0.3, 0.01);
    FOVEA_EXPECT_NO_VALIDATION_ERRORS_SINCE(*dev, errors_before);
}

// Gaze sweeping across the screen and jumping (saccades), far off screen and NaN included.
// FOVEA_LONG_RUN=1 runs the 10^4 frames of the issue; CI runs 240 frames on a tiny frame.
TEST_P(MethodGpu, GazeSweepAndJumpsStayFiniteAndCovered) {
    REQUIRE_DEVICE();
    const bool long_run = std::getenv("FOVEA_LONG_RUN") != nullptr;
    const int frames = long_run ? 10000 : 240;
    MethodHarness m(*dev, 64, 36, GetParam(), options_for(GetParam()));
    ASSERT_TRUE(m.ok()) << m.error();
    uint64_t bad = 0;
    for (int f = 0; f < frames; ++f) {
        float gx, gy;
        if (f % 50 < 40) {  // smooth sweep
            gx = 0.5f + 0.48f * std::sin(f * 0.05f);
            gy = 0.5f + 0.45f * std::cos(f * 0.031f);
        } else {  // saccadic jumps, corners, off screen, NaN
            const float jumps[10][2] = {{0, 0},         {1, 1},      {0, 1}, {1, 0},
                                        {0.5f, 0.5f},   {-2, 0.5f},  {3, 3}, {NAN, 0.5f},
                                        {0.99f, 0.01f}, {0.2f, 0.8f}};
            gx = jumps[f % 10][0];
            gy = jumps[f % 10][1];
        }
        const Frame out = m.render(uint64_t(f), gx, gy);
        if (!out.finite()) ++bad;
        for (std::size_t i = 0; i < out.rgba.size(); i += 4)
            if (out.rgba[i] + out.rgba[i + 1] + out.rgba[i + 2] <= 0.0f) {
                ++bad;
                break;
            }
    }
    EXPECT_EQ(bad, 0u) << "frames with NaN/inf or uncovered pixels";
    FOVEA_EXPECT_NO_VALIDATION_ERRORS_SINCE(*dev, errors_before);
}

}  // namespace
}  // namespace fovea::vk::test
