#include "fovea/gaze/landing.hpp"

#include <algorithm>
#include <cmath>

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

double LandingPredictor::duration_s(double a) const {
    return (p_.duration_slope_ms * a + p_.duration_intercept_ms) * 1e-3;
}

double LandingPredictor::profile(double tau, double amplitude_deg) const {
    (void)amplitude_deg;
    if (!(tau > 0.0)) return 0.0;
    if (tau >= 1.0) return 1.0;
    const double u = tau * kSteps;
    const int i = static_cast<int>(u);
    return cdf_[i] + (u - i) * (cdf_[i + 1] - cdf_[i]);
}

LandingEstimate LandingPredictor::predict(std::span<const double> t_s,
                                          std::span<const double> x_deg,
                                          std::span<const double> y_deg) const {
    LandingEstimate est;
    const size_t n = std::min({t_s.size(), x_deg.size(), y_deg.size()});
    if (n < 2) return est;
    const double x0 = x_deg[0], y0 = y_deg[0];
    const double dx = x_deg[n - 1] - x0, dy = y_deg[n - 1] - y0;
    const double d_now = std::hypot(dx, dy);
    const double t_now = t_s[n - 1];
    if (!std::isfinite(d_now) || !std::isfinite(t_now) || t_now <= 0.0) return est;
    if (d_now < 1e-6) return est;
    const double ux = dx / d_now, uy = dy / d_now;

    // Pick up to max_fit_points samples, always including the newest.
    const int m = std::max(2, p_.max_fit_points);
    double ts[64], ds[64];
    int k = 0;
    const size_t step =
        std::max<size_t>(1, (n - 1 + static_cast<size_t>(m) - 1) / static_cast<size_t>(m));
    for (size_t i = (n - 1) % step; i < n && k < 64; i += step) {
        ts[k] = t_s[i];
        ds[k] = (x_deg[i] - x0) * ux + (y_deg[i] - y0) * uy;
        ++k;
    }
    auto cost = [&](double a) {
        const double dur = duration_s(a);
        double c = 0.0;
        for (int i = 0; i < k; ++i) {
            // Later samples carry more information about the amplitude.
            const double w = 0.25 + ts[i] / t_now;
            const double r = ds[i] - a * profile(ts[i] / dur, a);
            c += w * r * r;
        }
        return c;
    };
    // Golden-section search on log amplitude: the displacement so far bounds A from below.
    // The cost is not unimodal early in flight (a small saccade near its end vs a large one
    // starting): a coarse log grid first, then golden section around the best cell.
    double glo = std::log(std::max(0.1, d_now)), ghi = std::log(80.0);
    if (glo >= ghi) glo = ghi - 1.0;
    constexpr int kGrid = 24;
    int best = 0;
    double best_cost = 1e300;
    for (int g = 0; g <= kGrid; ++g) {
        const double c = cost(std::exp(glo + (ghi - glo) * g / kGrid));
        if (c < best_cost) {
            best_cost = c;
            best = g;
        }
    }
    const double cell = (ghi - glo) / kGrid;
    double lo = std::max(glo, glo + cell * (best - 1)), hi = std::min(ghi, glo + cell * (best + 1));
    constexpr double kG = 0.6180339887498949;
    double a = hi - kG * (hi - lo), b = lo + kG * (hi - lo);
    double fa = cost(std::exp(a)), fb = cost(std::exp(b));
    for (int it = 0; it < 20; ++it) {
        if (fa < fb) {
            hi = b;
            b = a;
            fb = fa;
            a = hi - kG * (hi - lo);
            fa = cost(std::exp(a));
        } else {
            lo = a;
            a = b;
            fa = fb;
            b = lo + kG * (hi - lo);
            fb = cost(std::exp(b));
        }
    }
    const double amp = std::exp(0.5 * (lo + hi));
    const double dur = duration_s(amp);
    const double residual = std::sqrt(cost(amp) / std::max(1, k));
    est.valid = std::isfinite(amp);
    est.amplitude_deg = amp;
    est.duration_s = dur;
    est.fraction = std::min(1.0, t_now / dur);
    est.x_deg = x0 + ux * amp;
    est.y_deg = y0 + uy * amp;
    // Amplitude SD from the cost's curvature (flat early in the flight, sharp late), for a
    // measurement noise of at least 0.05 deg, plus 5 % model error (main-sequence spread).
    const double h = std::max(0.01, 0.02 * amp);
    const double curv = (cost(amp + h) - 2.0 * cost(amp) + cost(std::max(1e-3, amp - h))) / (h * h);
    const double noise = std::max(0.05, residual);
    const double sd_fit = curv > 0 ? std::sqrt(2.0 * noise * noise / curv) : amp;
    est.uncertainty_deg = std::hypot(std::min(sd_fit, 2.0 * amp), 0.05 * amp, residual);
    return est;
}

}  // namespace fovea::gaze
