#include "gaze_timeline.hpp"

#include <algorithm>
#include <cmath>

namespace fovea::openxr {
namespace {

// Minimum-jerk position profile (the Beta(3, 3) CDF the landing predictor also assumes).
double min_jerk(double tau) {
    tau = std::clamp(tau, 0.0, 1.0);
    return tau * tau * tau * (10.0 + tau * (-15.0 + 6.0 * tau));
}

// Turn `d` about the axis of the rotation a -> b by `scale` times its angle.
Vec3 continue_rotation(const Vec3& a, const Vec3& b, double scale) {
    const Vec3 axis = cross(a, b);
    const double s = norm(axis);
    if (s < 1e-12) return b;
    const double angle = std::atan2(s, dot(a, b)) * scale;
    const Vec3 u = scaled(axis, 1.0 / s);
    const double h = angle / 2;
    return normalized(
        rotate(Quat{u[0] * std::sin(h), u[1] * std::sin(h), u[2] * std::sin(h), std::cos(h)}, b));
}

}  // namespace

const char* status_name(GazeStatus s) {
    switch (s) {
        case GazeStatus::kTracked: return "tracked";
        case GazeStatus::kUntracked: return "untracked";
        case GazeStatus::kStale: return "stale";
        case GazeStatus::kNoData: return "no data";
        case GazeStatus::kTooOld: return "before the kept history";
    }
    return "?";
}

const char* method_name(GazeMethod m) {
    switch (m) {
        case GazeMethod::kNone: return "none";
        case GazeMethod::kInterpolated: return "interpolated";
        case GazeMethod::kNearest: return "nearest";
        case GazeMethod::kHeld: return "held";
        case GazeMethod::kLanding: return "landing";
        case GazeMethod::kPursuit: return "pursuit";
    }
    return "?";
}

GazeTimeline::GazeTimeline(TimelineParams params, std::size_t capacity)
    : params_(params), capacity_(std::max<std::size_t>(capacity, 2)) {}

void GazeTimeline::clear() { samples_.clear(); }

void GazeTimeline::push(const GazeSample& in) {
    GazeSample s = in;
    if (!samples_.empty()) {
        const int64_t newest = samples_.back().t_ns;
        if (s.t_ns < newest - params_.clock_jump_ns) {
            ++clock_jumps_;
            samples_.clear();
        } else if (s.t_ns <= newest) {
            s.t_ns = newest + 1;
        }
    }
    samples_.push_back(s);
    while (samples_.size() > capacity_) samples_.pop_front();
}

GazeEstimate GazeTimeline::at(int64_t t, int64_t now) const {
    GazeEstimate e;
    if (samples_.empty()) return e;
    e.t_newest_ns = samples_.back().t_ns;
    if (t >= samples_.back().t_ns) return beyond_newest(t, now);
    e.t_expressed_ns = t;
    if (t < samples_.front().t_ns) {
        e.status = GazeStatus::kTooOld;
        return e;
    }
    const auto hi = std::upper_bound(samples_.begin(), samples_.end(), t,
                                     [](int64_t v, const GazeSample& s) { return v < s.t_ns; });
    const GazeSample& b = *hi;
    const GazeSample& a = *(hi - 1);
    if (a.valid && b.valid) {
        const double f = static_cast<double>(t - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns);
        e.status = GazeStatus::kTracked;
        e.method = GazeMethod::kInterpolated;
        e.direction = slerp(a.direction, b.direction, f);
        return e;
    }
    // An untracked neighbour: the nearer sample decides (the spec's clamp to the nearest).
    const GazeSample& nearer = (t - a.t_ns) <= (b.t_ns - t) ? a : b;
    e.status = nearer.valid ? GazeStatus::kTracked : GazeStatus::kUntracked;
    e.method = nearer.valid ? GazeMethod::kNearest : GazeMethod::kNone;
    e.direction = nearer.direction;
    return e;
}

GazeEstimate GazeTimeline::beyond_newest(int64_t t, int64_t now) const {
    GazeEstimate e;
    const GazeSample& n = samples_.back();
    e.t_newest_ns = n.t_ns;
    e.t_expressed_ns = std::min(t, n.t_ns + params_.max_prediction_ns);
    if (now - n.t_ns > params_.stale_ns) {
        e.status = GazeStatus::kStale;
        return e;
    }
    if (!n.valid) {
        e.status = GazeStatus::kUntracked;
        return e;
    }
    e.status = GazeStatus::kTracked;
    if (n.saccade) {
        e.method = GazeMethod::kLanding;
        e.direction = landing_at(n, e.t_expressed_ns);
    } else if (n.pursuit) {
        e.method = GazeMethod::kPursuit;
        e.direction = pursuit_at(e.t_expressed_ns);
    } else {
        e.method = GazeMethod::kHeld;
        e.direction = n.direction;
    }
    return e;
}

Vec3 GazeTimeline::landing_at(const GazeSample& s, int64_t t) const {
    const double remaining_deg = angle_deg(s.direction, s.landing);
    const double amplitude = std::max(0.0, s.saccade_amplitude_deg) + remaining_deg;
    const double duration_ns =
        (params_.duration_slope_ms * amplitude + params_.duration_intercept_ms) * 1e6;
    const double done = min_jerk(static_cast<double>(s.t_ns - s.saccade_onset_ns) / duration_ns);
    const double then = min_jerk(static_cast<double>(t - s.saccade_onset_ns) / duration_ns);
    const double f = done >= 1.0 - 1e-9 ? 1.0 : std::clamp((then - done) / (1.0 - done), 0.0, 1.0);
    return slerp(s.direction, s.landing, f);
}

Vec3 GazeTimeline::pursuit_at(int64_t t) const {
    const GazeSample& n = samples_.back();
    // The oldest tracked sample within the window, so the velocity is not one noisy step.
    const GazeSample* from = nullptr;
    for (auto it = samples_.rbegin() + 1; it != samples_.rend(); ++it) {
        if (n.t_ns - it->t_ns > params_.pursuit_window_ns || !it->valid) break;
        from = &*it;
    }
    if (!from || from->t_ns >= n.t_ns) return n.direction;
    const double scale = static_cast<double>(t - n.t_ns) / static_cast<double>(n.t_ns - from->t_ns);
    return continue_rotation(from->direction, n.direction, scale);
}

}  // namespace fovea::openxr
