#include "layers_model.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace fovea::vk::methods {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kOmega0 = 1.0 / 48.0;
constexpr double kSlopeA = 0.0275;
constexpr double kSlopeB = 0.022;

double speedup(const LayerDisplay& d, int n, double m, bool half = false,
               std::optional<double> s2 = std::nullopt) {
    LayerOptions o;
    o.layer_count = n;
    o.slope = m;
    o.half_rate_outer = half;
    o.fixed_s2 = s2;
    auto plan = optimise_layers(d, o);
    EXPECT_TRUE(plan.ok()) << (plan.ok() ? "" : plan.error().message);
    return plan.ok() ? plan->speedup() : 0.0;
}

TEST(GuenterLayers, DesktopDisplayMatchesPaperAngles) {
    const LayerDisplay d;  // V* = 59 cm, W* = 51 cm, D* = 1920, α* = 9/16
    EXPECT_NEAR(display_radius_deg(d), 23.4, 0.05);
    EXPECT_NEAR(sharpness_deg(d), 0.0516, 0.00005);
    EXPECT_NEAR(kOmega0 / sharpness_deg(d), 0.40, 0.01);  // "only 40 % of foveal acuity"
}

TEST(GuenterLayers, Eq9ResolutionGivesSharpnessEqualToFovealAcuity) {
    for (double fov : {20.0, 70.0, 120.0}) {
        const LayerDisplay d = acuity_matched_display(fov, 0.75, kOmega0);
        EXPECT_NEAR(sharpness_deg(d), kOmega0, kOmega0 * 1e-3) << fov;
        EXPECT_NEAR(2.0 * display_radius_deg(d), fov, 1e-9) << fov;
    }
}

TEST(GuenterLayers, PlanIsConservativeAgainstTheMarLine) {
    const LayerDisplay d;
    LayerOptions o;
    o.slope = kSlopeB;
    for (int n = 2; n <= 4; ++n) {
        o.layer_count = n;
        const LayerPlan p = *optimise_layers(d, o);
        ASSERT_EQ(p.layers.size(), std::size_t(n));
        EXPECT_DOUBLE_EQ(p.layers[0].sampling_factor, 1.0);
        for (int i = 1; i < n; ++i) {
            const Layer& prev = p.layers[std::size_t(i - 1)];
            const Layer& cur = p.layers[std::size_t(i)];
            EXPECT_LT(prev.radius_deg, cur.radius_deg);
            // Layer i is sampled no coarser than the MAR at the inner edge of its visible ring:
            // its resolvable angle (2 pixels = s·ω*) never exceeds m·e_{i-1} + ω0 (Fig. 7).
            EXPECT_LE(cur.sampling_factor * sharpness_deg(d),
                      std::max(sharpness_deg(d), kSlopeB * prev.radius_deg + kOmega0) + 1e-12);
        }
        EXPECT_NEAR(p.layers.back().radius_deg, display_radius_deg(d), 1e-12);
    }
}

TEST(GuenterLayers, BruteForceFindsTheGridMinimum) {
    // Exhaustive check for n = 3 on a coarse grid: no radius pair beats the optimiser's.
    const LayerDisplay d;
    LayerOptions o;
    o.slope = kSlopeA;
    o.steps = 60;
    const LayerPlan best = *optimise_layers(d, o);
    const double e_star = display_radius_deg(d);
    for (int i = 1; i < 60; ++i)
        for (int j = i + 1; j < 60; ++j) {
            const LayerPlan p = evaluate_layers(d, o, {e_star * i / 60, e_star * j / 60});
            EXPECT_GE(p.work, best.work * (1.0 - 1e-12));
        }
}

TEST(GuenterLayers, MeasuredPixelSpeedupsOfSection6AreReproducedWithin5Percent) {
    // §6: three layers, s_2 = 2 (supplement), outer layers at half rate: 13.3 (A), 9.8 (B).
    const LayerDisplay d;
    EXPECT_NEAR(speedup(d, 3, kSlopeA, true, 2.0), 13.3, 13.3 * 0.05);
    EXPECT_NEAR(speedup(d, 3, kSlopeB, true, 2.0), 9.8, 9.8 * 0.05);
}

TEST(GuenterLayers, QualityBOnTheStudyDisplayShadesAtMostAnEighthAtHalfRate) {
    const LayerDisplay d;
    LayerOptions o;
    o.slope = kSlopeB;
    o.half_rate_outer = true;
    EXPECT_LE(optimise_layers(d, o)->shaded_fraction(), 1.0 / 8.0);
    o.half_rate_outer = false;  // every layer every frame: about 1/6.4
    EXPECT_GT(optimise_layers(d, o)->shaded_fraction(), 1.0 / 8.0);
}

TEST(GuenterLayers, HalfRateNeverUpdatesAFullResolutionLayerAtHalfRate) {
    // Weighted by w_i = 1/2 the unconstrained n = 4 minimum was a 0.1-degree inner layer and a
    // second s = 1 layer at half rate; every layer after the inner one must be coarser.
    const LayerDisplay d;
    LayerOptions o;
    o.slope = kSlopeB;
    o.half_rate_outer = true;
    for (int n = 2; n <= 4; ++n) {
        o.layer_count = n;
        const LayerPlan p = *optimise_layers(d, o);
        for (std::size_t i = 1; i < p.layers.size(); ++i)
            EXPECT_GT(p.layers[i].sampling_factor, 1.0) << "n " << n << " layer " << i;
        if (n >= 3) { EXPECT_LE(p.shaded_fraction(), 1.0 / 8.0) << n; }
    }
}

TEST(GuenterLayers, Figure12AbstractClaimHundredfoldAt70Degrees) {
    // Abstract: "100 times speedup at a field of view of 70° and resolution matching foveal
    // acuity" — the n = 4 curve at slope A.
    const LayerDisplay d = acuity_matched_display(70.0, 0.75, kOmega0);
    EXPECT_NEAR(speedup(d, 4, kSlopeA), 100.0, 10.0);
}

TEST(GuenterLayers, Figure12TrendsHold) {
    for (double m : {kSlopeA, kSlopeB}) {
        double prev4 = 0.0;
        for (double fov = 10.0; fov <= 120.0; fov += 10.0) {
            const LayerDisplay d = acuity_matched_display(fov, 0.75, kOmega0);
            const double s2 = speedup(d, 2, m);
            const double s3 = speedup(d, 3, m);
            const double s4 = speedup(d, 4, m);
            const double s3star = speedup(d, 3, m, false, 2.0);
            EXPECT_LT(s2, s3) << fov;  // more layers always help
            EXPECT_LT(s3, s4) << fov;
            EXPECT_LE(s3star, s3 * (1.0 + 1e-9)) << fov;  // the s_2 = 2 restriction costs
            EXPECT_GT(s4, prev4) << fov;                  // speed-up grows with field of view
            prev4 = s4;
        }
    }
    // A steeper slope (quality A) saves more than B.
    const LayerDisplay d = acuity_matched_display(60.0, 0.75, kOmega0);
    EXPECT_GT(speedup(d, 3, kSlopeA), speedup(d, 3, kSlopeB));
}

TEST(GuenterLayers, Figure13FoveatedCostGrowsRoughlyLinearlyUpTo90Degrees) {
    // Non-foveated cost grows like tan²(e*); foveated (n = 4) roughly linearly with FOV.
    auto work = [](double fov) {
        const LayerDisplay d = acuity_matched_display(fov, 0.75, kOmega0);
        LayerOptions o;
        o.layer_count = 4;
        o.slope = kSlopeB;
        return optimise_layers(d, o)->work;
    };
    const double w30 = work(30.0);
    const double w60 = work(60.0);
    const double w90 = work(90.0);
    EXPECT_NEAR((w90 - w60) / (w60 - w30), 1.0, 0.35);  // equal increments: linear
    const double full30 = acuity_matched_display(30.0, 0.75, kOmega0).resolution_px;
    const double full90 = acuity_matched_display(90.0, 0.75, kOmega0).resolution_px;
    EXPECT_GT((full90 * full90) / (full30 * full30), 3.0 * w90 / w30);
}

TEST(GuenterLayers, MinimumInnerRadiusKeepsAFullRateFoveaAtAPrice) {
    const LayerDisplay d;
    LayerOptions o;
    o.slope = kSlopeB;
    const LayerPlan free_plan = *optimise_layers(d, o);
    o.min_inner_deg = 5.0 / 0.6;  // full weight (inside the 40 % blend) out to 5 degrees
    const LayerPlan fovea_plan = *optimise_layers(d, o);
    EXPECT_LT(free_plan.layers[0].radius_deg, o.min_inner_deg);
    EXPECT_GE(fovea_plan.layers[0].radius_deg, o.min_inner_deg);
    EXPECT_GT(fovea_plan.work, free_plan.work);
    EXPECT_LT(fovea_plan.shaded_fraction(), 0.5);  // still far below full rate
}

TEST(GuenterLayers, PortraitDisplayIsMeasuredAlongItsLongerAxis) {
    // Guenter fn. 8: for a portrait display width and resolution are those of the vertical axis.
    // The HMD eye (1440 x 1600, 98 x 104 degrees) and the same panel turned landscape.
    const LayerDisplay portrait = layer_display_for(1440, 1600, 98.0, 104.0);
    const LayerDisplay landscape = layer_display_for(1600, 1440, 104.0, 98.0);
    EXPECT_EQ(portrait.resolution_px, 1600);
    EXPECT_NEAR(portrait.aspect, 0.9, 1e-12);
    EXPECT_NEAR(display_radius_deg(portrait), 52.0, 1e-9);
    EXPECT_EQ(landscape.resolution_px, portrait.resolution_px);
    EXPECT_DOUBLE_EQ(landscape.width_cm, portrait.width_cm);
    EXPECT_DOUBLE_EQ(landscape.aspect, portrait.aspect);
    LayerOptions o;
    o.slope = kSlopeB;
    const auto p = optimise_layers(portrait, o);
    ASSERT_TRUE(p.ok()) << p.error().message;
    const LayerPlan l = *optimise_layers(landscape, o);
    ASSERT_EQ(p->layers.size(), l.layers.size());
    for (std::size_t i = 0; i < l.layers.size(); ++i)
        EXPECT_DOUBLE_EQ(p->layers[i].radius_deg, l.layers[i].radius_deg) << i;
    // The outer layer covers the whole 1440 x 1600 panel: P_n = α* D_n² = (1440/s)(1600/s).
    const Layer& outer = p->layers.back();
    EXPECT_NEAR(outer.pixels, 1440.0 * 1600.0 / (outer.sampling_factor * outer.sampling_factor),
                1e-6);
    EXPECT_DOUBLE_EQ(p->display_pixels, 1440.0 * 1600.0);
    EXPECT_GT(p->speedup(), 1.0);
    // A square display is both: aspect 1.
    EXPECT_DOUBLE_EQ(layer_display_for(1000, 1000, 90.0, 90.0).aspect, 1.0);
}

TEST(GuenterLayers, InnerRadiusForFoveaCoversItFromAnyGazePoint) {
    // Brute force over gaze points and directions on the study display: every pixel within the
    // fovea's eccentricity lies inside the full-weight 60 % of the inner layer's pixel radius,
    // and at the corner the bound is tight.
    const LayerDisplay d;
    const double fovea = 5.0;
    const double e1 = inner_radius_for_fovea(d, fovea, 0.6);
    const double f = 0.5 * d.resolution_px / std::tan(display_radius_deg(d) * kPi / 180.0);
    const double full_weight_px = 0.6 * f * std::tan(e1 * kPi / 180.0);  // Eq. 3 radius, 60 %
    const double w = d.resolution_px, h = d.aspect * d.resolution_px;
    auto angle_deg = [&](double x0, double y0, double x1, double y1) {
        const double ax = x0 - 0.5 * w, ay = y0 - 0.5 * h, bx = x1 - 0.5 * w, by = y1 - 0.5 * h;
        const double la = std::sqrt(ax * ax + ay * ay + f * f);
        const double lb = std::sqrt(bx * bx + by * by + f * f);
        const double c = (ax * bx + ay * by + f * f) / (la * lb);
        return std::acos(std::min(1.0, c)) * 180.0 / kPi;
    };
    double tightest = 1e9;
    for (double gx = 0; gx <= w; gx += w / 16)
        for (double gy = 0; gy <= h; gy += h / 9)
            for (int k = 0; k < 64; ++k) {
                const double a = 2.0 * kPi * k / 64;
                // The pixel just outside the full-weight disc is at least `fovea` away.
                const double e = angle_deg(gx, gy, gx + full_weight_px * std::cos(a),
                                           gy + full_weight_px * std::sin(a));
                EXPECT_GE(e, fovea - 1e-9) << gx << "," << gy << " dir " << k;
                tightest = std::min(tightest, e);
            }
    EXPECT_NEAR(tightest, fovea, 0.02);
    // At the display centre alone fovea / 0.6 would do; the corners need more.
    EXPECT_GT(e1, fovea / 0.6);
    LayerOptions o;
    o.min_inner_deg = e1;
    EXPECT_GE(optimise_layers(d, o)->layers[0].radius_deg, e1);
}

TEST(GuenterLayers, RejectsBadInput) {
    LayerDisplay d;
    LayerOptions o;
    o.layer_count = 5;
    EXPECT_FALSE(optimise_layers(d, o).ok());
    o.layer_count = 3;
    o.slope = 0.0;
    EXPECT_FALSE(optimise_layers(d, o).ok());
    o.slope = kSlopeB;
    d.aspect = 1.5;
    EXPECT_FALSE(optimise_layers(d, o).ok());
    d.aspect = 0.5625;
    o.fixed_s2 = 1000.0;  // e_1 beyond the display
    EXPECT_FALSE(optimise_layers(d, o).ok());
}

}  // namespace
}  // namespace fovea::vk::methods
