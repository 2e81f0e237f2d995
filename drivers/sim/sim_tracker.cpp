#include "sim/sim_tracker.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <string>

namespace fovea::drivers::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kNsPerS = 1e9;
constexpr int64_t kMsNs = 1'000'000;

double smoothstep(double u) {
    u = std::clamp(u, 0.0, 1.0);
    return u * u * (3.0 - 2.0 * u);
}

// Beta(a, b) density at its mode: the ratio peak velocity / mean velocity of the profile.
double beta_peak_density(double a, double b) {
    const double m = (a - 1.0) / (a + b - 2.0);
    const double log_beta = std::lgamma(a) + std::lgamma(b) - std::lgamma(a + b);
    return std::exp((a - 1.0) * std::log(m) + (b - 1.0) * std::log1p(-m) - log_beta);
}

}  // namespace

void distort(double s, bool right_eye, double& x, double& y) {
    if (s == 0.0) return;
    const double u = x - 0.5, v = y - 0.5;
    x += s * (0.035 + 0.06 * u + 0.03 * v + 0.10 * u * v + 0.08 * u * u - 0.04 * v * v +
              (right_eye ? -0.010 : 0.0));
    y += s * (-0.030 + 0.02 * u + 0.07 * v - 0.06 * u * v + 0.03 * u * u + 0.09 * v * v +
              (right_eye ? 0.008 : 0.0));
}

Result<void> validate(const SimConfig& c) {
    if (!(c.rate_hz >= 60.0 && c.rate_hz <= 2000.0))
        return make_error("sim: rate_hz must be within 60..2000, got " + std::to_string(c.rate_hz));
    if (c.counter_bits != 16 && c.counter_bits != 32 && c.counter_bits != 64)
        return make_error("sim: counter_bits must be 16, 32 or 64");
    if (!(c.tick_hz >= 1e3 && c.tick_hz <= 1e10))
        return make_error("sim: tick_hz must be 1e3..1e10");
    if (!(std::fabs(c.drift_ppm) <= 1000.0)) return make_error("sim: |drift_ppm| must be <= 1000");
    if (!(c.noise_deg >= 0 && c.noise_deg <= 5 && c.tremor_deg >= 0 && c.tremor_deg <= 1 &&
          c.drift_dps >= 0 && c.drift_dps <= 5 && std::fabs(c.vergence_deg) <= 5))
        return make_error(
            "sim: noise_deg 0..5, tremor_deg 0..1, drift_dps 0..5, |vergence_deg| <= 5");
    if (!(c.fixation_mean_ms >= 80 && c.fixation_mean_ms <= 5000))
        return make_error("sim: fixation_mean_ms must be within 80..5000");
    if (!(c.saccade_median_deg >= 0.5 && c.saccade_median_deg <= 30))
        return make_error("sim: saccade_median_deg must be within 0.5..30");
    if (!(c.blink_rate_hz >= 0 && c.blink_rate_hz <= 1))
        return make_error("sim: blink_rate_hz must be within 0..1");
    if (!(c.pursuit_share >= 0 && c.pursuit_share <= 0.8))
        return make_error("sim: pursuit_share must be within 0..0.8");
    if (!(c.pupil_mm >= 1.5 && c.pupil_mm <= 8)) return make_error("sim: pupil_mm must be 1.5..8");
    if (!(c.distortion >= 0 && c.distortion <= 3))
        return make_error("sim: distortion must be within 0..3");
    const auto& d = c.display;
    if (!(d.width_px > 0 && d.height_px > 0 && d.width_m > 0 && d.height_m > 0 && d.distance_m > 0))
        return make_error("sim: display geometry must be positive");
    return {};
}

SimTracker::Rng::Rng(uint64_t seed) {
    // splitmix64 expands the seed into xoshiro256** state.
    for (auto& word : s) {
        seed += 0x9e3779b97f4a7c15ULL;
        uint64_t z = seed;
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        word = z ^ (z >> 31);
    }
}

uint64_t SimTracker::Rng::next_u64() {
    const auto rotl = [](uint64_t x, int k) { return (x << k) | (x >> (64 - k)); };
    const uint64_t result = rotl(s[1] * 5, 7) * 9;
    const uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = rotl(s[3], 45);
    return result;
}

double SimTracker::Rng::uniform() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }
double SimTracker::Rng::uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

double SimTracker::Rng::normal() {
    const double u1 = 1.0 - uniform();  // (0, 1]
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
}

SimTracker::SimTracker(const SimConfig& config)
    : config_(config), rng_(config.seed), shape_rng_(config.seed ^ 0x5ACCADE5ULL) {
    assert(validate(config).ok());
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    config_.display.to_degrees(0.05, 0.05, x0, y0);
    config_.display.to_degrees(0.95, 0.95, x1, y1);
    half_w_deg_ = (x1 - x0) / 2;
    half_h_deg_ = (y1 - y0) / 2;

    // Solve for the per-movement chances that give the configured blink rate and pursuit share
    // (a fixation is followed by one movement: saccade + PSO, pursuit or blink).
    const double t_fix = config_.fixation_mean_ms * 1e-3;
    const double t_sac = 0.06, t_pur = 0.9, t_blink = 0.25;
    const double s = config_.pursuit_share;
    double pb = 0, pp = 0;
    for (int i = 0; i < 50; ++i) {
        const double cycle = t_fix + pp * t_pur + pb * t_blink + (1 - pp - pb) * t_sac;
        pb = std::min(0.5, config_.blink_rate_hz * cycle);
        pp = std::min(0.9 - pb, s * (t_fix + pb * t_blink + (1 - pb) * t_sac) /
                                    (t_pur - s * t_pur + s * t_sac));
    }
    p_blink_ = pb;
    p_pursuit_ = std::max(0.0, pp);

    const uint64_t range_mask =
        config_.counter_bits == 64 ? ~0ULL : (1ULL << config_.counter_bits) - 1;
    if (config_.counter_offset >= 0) {
        counter_offset_ = static_cast<uint64_t>(config_.counter_offset) & range_mask;
    } else {
        // Wrap ~10 s into the run so every consumer exercises counter unwrapping.
        const auto ten_s = static_cast<uint64_t>(10.0 * config_.tick_hz);
        counter_offset_ = ten_s < range_mask ? (range_mask - ten_s + 1) : 0;
    }

    // This subject's main sequence: the published curve scaled per subject (peak velocity and
    // duration each vary ~10 % between people; a seed is one subject). Saccade shapes draw from
    // their own stream, so the rest of the simulation does not depend on them.
    subject_ = config_.main_sequence;
    subject_.peak_dps *= 1.0 + std::clamp(0.10 * shape_rng_.normal(), -0.25, 0.25);
    const double dur_scale = 1.0 + std::clamp(0.08 * shape_rng_.normal(), -0.2, 0.2);
    subject_.duration_slope_ms *= dur_scale;
    subject_.duration_intercept_ms *= dur_scale;
    anisocoria_mm_ = rng_.uniform(-0.15, 0.15);
    bias_lx_ = rng_.normal() * 0.1;
    bias_ly_ = rng_.normal() * 0.1;
    bias_rx_ = rng_.normal() * 0.1;
    bias_ry_ = rng_.normal() * 0.1;
    hippus_phase_ = rng_.uniform(0, 2 * kPi);
    tremor_phase_x_ = rng_.uniform(0, 2 * kPi);
    tremor_phase_y_ = rng_.uniform(0, 2 * kPi);
    x_ = rng_.uniform(-0.3, 0.3) * half_w_deg_;
    y_ = rng_.uniform(-0.3, 0.3) * half_h_deg_;
    start_fixation(0, config_.fixation_mean_ms);
}

void SimTracker::clamp_to_display(double& x, double& y) const {
    x = std::clamp(x, -half_w_deg_, half_w_deg_);
    y = std::clamp(y, -half_h_deg_, half_h_deg_);
}

void SimTracker::start_fixation(int64_t t_ns, double mean_ms) {
    phase_ = Phase::kFixation;
    // Fixation durations are right-skewed: log-normal around the mean, clamped to 80..2000 ms.
    const double ms = std::clamp(mean_ms * 0.9 * std::exp(0.45 * rng_.normal()), 80.0, 2000.0);
    phase_start_ns_ = t_ns;
    phase_end_ns_ = t_ns + static_cast<int64_t>(ms * kMsNs);
    fix_x_ = target_held_ && !target_pending_ ? target_x_ : x_;
    fix_y_ = target_held_ && !target_pending_ ? target_y_ : y_;
    drift_dir_ = rng_.uniform(0, 2 * kPi);
    truth_.event = gaze::Event::kFixation;
    truth_.in_saccade = false;
}

bool SimTracker::start_saccade(int64_t t_ns) {
    // Amplitude: log-normal around the configured median, limited to what fits the display.
    double amp = std::clamp(config_.saccade_median_deg * std::exp(0.7 * rng_.normal()), 0.5, 30.0);
    double dx = 0, dy = 0;
    bool found = false;
    for (int attempt = 0; attempt < 24 && !found; ++attempt) {
        // Horizontal saccades dominate: squeeze the direction distribution towards the x axis.
        const double theta = rng_.uniform(0, 2 * kPi);
        dx = amp * std::cos(theta);
        dy = amp * 0.6 * std::sin(theta);
        const double norm = std::hypot(dx, dy);
        dx *= amp / norm;
        dy *= amp / norm;
        found = std::fabs(x_ + dx) <= half_w_deg_ && std::fabs(y_ + dy) <= half_h_deg_;
        if (attempt % 8 == 7) amp = std::max(0.5, amp * 0.6);
    }
    if (!found) {
        // Near an edge: jump back towards the centre.
        const double dist = std::hypot(x_, y_);
        if (dist < 0.5) return false;
        amp = std::clamp(dist * rng_.uniform(0.5, 1.0), 0.5, 30.0);
        dx = -x_ / dist * amp;
        dy = -y_ / dist * amp;
    }
    begin_saccade(t_ns, dx, dy, amp);
    return true;
}

void SimTracker::begin_saccade(int64_t t_ns, double dx, double dy, double amp) {
    // Per saccade: the duration spreads +-15-20 % (2 SD) around the subject's curve, the peak
    // velocity moves against it (a faster saccade of the same size is shorter), with its own
    // 4 % scatter, so the profile's peak-to-mean ratio Vp D / A varies too.
    const double dur_f = 1.0 + std::clamp(0.09 * rng_.normal(), -0.3, 0.3);
    const double dur_s = subject_.duration_s(amp) * dur_f;
    const double vp = subject_.peak_velocity_dps(amp) / dur_f *
                      (1.0 + std::clamp(0.04 * shape_rng_.normal(), -0.12, 0.12));
    // Velocity ~ Beta(a, b) in normalized time with its peak at 30-45 % of the duration, the
    // earlier the larger the saccade (fast acceleration, long deceleration); a sets how peaked
    // it is, chosen so the peak matches vp.
    const double q = std::max(1.05, vp * dur_s / amp);
    const double mode = std::clamp(0.45 - 0.15 * std::min(amp, 30.0) / 30.0 +
                                       std::clamp(0.03 * shape_rng_.normal(), -0.05, 0.05),
                                   0.28, 0.48);
    auto b_of = [mode](double a) { return 1.0 + (a - 1.0) * (1.0 - mode) / mode; };
    double lo = 1.0001, hi = 60.0;
    for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        (beta_peak_density(mid, b_of(mid)) < q ? lo : hi) = mid;
    }
    const double a = 0.5 * (lo + hi), b = b_of(a);
    profile_cdf_[0] = 0;
    for (int i = 0; i < kProfileSteps; ++i) {
        const double tau = (i + 0.5) / kProfileSteps;
        profile_cdf_[i + 1] =
            profile_cdf_[i] + std::pow(tau, a - 1.0) * std::pow(1.0 - tau, b - 1.0);
    }
    for (auto& v : profile_cdf_) v /= profile_cdf_[kProfileSteps];

    phase_ = Phase::kSaccade;
    phase_start_ns_ = t_ns;
    phase_end_ns_ = t_ns + static_cast<int64_t>(dur_s * kNsPerS);
    sac_x0_ = x_;
    sac_y0_ = y_;
    sac_dx_ = dx;
    sac_dy_ = dy;
    truth_.event = gaze::Event::kSaccade;
    truth_.in_saccade = true;
    truth_.saccade_onset_ns = config_.start_ns + t_ns;
    truth_.saccade_end_ns = config_.start_ns + phase_end_ns_;
    truth_.saccade_amplitude_deg = amp;
    truth_.saccade_peak_velocity_dps = vp;
    truth_.landing_x_deg = x_ + dx;
    truth_.landing_y_deg = y_ + dy;
}

void SimTracker::look_at(double x_deg, double y_deg) {
    target_x_ = x_deg;
    target_y_ = y_deg;
    clamp_to_display(target_x_, target_y_);
    target_held_ = target_pending_ = true;
    // Saccadic latency: the eyes leave 150-250 ms after the target appears.
    target_go_ns_ = prev_t_ns_ + static_cast<int64_t>(rng_.uniform(150.0, 250.0) * kMsNs);
}

void SimTracker::release() { target_held_ = target_pending_ = false; }

void SimTracker::maybe_go_to_target(int64_t t_ns) {
    // Leave from a fixation or a pursuit; a saccade, PSO or blink in progress finishes first.
    if (!target_pending_ || t_ns < target_go_ns_ ||
        (phase_ != Phase::kFixation && phase_ != Phase::kPursuit)) {
        return;
    }
    target_pending_ = false;
    const double dx = target_x_ - x_, dy = target_y_ - y_;
    if (std::hypot(dx, dy) < 0.05) {
        start_fixation(t_ns, config_.fixation_mean_ms);
    } else {
        begin_saccade(t_ns, dx, dy, std::hypot(dx, dy));
    }
}

void SimTracker::start_pursuit(int64_t t_ns) {
    // Speed log-uniform in 2..30 deg/s; the path must stay on the display for >= 300 ms.
    for (int attempt = 0; attempt < 12; ++attempt) {
        const double speed = 2.0 * std::exp(rng_.uniform(0, std::log(15.0)));
        const double theta = rng_.uniform(0, 2 * kPi);
        const double vx = speed * std::cos(theta), vy = speed * std::sin(theta);
        double t_max = 1.5;
        if (vx != 0) t_max = std::min(t_max, ((vx > 0 ? half_w_deg_ : -half_w_deg_) - x_) / vx);
        if (vy != 0) t_max = std::min(t_max, ((vy > 0 ? half_h_deg_ : -half_h_deg_) - y_) / vy);
        if (t_max < 0.3) continue;
        const double dur_s = rng_.uniform(0.3, t_max);
        phase_ = Phase::kPursuit;
        phase_start_ns_ = t_ns;
        phase_end_ns_ = t_ns + static_cast<int64_t>(dur_s * kNsPerS);
        pur_vx_ = vx;
        pur_vy_ = vy;
        truth_.event = gaze::Event::kPursuit;
        truth_.in_saccade = false;
        return;
    }
    if (!start_saccade(t_ns)) start_fixation(t_ns, config_.fixation_mean_ms);
}

void SimTracker::start_blink(int64_t t_ns) {
    const double dur_s = rng_.uniform(0.1, 0.4);
    phase_ = Phase::kBlink;
    phase_start_ns_ = t_ns;
    phase_end_ns_ = t_ns + static_cast<int64_t>(dur_s * kNsPerS);
    blink_in_s_ = rng_.uniform(0.015, 0.035);
    blink_out_s_ = rng_.uniform(0.025, 0.06);
    blink_sag_deg_ = rng_.uniform(1.5, 5.0);
    truth_.event = gaze::Event::kBlink;
    truth_.in_saccade = false;
}

void SimTracker::start_next_phase(int64_t t_ns) {
    switch (phase_) {
        case Phase::kFixation: {
            const double u = rng_.uniform();
            if (target_held_) {
                // Looking at a target: blink now and then, otherwise keep fixating it.
                if (u < p_blink_) {
                    start_blink(t_ns);
                } else {
                    start_fixation(t_ns, config_.fixation_mean_ms);
                }
            } else if (u < p_blink_) {
                start_blink(t_ns);
            } else if (u < p_blink_ + p_pursuit_) {
                start_pursuit(t_ns);
            } else if (!start_saccade(t_ns)) {
                start_fixation(t_ns, config_.fixation_mean_ms);
            }
            break;
        }
        case Phase::kSaccade: {
            x_ = sac_x0_ + sac_dx_;
            y_ = sac_y0_ + sac_dy_;
            // PSO: 10-40 ms, amplitude grows with the saccade; 1-1.5 cycles, decaying.
            const double amp = truth_.saccade_amplitude_deg;
            const double dur_s =
                std::clamp(0.010 + 0.0012 * amp + rng_.uniform(0, 0.012), 0.010, 0.040);
            pso_amp_deg_ = std::min(0.03 + 0.03 * amp, 0.6) * rng_.uniform(0.6, 1.2);
            pso_period_s_ = dur_s / rng_.uniform(1.0, 1.5);
            pso_decay_s_ = dur_s / 3.0;
            pso_eye_ratio_ = rng_.uniform(1.1, 1.5);
            phase_ = Phase::kPso;
            phase_start_ns_ = t_ns;
            phase_end_ns_ = t_ns + static_cast<int64_t>(dur_s * kNsPerS);
            truth_.event = gaze::Event::kPso;
            truth_.in_saccade = false;
            break;
        }
        case Phase::kPso:
        case Phase::kPursuit:
        case Phase::kBlink: start_fixation(t_ns, config_.fixation_mean_ms); break;
    }
}

double SimTracker::saccade_progress(double tau) const {
    tau = std::clamp(tau, 0.0, 1.0) * kProfileSteps;
    const int i = std::min(static_cast<int>(tau), kProfileSteps - 1);
    const double f = tau - i;
    return profile_cdf_[i] + f * (profile_cdf_[i + 1] - profile_cdf_[i]);
}

void SimTracker::advance(int64_t t_ns, double dt_s) {
    const double t_in = (t_ns - phase_start_ns_) / kNsPerS;
    switch (phase_) {
        case Phase::kFixation: {
            // Drift: a slowly turning velocity, pulled back towards the fixated point.
            drift_dir_ += 2.0 * std::sqrt(dt_s) * rng_.normal();
            x_ += (config_.drift_dps * std::cos(drift_dir_) - 1.5 * (x_ - fix_x_)) * dt_s;
            y_ += (config_.drift_dps * std::sin(drift_dir_) - 1.5 * (y_ - fix_y_)) * dt_s;
            break;
        }
        case Phase::kSaccade: {
            const double dur = (phase_end_ns_ - phase_start_ns_) / kNsPerS;
            const double p = saccade_progress(t_in / dur);
            x_ = sac_x0_ + sac_dx_ * p;
            y_ = sac_y0_ + sac_dy_ * p;
            break;
        }
        case Phase::kPso:
        case Phase::kBlink: break;
        case Phase::kPursuit: {
            const double ramp = smoothstep(t_in / 0.08);  // ~80 ms onset
            x_ += pur_vx_ * ramp * dt_s;
            y_ += pur_vy_ * ramp * dt_s;
            clamp_to_display(x_, y_);
            break;
        }
    }
    hippus_phase_ += 2 * kPi * 0.3 * dt_s + 0.3 * std::sqrt(dt_s) * rng_.normal();
    tremor_phase_x_ += 2 * kPi * 84.0 * dt_s;
    tremor_phase_y_ += 2 * kPi * 79.0 * dt_s;
}

void SimTracker::eye_outputs(int64_t t_ns, gaze::EyeSample& left, gaze::EyeSample& right) {
    const double t_in = (t_ns - phase_start_ns_) / kNsPerS;
    // Dynamic offsets per eye along the saccade direction (PSO) and horizontally (vergence).
    double pso = 0.0, pso_l = 1.0, pso_r = 1.0;
    double sac_diverge = 0.0;
    const double sac_len = std::hypot(sac_dx_, sac_dy_);
    const double ux = sac_len > 0 ? sac_dx_ / sac_len : 0, uy = sac_len > 0 ? sac_dy_ / sac_len : 0;
    if (phase_ == Phase::kPso) {
        const double dur = (phase_end_ns_ - phase_start_ns_) / kNsPerS;
        const double u = t_in / dur;
        pso = pso_amp_deg_ * std::exp(-t_in / pso_decay_s_) *
              std::sin(2 * kPi * t_in / pso_period_s_) * (1.0 - u * u * u);
        // The abducting eye (the one moving away from the nose) oscillates more.
        (ux > 0 ? pso_r : pso_l) = pso_eye_ratio_;
    } else if (phase_ == Phase::kSaccade) {
        // Transient divergence: the abducting eye leads during the saccade.
        const double dur = (phase_end_ns_ - phase_start_ns_) / kNsPerS;
        sac_diverge = 0.03 * sac_dx_ * std::sin(kPi * std::clamp(t_in / dur, 0.0, 1.0));
    }
    truth_.x_deg = x_ + pso * ux;
    truth_.y_deg = y_ + pso * uy;

    // Blink: occlusion 0..1 at the lid edges, invalid in between.
    bool closed = false;
    double occlusion = 0.0;
    if (phase_ == Phase::kBlink) {
        const double dur = (phase_end_ns_ - phase_start_ns_) / kNsPerS;
        if (t_in < blink_in_s_) {
            occlusion = t_in / blink_in_s_;
        } else if (t_in > dur - blink_out_s_) {
            occlusion = (dur - t_in) / blink_out_s_;
        } else {
            closed = true;
        }
    }

    const double tremor_x = config_.tremor_deg * std::sin(tremor_phase_x_);
    const double tremor_y = config_.tremor_deg * std::sin(tremor_phase_y_);
    const double pupil = config_.pupil_mm + 0.15 * std::sin(hippus_phase_);
    const double noise = config_.noise_deg * (1.0 + 3.0 * occlusion);
    const double sag = blink_sag_deg_ * occlusion * occlusion;

    auto make_eye = [&](gaze::EyeSample& eye, double side, double pso_gain, double bx, double by,
                        double pupil_mm) {
        if (closed) {
            eye = gaze::EyeSample{};  // lost: NaN position, no pupil, invalid
            rng_.normal();            // keep the random stream independent of blink timing
            rng_.normal();
            rng_.normal();
            return;
        }
        const double ex = x_ + pso * pso_gain * ux +
                          side * (config_.vergence_deg / 2 + sac_diverge) + bx + tremor_x +
                          noise * rng_.normal();
        const double ey = y_ + pso * pso_gain * uy + by + tremor_y + sag + noise * rng_.normal();
        config_.display.to_normalized(ex, ey, eye.x, eye.y);
        distort(config_.distortion, side < 0, eye.x, eye.y);
        eye.pupil_mm = std::max(0.5, pupil_mm * (1.0 - 0.6 * occlusion) + 0.01 * rng_.normal());
        eye.valid = true;
    };
    // Fixation disparity: the lines of sight cross slightly off the screen plane.
    make_eye(left, +1.0, pso_l, bias_lx_, bias_ly_, pupil + anisocoria_mm_ / 2);
    if (config_.binocular) {
        make_eye(right, -1.0, pso_r, bias_rx_, bias_ry_, pupil - anisocoria_mm_ / 2);
    } else {
        right = gaze::EyeSample{};
    }
}

uint64_t SimTracker::device_ticks(int64_t t_rel_ns) const {
    const long double ticks = static_cast<long double>(t_rel_ns) * config_.tick_hz *
                              (1.0L + config_.drift_ppm * 1e-6L) / 1e9L;
    const uint64_t raw = counter_offset_ + static_cast<uint64_t>(ticks);  // wraps mod 2^64
    return config_.counter_bits == 64 ? raw : raw & ((1ULL << config_.counter_bits) - 1);
}

SimTracker::Frame SimTracker::next() {
    const auto t_ns = static_cast<int64_t>(
        std::llround(static_cast<long double>(index_) * 1e9L / config_.rate_hz));
    const double dt_s = (t_ns - prev_t_ns_) / kNsPerS;
    // Phase boundaries fall at exact times, independent of the sampling rate.
    while (t_ns >= phase_end_ns_) start_next_phase(phase_end_ns_);
    maybe_go_to_target(t_ns);
    advance(t_ns, dt_s);

    Frame f;
    eye_outputs(t_ns, f.raw.left, f.raw.right);
    f.raw.device_ticks = device_ticks(t_ns);
    f.raw.truth = truth_.event;
    f.truth = truth_;
    f.t_true_ns = config_.start_ns + t_ns;
    prev_t_ns_ = t_ns;
    ++index_;
    return f;
}

}  // namespace fovea::drivers::sim
