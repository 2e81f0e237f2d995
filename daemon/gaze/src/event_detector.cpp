#include "fovea/gaze/event_detector.hpp"

#include <algorithm>
#include <cmath>

namespace fovea::gaze {

namespace {

constexpr double kRadToDeg = 57.29577951308232;

int samples_for(double seconds, double rate_hz, int minimum) {
    return std::max(minimum, static_cast<int>(std::lround(seconds * rate_hz)));
}

}  // namespace

EventDetector::EventDetector(const DetectorParams& params, double nominal_rate_hz,
                             DetectorMode mode)
    : p_(params), mode_(mode) {
    rate_ = std::isfinite(nominal_rate_hz) && nominal_rate_hz > 0 ? nominal_rate_hz : 1000.0;
    k_ = samples_for(p_.velocity_half_window_s, rate_, 1);
    w_ = samples_for(p_.smooth_half_window_s, rate_, 2);
    // Online: at least the velocity window, one sample for the local-minimum test and the
    // pursuit window must fit, or labels would be forced before they are known.
    const int needed = k_ + 2 + w_;
    if (mode_ == DetectorMode::kOnline) {
        lookahead_ = std::max(needed, samples_for(p_.lookahead_s, rate_, 1));
    } else {
        lookahead_ = std::max(needed, samples_for(2.0, rate_, 1));  // effectively unbounded
    }
    history_ = std::max(k_, w_) + 2;
    peak_ = p_.initial_peak_dps;
    onset_ = std::max(p_.min_onset_dps, stat_mean_ + p_.onset_sd * std::sqrt(stat_var_));
}

void EventDetector::set_thresholds(const VelocityThresholds& t) {
    peak_ = std::max(p_.min_peak_dps, t.peak_dps);
    onset_ = std::max(p_.min_onset_dps, std::min(t.onset_dps, peak_));
}

void EventDetector::push(const DetectorInput& in) {
    Entry e;
    double t = in.t_s;
    if (!buf_.empty()) {
        const double last = buf_.back().t;
        // Time never runs backwards inside the detector; a bad stamp gets the nominal period.
        if (!std::isfinite(t) || t <= last) t = last + 1.0 / rate_;
    } else if (!std::isfinite(t)) {
        t = 0.0;
    }
    e.t = t;
    e.valid = in.valid && std::isfinite(in.x_deg) && std::isfinite(in.y_deg) &&
              std::fabs(in.x_deg) < 1e4 && std::fabs(in.y_deg) < 1e4;
    if (e.valid) {
        e.x = last_valid_x_ = in.x_deg;
        e.y = last_valid_y_ = in.y_deg;
        loss_start_ = -1;
    } else {
        // Hold the last position: short dropouts then look like no movement.
        e.x = std::isfinite(last_valid_x_) ? last_valid_x_ : 0.0;
        e.y = std::isfinite(last_valid_y_) ? last_valid_y_ : 0.0;
        if (loss_start_ < 0 || loss_start_ < base_) loss_start_ = n_;
    }
    buf_.push_back(e);
    ++n_;
    if (!e.valid && n_ - 1 - loss_start_ + 1 >= 1) {
        const double lost_for = t - at(loss_start_).t + 1.0 / rate_;
        if (lost_for >= p_.min_blink_s) {
            for (int64_t i = loss_start_; i < n_; ++i) {
                Entry& le = at(i);
                if (le.lost) continue;
                le.lost = true;
                if (i < s2_next_ && i >= emit_next_) le.label = Label::kBlink;
            }
        }
    }
    advance(false);
}

void EventDetector::flush() {
    flushing_ = true;
    advance(true);
}

void EventDetector::advance(bool flushing) {
    while (vel_next_ < n_ && (vel_next_ + k_ < n_ || flushing)) compute_velocity(vel_next_++);
    while (s2_next_ < vel_next_ && (s2_next_ + 1 < vel_next_ || flushing)) {
        stage_saccades(s2_next_++);
    }
    const int64_t newest = s2_next_ - 1;
    while (s3_next_ < s2_next_ && (s3_next_ + w_ <= newest || flushing)) {
        stage_smooth(s3_next_++, newest);
    }
    // The look-ahead bound: anything older than it is decided now, with what is known.
    const int64_t due = n_ - 1 - lookahead_;
    while (s3_next_ <= due && s3_next_ < s2_next_) stage_smooth(s3_next_++, newest);
}

bool EventDetector::pop(DetectorOutput& out) {
    if (emit_next_ >= s3_next_) return false;
    if (!flushing_ && emit_next_ > n_ - 1 - lookahead_) return false;
    const Entry& e = at(emit_next_);
    out.index = emit_next_;
    out.saccade = SaccadeInfo{};
    switch (e.label) {
        case Label::kInter:
        case Label::kFixation:
            out.event = Event::kFixation;
            break;
        case Label::kPursuit:
            out.event = Event::kPursuit;
            break;
        case Label::kSaccade:
            out.event = Event::kSaccade;
            break;
        case Label::kPso:
            out.event = Event::kPso;
            break;
        case Label::kBlink:
            out.event = Event::kBlink;
            break;
        default:
            out.event = Event::kUnknown;
            break;
    }
    if ((out.event == Event::kSaccade || out.event == Event::kPso) && e.sacc >= 0) {
        if (const Record* r = record(e.sacc)) out.saccade = r->info;
    }
    ++emit_next_;
    while (base_ < emit_next_ - history_ && !buf_.empty()) {
        buf_.pop_front();
        ++base_;
    }
    return true;
}

void EventDetector::compute_velocity(int64_t c) {
    const int64_t lo = std::max(base_, c - k_);
    const int64_t hi = std::min(n_ - 1, c + k_);
    Entry& e = at(c);
    double st = 0, sx = 0, sy = 0;
    int m = 0;
    for (int64_t i = lo; i <= hi; ++i) {
        const Entry& q = at(i);
        if (q.lost) {
            e.v = kNaN;
            if (velocity_sink_) velocity_sink_->push_back(kNaN);
            return;
        }
        st += q.t - e.t;
        sx += q.x;
        sy += q.y;
        ++m;
    }
    const double tm = st / m, xm = sx / m, ym = sy / m;
    double stt = 0, stx = 0, sty = 0;
    for (int64_t i = lo; i <= hi; ++i) {
        const Entry& q = at(i);
        const double dt = q.t - e.t - tm;
        stt += dt * dt;
        stx += dt * (q.x - xm);
        sty += dt * (q.y - ym);
    }
    e.v = stt > 0 ? std::hypot(stx / stt, sty / stt) : 0.0;
    if (velocity_sink_) velocity_sink_->push_back(e.v);
}

EventDetector::Record* EventDetector::record(int64_t id) {
    if (records_.empty() || id < records_.front().id || id > records_.back().id) return nullptr;
    return &records_[static_cast<size_t>(id - records_.front().id)];
}

void EventDetector::update_stats(double v, double dt) {
    stat_weight_ += dt;
    const double a = std::clamp(dt / std::min(stat_weight_, p_.threshold_horizon_s), 0.0, 1.0);
    const double d = v - stat_mean_;
    stat_mean_ += a * d;
    stat_var_ = (1.0 - a) * (stat_var_ + a * d * d);
    const double sd = std::sqrt(stat_var_);
    peak_ = std::max(p_.min_peak_dps, stat_mean_ + p_.peak_sd * sd);
    onset_ = std::max(p_.min_onset_dps, std::min(peak_, stat_mean_ + p_.onset_sd * sd));
}

void EventDetector::mark_blink_back(int64_t c) {
    const double t0 = at(c).t;
    for (int64_t i = c - 1; i >= emit_next_ && i >= base_; --i) {
        Entry& q = at(i);
        const bool in_margin = t0 - q.t <= p_.blink_pre_s;
        const bool artefact = q.label == Label::kSaccade || q.label == Label::kPso;
        if (!in_margin && !artefact) break;
        q.label = Label::kBlink;
    }
}

void EventDetector::start_saccade(int64_t c) {
    int64_t j = c;
    const int64_t lo = std::max(emit_next_, base_);
    auto usable = [&](int64_t i) {
        const Entry& q = at(i);
        return i >= lo && std::isfinite(q.v) && (is_inter(q.label));
    };
    while (usable(j - 1) && at(j - 1).v > onset_) --j;
    // Onset is the local velocity minimum just below the onset threshold.
    for (int extra = 0; extra < k_ && usable(j - 1) && at(j - 1).v < at(j).v; ++extra) --j;
    const int64_t id = next_id_++;
    records_.push_back({id, j, c, SaccadeInfo{}});
    while (records_.size() > 256) records_.pop_front();
    Record& r = records_.back();
    r.info.onset_ns = std::llround(at(j).t * 1e9);
    r.info.peak_velocity_dps = at(c).v;
    const bool near_blink = at(j).t - last_lost_t_ < 2.0 * p_.blink_post_s;
    for (int64_t i = j; i <= c; ++i) {
        at(i).label = near_blink ? Label::kBlink : Label::kSaccade;
        at(i).sacc = id;
    }
    sacc_blink_ = near_blink;
    state_ = State::kSaccade;
    sacc_onset_ = j;
    sacc_id_ = id;
    sacc_peak_ = at(c).v;
}

void EventDetector::finish_record(int64_t id, int64_t last) {
    Record* r = record(id);
    if (!r) return;
    const Entry& a = at(std::max(r->onset, base_));
    const Entry& b = at(last);
    r->offset = last;
    const double dx = b.x - a.x, dy = b.y - a.y;
    r->info.amplitude_deg = std::hypot(dx, dy);
    r->info.direction_deg = std::atan2(dy, dx) * kRadToDeg;
    r->info.peak_velocity_dps = sacc_peak_;
}

void EventDetector::end_saccade(int64_t last) {
    const double duration = at(last).t - at(std::max(sacc_onset_, base_)).t;
    if (sacc_blink_) {
        state_ = State::kIdle;
        return;
    }
    if (duration < p_.min_saccade_s) {
        // Too short for a saccade: a noise spike, give it back to the intersaccadic stage.
        for (int64_t i = std::max(sacc_onset_, emit_next_); i <= last; ++i) {
            if (at(i).label == Label::kSaccade) at(i).label = Label::kInter;
        }
        state_ = State::kIdle;
        return;
    }
    finish_record(sacc_id_, last);
    state_ = State::kPostSaccade;
    post_start_ = last + 1;
    post_t0_ = at(last).t;
}

void EventDetector::stage_saccades(int64_t c) {
    Entry& e = at(c);
    if (e.lost || !std::isfinite(e.v)) {
        if (state_ != State::kIdle && sacc_onset_ >= 0) {
            for (int64_t i = std::max(sacc_onset_, emit_next_); i < c; ++i) {
                at(i).label = Label::kBlink;
            }
        }
        state_ = State::kIdle;
        e.label = Label::kBlink;
        if (e.lost) {
            if (last_lost_t_ < e.t - 2.0 / rate_) mark_blink_back(c);
            last_lost_t_ = e.t;
        }
        return;
    }
    const double v = e.v;
    const double v_next = c + 1 < vel_next_ ? at(c + 1).v : v;
    if (e.t - last_lost_t_ < p_.blink_post_s) {
        e.label = Label::kBlink;
        state_ = State::kIdle;
        return;
    }
    const bool local_min = !(v_next < v);  // NaN next counts as a minimum
    switch (state_) {
        case State::kSaccade: {
            e.label = sacc_blink_ ? Label::kBlink : Label::kSaccade;
            e.sacc = sacc_id_;
            sacc_peak_ = std::max(sacc_peak_, v);
            const double duration = e.t - at(std::max(sacc_onset_, base_)).t;
            if ((v < onset_ && local_min) || duration > p_.max_saccade_s) end_saccade(c);
            return;
        }
        case State::kPso: {
            e.label = Label::kPso;
            e.sacc = sacc_id_;
            if ((v < onset_ && local_min) || e.t - post_t0_ > 2.0 * p_.pso_window_s) {
                state_ = State::kIdle;
            }
            return;
        }
        case State::kPostSaccade: {
            if (e.t - post_t0_ <= p_.pso_window_s) {
                if (v > onset_) {
                    for (int64_t i = std::max(post_start_, emit_next_); i <= c; ++i) {
                        at(i).label = Label::kPso;
                        at(i).sacc = sacc_id_;
                    }
                    state_ = State::kPso;
                } else {
                    e.label = Label::kInter;
                }
                return;
            }
            state_ = State::kIdle;
            break;
        }
        case State::kIdle:
            break;
    }
    if (v > peak_) {
        start_saccade(c);
        return;
    }
    e.label = Label::kInter;
    if (mode_ == DetectorMode::kOnline && c > base_) {
        update_stats(v, std::min(e.t - at(c - 1).t, 0.1));
    }
}

void EventDetector::stage_smooth(int64_t d, int64_t newest) {
    Entry& e = at(d);
    if (e.label != Label::kInter) return;
    int64_t lo = d, hi = d;
    while (lo - 1 >= base_ && d - (lo - 1) <= w_ && is_inter(at(lo - 1).label)) --lo;
    while (hi + 1 <= newest && (hi + 1) - d <= w_ && is_inter(at(hi + 1).label)) ++hi;
    double speed = 0.0;
    const int64_t m = hi - lo + 1;
    if (m >= 3) {
        double st = 0, sx = 0, sy = 0;
        for (int64_t i = lo; i <= hi; ++i) {
            st += at(i).t - e.t;
            sx += at(i).x;
            sy += at(i).y;
        }
        const double tm = st / m, xm = sx / m, ym = sy / m;
        double stt = 0, stx = 0, sty = 0;
        for (int64_t i = lo; i <= hi; ++i) {
            const double dt = at(i).t - e.t - tm;
            stt += dt * dt;
            stx += dt * (at(i).x - xm);
            sty += dt * (at(i).y - ym);
        }
        if (stt > 0) speed = std::hypot(stx / stt, sty / stt);
    }
    const bool was_pursuit = d - 1 >= base_ && at(d - 1).label == Label::kPursuit;
    const double threshold = was_pursuit ? 0.7 * p_.pursuit_dps : p_.pursuit_dps;
    e.label = speed > threshold ? Label::kPursuit : Label::kFixation;
}

std::vector<double> EventDetector::velocities(std::span<const DetectorInput> samples,
                                              const DetectorParams& params,
                                              double nominal_rate_hz) {
    std::vector<double> v;
    v.reserve(samples.size());
    EventDetector d(params, nominal_rate_hz, DetectorMode::kOffline);
    d.peak_ = d.onset_ = 1e300;  // velocities only: never enter a saccade
    d.velocity_sink_ = &v;
    DetectorOutput out;
    for (const auto& s : samples) {
        d.push(s);
        while (d.pop(out)) {
        }
    }
    d.flush();
    return v;
}

VelocityThresholds EventDetector::estimate_thresholds(std::span<const DetectorInput> samples,
                                                      const DetectorParams& params,
                                                      double nominal_rate_hz) {
    const std::vector<double> v = velocities(samples, params, nominal_rate_hz);
    double peak = params.initial_peak_dps;
    double mean = 0, sd = 0;
    for (int iter = 0; iter < 100; ++iter) {
        double s = 0, ss = 0;
        size_t m = 0;
        for (double x : v) {
            if (std::isfinite(x) && x < peak) {
                s += x;
                ss += x * x;
                ++m;
            }
        }
        if (m < 2) break;
        mean = s / static_cast<double>(m);
        sd = std::sqrt(std::max(0.0, ss / static_cast<double>(m) - mean * mean));
        const double next = mean + params.peak_sd * sd;
        const bool done = std::fabs(next - peak) < 1.0;
        peak = next;
        if (done) break;
    }
    VelocityThresholds t;
    t.peak_dps = std::max(params.min_peak_dps, peak);
    t.onset_dps = std::max(params.min_onset_dps, std::min(t.peak_dps, mean + params.onset_sd * sd));
    return t;
}

std::vector<DetectorOutput> EventDetector::detect_offline(std::span<const DetectorInput> samples,
                                                          const DetectorParams& params,
                                                          double nominal_rate_hz) {
    EventDetector d(params, nominal_rate_hz, DetectorMode::kOffline);
    d.set_thresholds(estimate_thresholds(samples, params, nominal_rate_hz));
    std::vector<DetectorOutput> out;
    out.reserve(samples.size());
    DetectorOutput o;
    for (const auto& s : samples) {
        d.push(s);
        while (d.pop(o)) out.push_back(o);
    }
    d.flush();
    while (d.pop(o)) out.push_back(o);
    return out;
}

}  // namespace fovea::gaze
