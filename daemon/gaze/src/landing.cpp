#include "fovea/gaze/landing.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "fovea/gaze/sample.hpp"
#include "gauss_jordan.hpp"

namespace fovea::gaze {

LandingPredictor::LandingPredictor(const LandingParams& params) : p_(params) {
    const double a = std::max(1.0, p_.profile_a), b = std::max(1.0, p_.profile_b);
    cdf_[0] = 0.0;
    for (int i = 0; i < kSteps; ++i) {
        const double tau = (i + 0.5) / kSteps;
        cdf_[i + 1] = cdf_[i] + std::pow(tau, a - 1.0) * std::pow(1.0 - tau, b - 1.0);
    }
    for (auto& v : cdf_) v /= cdf_[kSteps];
}

double LandingPredictor::duration_s(double a) const { return p_.main_sequence.duration_s(a); }

double LandingPredictor::profile(double tau, double amplitude_deg) const {
    (void)amplitude_deg;
    if (!(tau > 0.0)) return 0.0;
    if (tau >= 1.0) return 1.0;
    const double u = tau * kSteps;
    const int i = static_cast<int>(u);
    return cdf_[i] + (u - i) * (cdf_[i + 1] - cdf_[i]);
}

double LandingPredictor::speed_profile(double tau) const {
    if (!(tau > 0.0) || tau >= 1.0) return 0.0;
    const int i = std::min(kSteps - 1, static_cast<int>(tau * kSteps));
    return (cdf_[i + 1] - cdf_[i]) * kSteps;
}

double LandingPredictor::amplitude_from_profile(double t, double d, double v) const {
    const double top = p_.max_amplitude_deg;
    const double lo_amp = std::max(d, 0.05);
    if (lo_amp >= top) return top;
    // Covered distance of a main-sequence saccade of amplitude A after t: A * s(t / D(A)).
    // It rises with A while the saccade would already be near its end, then falls again (a
    // large saccade has barely started), so two amplitudes can explain d: a small saccade
    // ending and a large one in mid-flight. The eye's current speed tells them apart. If no
    // A reaches d the eye moves faster than the main sequence allows: take the closest.
    auto covered = [&](double a) { return a * profile(t / duration_s(a), a); };
    auto speed_misfit = [&](double a) {
        const double dur = duration_s(a);
        return std::fabs(std::log((a / dur * speed_profile(t / dur) + 1.0) / (v + 1.0)));
    };
    constexpr int kGrid = 48;
    const double step = std::log(top / lo_amp) / kGrid;
    double best = std::log(lo_amp), best_cov = -1.0;
    double root = kNaN, root_misfit = 1e300;
    double prev = std::log(lo_amp), prev_c = covered(lo_amp);
    if (prev_c >= d) return lo_amp;
    for (int g = 1; g <= kGrid; ++g) {
        const double la = std::log(lo_amp) + step * g;
        const double c = covered(std::exp(la));
        if ((c >= d) != (prev_c >= d)) {
            double lo = prev, hi = la;
            const bool rising = c >= d;
            for (int it = 0; it < 24; ++it) {
                const double mid = 0.5 * (lo + hi);
                ((covered(std::exp(mid)) >= d) == rising ? hi : lo) = mid;
            }
            const double a = std::exp(0.5 * (lo + hi));
            const double misfit = speed_misfit(a);
            if (misfit < root_misfit) {
                root_misfit = misfit;
                root = a;
            }
        }
        if (c > best_cov) {
            best_cov = c;
            best = la;
        }
        prev = la;
        prev_c = c;
    }
    return std::isfinite(root) ? root : std::exp(best);
}

double LandingPredictor::amplitude_from_deceleration(double t, double d, double v) const {
    // A = d + c v (D(A) - t) with D(A) = s A + i  =>  A (1 - c v s) = d + c v (i - t).
    const double cv = p_.deceleration_factor * std::max(0.0, v);
    const double den = 1.0 - cv * p_.main_sequence.duration_slope_ms * 1e-3;
    double a = p_.max_amplitude_deg;
    // A speed near the main sequence's asymptote says "large", not how large.
    if (den > 0.15) a = (d + cv * (p_.main_sequence.duration_intercept_ms * 1e-3 - t)) / den;
    return std::clamp(a, std::max(d, 1e-3), std::max(d, p_.max_amplitude_deg));
}

double LandingPredictor::amplitude_from_peak(double t, double d, double v, double vp) const {
    if (!(vp > 0.0) || !(v < p_.peak_passed_ratio * vp)) return kNaN;
    // A = d + c v (r A / Vp - t)  =>  A (1 - c v r / Vp) = d - c v t; v < Vp keeps the
    // denominator above 1 - c r (> 0 for c r < 1).
    const double cv = p_.deceleration_factor * std::max(0.0, v);
    const double den = 1.0 - cv * p_.peak_to_mean_speed / vp;
    if (!(den > 0.05)) return kNaN;
    const double a = (d - cv * t) / den;
    return std::clamp(a, std::max(d, 1e-3), std::max(d, p_.max_amplitude_deg));
}

namespace {

// Least-squares line through samples [from, to) of the projected track: slope and the value
// at t_s[to - 1].
struct Line {
    double slope, end_value;
    double mean_t, mean_value;  // the fit's centre: the slope is the speed there
};
Line fit_line(std::span<const double> t_s, const double* along, size_t from, size_t to) {
    const double m = static_cast<double>(to - from);
    double tm = 0, pm = 0;
    for (size_t i = from; i < to; ++i) {
        tm += t_s[i];
        pm += along[i];
    }
    tm /= m;
    pm /= m;
    double stt = 0, stp = 0;
    for (size_t i = from; i < to; ++i) {
        stt += (t_s[i] - tm) * (t_s[i] - tm);
        stp += (t_s[i] - tm) * (along[i] - pm);
    }
    if (!(stt > 0)) return {kNaN, kNaN, kNaN, kNaN};
    const double slope = stp / stt;
    return {slope, pm + slope * (t_s[to - 1] - tm), tm, pm};
}

}  // namespace

LandingObservation LandingPredictor::observe(std::span<const double> t_s,
                                             std::span<const double> x_deg,
                                             std::span<const double> y_deg) const {
    LandingObservation obs;
    const size_t n = std::min({t_s.size(), x_deg.size(), y_deg.size()});
    if (n < 2) return obs;
    const double x0 = x_deg[0], y0 = y_deg[0];
    const double dx = x_deg[n - 1] - x0, dy = y_deg[n - 1] - y0;
    const double d_now = std::hypot(dx, dy);
    const double t_now = t_s[n - 1];
    if (!std::isfinite(d_now) || !std::isfinite(t_now) || t_now <= 0.0) return obs;
    if (d_now < 1e-6) return obs;
    // Direction: onset to the newest sample (fits over the whole trajectory are pulled off by
    // the curved start of oblique saccades; blending in the newest heading gains nothing).
    const double ux = dx / d_now, uy = dy / d_now;

    // Displacement and speed along that direction from lines through the newest samples (one
    // noisy sample would set both); the same fit over earlier windows gives the peak speed.
    constexpr size_t kMaxSamples = 512;  // 1 s at 500 Hz: longer "saccades" use the newest
    const size_t first = n > kMaxSamples ? n - kMaxSamples : 0;
    double along[kMaxSamples];
    const size_t count = n - first;
    for (size_t i = 0; i < count; ++i)
        along[i] = (x_deg[first + i] - x0) * ux + (y_deg[first + i] - y0) * uy;
    const auto ts = t_s.subspan(first, count);
    const size_t m = std::min(count, static_cast<size_t>(std::max(2, p_.speed_fit_samples)));
    const Line now = fit_line(ts, along, count - m, count);
    if (!std::isfinite(now.slope) || !std::isfinite(now.end_value)) return obs;
    const double v = std::max(0.0, now.slope);
    const double d = std::max(1e-3, now.end_value);
    double peak = 0.0;  // highest speed of the earlier windows (the newest one is v)
    for (size_t end = m; end < count; ++end) {
        const double s = fit_line(ts, along, end - m, end).slope;
        if (std::isfinite(s)) peak = std::max(peak, s);
    }

    auto combined = [&](double t, double dist) {
        const double a_profile = amplitude_from_profile(t, dist, v);
        const double a_decel = amplitude_from_deceleration(t, dist, v);
        const double a_peak = amplitude_from_peak(t, dist, v, peak);
        return std::isfinite(a_peak) ? std::cbrt(a_profile * a_decel * a_peak)
                                     : std::sqrt(a_profile * a_decel);
    };
    // The prediction: the newest displacement with the line's (older) slope.
    const double amp = combined(t_now, d);
    if (!std::isfinite(amp)) return obs;
    // The late correction's phase (landing.hpp): also the estimates at the line's mean time,
    // where displacement, speed and time belong to one instant.
    const double amp_mean = combined(now.mean_t, std::max(1e-3, now.mean_value));
    const double phase_amp = std::isfinite(amp_mean) ? std::sqrt(amp * amp_mean) : amp;
    obs.valid = true;
    obs.x0_deg = x0;
    obs.y0_deg = y0;
    obs.ux = ux;
    obs.uy = uy;
    obs.elapsed_s = t_now;
    obs.displacement_deg = d;
    obs.speed_dps = v;
    obs.peak_speed_dps = std::max(peak, v);
    obs.base_amplitude_deg = amp;
    obs.phase_amplitude_deg = phase_amp;
    obs.phase_fraction = std::min(1.0, t_now / duration_s(phase_amp));
    return obs;
}

double LandingPredictor::late_weight(double f) const {
    const double span = p_.late_full - p_.late_from;
    if (!(span > 0.0)) return f >= p_.late_full ? 1.0 : 0.0;
    return std::clamp((f - p_.late_from) / span, 0.0, 1.0);
}

namespace {

// The late correction's features: the log of A / A_base is linear in them.
std::array<double, 3> late_features(const LandingObservation& o) {
    return {1.0, o.displacement_deg / o.base_amplitude_deg,
            o.peak_speed_dps > 0.0 ? o.speed_dps / o.peak_speed_dps : 1.0};
}

}  // namespace

LandingEstimate LandingPredictor::estimate(const LandingObservation& obs) const {
    LandingEstimate est;
    if (!obs.valid) return est;
    double amp = obs.base_amplitude_deg;
    const double w = late_weight(obs.phase_fraction);
    if (w > 0.0) {
        const auto x = late_features(obs);
        const double log_ratio =
            p_.late_bias * x[0] + p_.late_displacement * x[1] + p_.late_speed * x[2];
        // Pulled back at most e^-2 (no feature outlier throws the landing point far; the fitted
        // pull-backs stay within e^-1.4), pushed on at most late_max_log_push (landing.hpp).
        amp *= std::exp(w * std::clamp(log_ratio, -2.0, p_.late_max_log_push));
        // The eye has already covered d along the direction: it lands no nearer than that.
        amp = std::clamp(amp, obs.displacement_deg,
                         std::max(obs.displacement_deg, p_.max_amplitude_deg));
    }
    if (!std::isfinite(amp)) return est;
    const double dur = duration_s(amp);
    est.valid = true;
    est.amplitude_deg = amp;
    est.duration_s = dur;
    est.fraction = std::min(1.0, obs.elapsed_s / dur);
    est.x_deg = obs.x0_deg + obs.ux * amp;
    est.y_deg = obs.y0_deg + obs.uy * amp;
    // Uncertainty: shrinks with the elapsed fraction as measured on the labels (landing.hpp).
    const double f = std::max(0.05, est.fraction);
    est.uncertainty_deg = std::min(p_.uncertainty_scale * amp * std::pow(f, -p_.uncertainty_power),
                                   p_.max_amplitude_deg) +
                          p_.position_noise_deg;
    return est;
}

LandingEstimate LandingPredictor::predict(std::span<const double> t_s,
                                          std::span<const double> x_deg,
                                          std::span<const double> y_deg) const {
    return estimate(observe(t_s, x_deg, y_deg));
}

LateCorrection LandingPredictor::fit_late_correction(
    std::span<const LateCorrectionRow> rows) const {
    // Rows in the fit: late enough that the correction carries at least half weight.
    const double from = 0.5 * (p_.late_from + p_.late_full);
    std::vector<std::array<double, 3>> x;
    std::vector<double> y;
    for (const auto& r : rows) {
        const auto& o = r.obs;
        if (!o.valid || o.phase_fraction < from || !(o.base_amplitude_deg > 0.0)) continue;
        // A landing behind the covered distance (a curved or returning track) counts as
        // landing just past it.
        const double landed = std::max(r.landed_along_deg, o.displacement_deg + 0.02);
        const double target = std::log(landed / o.base_amplitude_deg);
        if (!std::isfinite(target)) continue;
        x.push_back(late_features(o));
        y.push_back(target);
    }
    LateCorrection out;
    out.rows = y.size();
    if (y.size() < 3) return out;
    // Iteratively reweighted least squares for the least absolute error: weights 1 / |residual|
    // (floored at 0.05, i.e. 5 %), 12 rounds; a tiny ridge keeps the 3x3 system regular.
    std::array<double, 3> beta{};
    std::vector<double> w(y.size(), 1.0);
    for (int round = 0; round <= 12; ++round) {
        double a[3][4] = {};
        for (size_t k = 0; k < y.size(); ++k) {
            for (int i = 0; i < 3; ++i) {
                for (int j = 0; j < 3; ++j) a[i][j] += w[k] * x[k][i] * x[k][j];
                a[i][3] += w[k] * x[k][i] * y[k];
            }
        }
        for (int i = 0; i < 3; ++i) a[i][i] += 1e-6;
        if (!detail::gauss_jordan<3, 1>(a)) return out;
        for (int i = 0; i < 3; ++i) beta[i] = a[i][3];
        for (size_t k = 0; k < y.size(); ++k) {
            const double r = beta[0] * x[k][0] + beta[1] * x[k][1] + beta[2] * x[k][2] - y[k];
            w[k] = 1.0 / std::max(std::fabs(r), 0.05);
        }
    }
    out.bias = beta[0];
    out.displacement = beta[1];
    out.speed = beta[2];
    return out;
}

}  // namespace fovea::gaze
