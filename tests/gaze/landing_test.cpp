#include "fovea/gaze/landing.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace fovea::gaze {
namespace {

// A main-sequence saccade (duration from LandingParams) with the position profile of a
// Beta(a, b) CDF in normalised time, 500 Hz, uniform noise of +-0.02 deg on x: (3, 3) is minimum
// jerk, (2, 3) the early-peaked shape of the lund2013 labels (peak speed at ~1/3 of the
// duration). Returns the samples up to `fraction` of the duration.
struct Track {
    std::vector<double> t, x, y;
    double land_x, land_y;
};
Track beta_saccade(double amp, double a, double b, double fraction, uint32_t seed) {
    const LandingPredictor shape(LandingParams{.profile_a = a, .profile_b = b});
    const double dur = shape.duration_s(amp);
    Track tr{{}, {}, {}, 2.0 + 0.8 * amp, -1.0 + 0.6 * amp};
    for (double u = 0; u <= fraction * dur + 1e-12; u += 0.002) {
        seed = seed * 1664525u + 1013904223u;
        const double noise = (static_cast<double>(seed >> 8) / 16777216.0 - 0.5) * 0.04;
        tr.t.push_back(u);
        tr.x.push_back(2.0 + 0.8 * amp * shape.profile(u / dur, amp) + noise);
        tr.y.push_back(-1.0 + 0.6 * amp * shape.profile(u / dur, amp));
    }
    return tr;
}

double landing_error(const LandingEstimate& e, const Track& tr) {
    return std::hypot(e.x_deg - tr.land_x, e.y_deg - tr.land_y);
}

// From half its duration the landing point of either shape is within 20 % of the amplitude
// (the current position is 50 % away for minimum jerk, ~35 % for the early-peaked shape).
// Not exact: the deceleration estimates assume a slow-down between linear and early-peaked
// (landing.hpp), neither shape is exactly that.
TEST(LandingPredictor, PredictsMainSequenceSaccadeFromHalfItsDuration) {
    LandingPredictor p;
    for (auto [a, b] : {std::pair{3.0, 3.0}, std::pair{2.0, 3.0}}) {
        for (double amp : {6.0, 12.0, 20.0}) {
            const Track tr = beta_saccade(amp, a, b, 0.5, 3);
            const LandingEstimate e = p.predict(tr.t, tr.x, tr.y);
            ASSERT_TRUE(e.valid);
            const double now = std::hypot(tr.x.back() - tr.land_x, tr.y.back() - tr.land_y);
            EXPECT_LT(landing_error(e, tr), 0.2 * amp) << amp << " beta " << a << "," << b;
            EXPECT_LT(landing_error(e, tr), 0.6 * now) << amp << " beta " << a << "," << b;
            EXPECT_GT(e.uncertainty_deg, 0.0) << amp;
        }
    }
}

// At 75 % of a minimum-jerk saccade the peak speed is behind the eye and estimate 3 joins: the
// prediction must beat the current position (~16 % away) and stay within 10 % (6 deg: 8.9 %).
// (An early-peaked Beta(2, 3) profile, which ends faster than the lund2013 labels do, is
// overshot at 75 %: ~12 % of the amplitude against the current position's ~5 %.)
TEST(LandingPredictor, MinimumJerkSaccadeAtThreeQuartersBeatsCurrentPosition) {
    LandingPredictor p;
    for (double amp : {6.0, 12.0, 20.0}) {
        const Track tr = beta_saccade(amp, 3.0, 3.0, 0.75, 11);
        const LandingEstimate e = p.predict(tr.t, tr.x, tr.y);
        ASSERT_TRUE(e.valid);
        const double now = std::hypot(tr.x.back() - tr.land_x, tr.y.back() - tr.land_y);
        EXPECT_LT(landing_error(e, tr), now) << amp;
        EXPECT_LT(landing_error(e, tr), 0.10 * amp) << amp;
    }
}

// Estimate 3 solves A = d + c v (r A / Vp - t): it must reproduce an amplitude built to satisfy
// that relation, and stay silent while the speed has not dropped below the peak-passed ratio.
TEST(LandingPredictor, PeakSpeedEstimateSolvesItsRelation) {
    const LandingParams params;
    const LandingPredictor p(params);
    const double amp = 10.0, vp = 400.0, t = 0.03, v = 0.5 * vp;
    const double c = params.deceleration_factor, r = params.peak_to_mean_speed;
    const double d = amp - c * v * (r * amp / vp - t);
    EXPECT_NEAR(p.amplitude_from_peak(t, d, v, vp), amp, 1e-9);
    EXPECT_TRUE(std::isnan(p.amplitude_from_peak(t, d, 0.95 * vp, vp)));
    EXPECT_TRUE(std::isnan(p.amplitude_from_peak(t, d, v, 0.0)));
    // Never behind the eye: a slow eye far along predicts at least where it is.
    EXPECT_GE(p.amplitude_from_peak(0.2, 9.0, 10.0, vp), 9.0);
}

TEST(LandingPredictor, UncertaintyShrinksAsSaccadeProgresses) {
    LandingPredictor p;
    const double amp = 10.0, dur = p.duration_s(amp);
    double last = 1e9;
    for (double frac : {0.25, 0.5, 0.75, 0.95}) {
        std::vector<double> t, x, y;
        for (double u = 0; u <= frac * dur; u += 0.0005) {
            t.push_back(u);
            x.push_back(amp * p.profile(u / dur, amp));
            y.push_back(0.0);
        }
        const LandingEstimate e = p.predict(t, x, y);
        ASSERT_TRUE(e.valid);
        EXPECT_LT(e.uncertainty_deg, last) << frac;
        last = e.uncertainty_deg;
    }
}

// On the noisy synthetic shapes the radius holds the error from half the duration on, shrinks
// and ends small. Not at 25 %: the eye has covered only 10-26 % of the amplitude with a slow
// start, and both estimates take it for a small saccade ending (predicted A ~2 deg for 12 deg),
// so the fraction, and with it the radius, is wrong too; the lund2013 labels show the same
// (median error 4.4 deg at 25 %), where the radius holds 62 % of the errors.
TEST(LandingPredictor, UncertaintyRadiusHoldsTheError) {
    LandingPredictor p;
    for (auto [a, b] : {std::pair{3.0, 3.0}, std::pair{2.0, 3.0}}) {
        for (double amp : {6.0, 12.0, 20.0}) {
            double last = 1e9;
            for (double frac : {0.5, 0.75, 0.95}) {
                const Track tr = beta_saccade(amp, a, b, frac, 5);
                const LandingEstimate e = p.predict(tr.t, tr.x, tr.y);
                ASSERT_TRUE(e.valid);
                EXPECT_LE(landing_error(e, tr), e.uncertainty_deg) << amp << " at " << frac;
                EXPECT_LT(e.uncertainty_deg, last) << amp << " at " << frac;
                last = e.uncertainty_deg;
            }
            EXPECT_LT(last, 0.1 * amp) << amp;
        }
    }
}

// The late correction is off before late_from, fully on from late_full, linear between.
TEST(LandingPredictor, LateCorrectionRampsInWithTheElapsedFraction) {
    const LandingParams params;
    const LandingPredictor p(params);
    EXPECT_EQ(p.late_weight(0.5 * params.late_from), 0.0);
    EXPECT_EQ(p.late_weight(params.late_full), 1.0);
    EXPECT_EQ(p.late_weight(1.0), 1.0);
    EXPECT_NEAR(p.late_weight(0.5 * (params.late_from + params.late_full)), 0.5, 1e-12);

    // Early observation: the estimate is the base amplitude; late: base x exp(correction).
    LandingObservation obs;
    obs.valid = true;
    obs.ux = 1.0;
    obs.elapsed_s = 0.02;
    obs.displacement_deg = 4.0;
    obs.speed_dps = 200.0;
    obs.peak_speed_dps = 400.0;
    obs.base_amplitude_deg = 10.0;
    obs.phase_fraction = 0.3;
    EXPECT_NEAR(p.estimate(obs).amplitude_deg, 10.0, 1e-12);
    obs.phase_fraction = 0.9;
    const double expected = 10.0 * std::exp(params.late_bias + params.late_displacement * 0.4 +
                                            params.late_speed * 0.5);
    EXPECT_NEAR(p.estimate(obs).amplitude_deg, expected, 1e-9);
    EXPECT_NEAR(p.estimate(obs).x_deg, expected, 1e-9);
    // A push beyond the base amplitude is capped (here the formula would give e^0.27).
    obs.displacement_deg = 10.0;
    obs.speed_dps = 400.0;
    EXPECT_NEAR(p.estimate(obs).amplitude_deg, 10.0 * std::exp(params.late_max_log_push), 1e-9);
    // Never behind the eye's covered distance.
    obs.displacement_deg = 9.9;
    obs.base_amplitude_deg = 40.0;
    EXPECT_GE(p.estimate(obs).amplitude_deg, 9.9);
}

// The least-absolute-error fit recovers the constants that generated the landings, even with
// a quarter of the rows replaced by gross outliers (which least squares would follow), and
// ignores rows too early for the correction.
TEST(LandingPredictor, LateCorrectionFitRecoversConstantsDespiteOutliers) {
    const LandingPredictor p;
    const double bias = -0.8, disp = 0.9, speed = 0.3;
    std::vector<LateCorrectionRow> rows;
    uint32_t seed = 7;
    auto uniform = [&] {
        seed = seed * 1664525u + 1013904223u;
        return static_cast<double>(seed >> 8) / 16777216.0;
    };
    for (int k = 0; k < 400; ++k) {
        LateCorrectionRow r;
        r.obs.valid = true;
        r.obs.base_amplitude_deg = 5.0 + 10.0 * uniform();
        r.obs.displacement_deg = r.obs.base_amplitude_deg * (0.5 + 0.5 * uniform());
        r.obs.peak_speed_dps = 400.0;
        r.obs.speed_dps = 400.0 * uniform();
        r.obs.phase_fraction = 0.7 + 0.3 * uniform();
        const double log_ratio = bias + disp * r.obs.displacement_deg / r.obs.base_amplitude_deg +
                                 speed * r.obs.speed_dps / r.obs.peak_speed_dps;
        r.landed_along_deg = r.obs.base_amplitude_deg * std::exp(log_ratio);
        if (k % 4 == 0) r.landed_along_deg *= 3.0;  // outlier
        rows.push_back(r);
        if (k % 2 == 0) {  // too early: must not enter the fit
            r.obs.phase_fraction = 0.2;
            r.landed_along_deg *= 5.0;
            rows.push_back(r);
        }
    }
    const LateCorrection c = p.fit_late_correction(rows);
    EXPECT_EQ(c.rows, 400u);
    EXPECT_NEAR(c.bias, bias, 0.02);
    EXPECT_NEAR(c.displacement, disp, 0.02);
    EXPECT_NEAR(c.speed, speed, 0.02);
}

TEST(LandingPredictor, DegenerateInputIsInvalid) {
    LandingPredictor p;
    std::vector<double> t{0.0}, x{1.0}, y{1.0};
    EXPECT_FALSE(p.predict(t, x, y).valid);
    std::vector<double> t2{0.0, 0.001}, x2{1.0, std::nan("")}, y2{1.0, 1.0};
    EXPECT_FALSE(p.predict(t2, x2, y2).valid);
}

}  // namespace
}  // namespace fovea::gaze
