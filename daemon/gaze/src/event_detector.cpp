#include "fovea/gaze/event_detector.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace fovea::gaze {

namespace {

// The pursuit window's least-squares sums t, x, y, t^2, t x, t y, one sample added.
void add_moments(std::array<double, 6>& sum, double rt, double rx, double ry) {
    sum[0] += rt;
    sum[1] += rx;
    sum[2] += ry;
    sum[3] += rt * rt;
    sum[4] += rt * rx;
    sum[5] += rt * ry;
}

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
    kf_ = std::min(k_, samples_for(p_.offset_half_window_s, rate_, 1));
    // The window's excess over its design, where it cannot shrink any more (one sample either
    // side; above, rounding k leaves at most half a sample either way). It is below one sample
    // there and counts from a third of one: 167 Hz and below. There a saccade's neighbours carry
    // its jump, so its bounds move in by one sample (trim_window_excess) and their velocities stay
    // out of the threshold statistics (stats_exclude_flanks).
    wide_window_ = k_ == 1 && 1.0 - p_.velocity_half_window_s * rate_ >= 1.0 / 3.0;
    bound_trim_ = p_.trim_window_excess != 0 && wide_window_ ? 1 : 0;
    w_ = samples_for(p_.smooth_half_window_s, rate_, 2);
    // Online: at least the velocity window and one sample for the local-minimum test; the
    // pursuit window is then truncated at the newest sample (decided with what is known).
    const int needed = k_ + 2;
    if (mode_ == DetectorMode::kOnline) {
        lookahead_ = std::max(needed, samples_for(p_.lookahead_s, rate_, 1));
    } else {
        lookahead_ = std::max(needed + w_, samples_for(2.0, rate_, 1));  // effectively unbounded
    }
    km_ = samples_for(p_.microsaccade_half_window_s, rate_, 1);
    ms_interval_ = static_cast<int>(std::ceil(p_.microsaccade_min_interval_s * rate_ - 1e-9));
    history_ = std::max({k_, w_, km_ + ms_interval_}) + 2;
    // Online stage: a run is judged ms_interval_ after it (its lag behind stage 3) and may join
    // the previous microsaccade up to ms_interval_ before it (held back in pop()).
    ms_hold_ = 2 * ms_interval_ + 1;
    ms_refresh_ = samples_for(0.010, rate_, 1);
    ms_warmup_ = std::max(0.0, p_.microsaccade_warmup_values) * 2.0 * km_;
    stats_delay_ = samples_for(p_.blink_pre_s, rate_, 1) + 2;
    // The noise lags bracket the reference step; below one sample the first two extrapolate.
    noise_ref_lag_ = p_.noise_reference_s > 0.0 ? std::max(1e-3, p_.noise_reference_s * rate_)
                                                : 1.0;  // 0: per sample, whatever the rate
    noise_lag_[0] = std::max(1, static_cast<int>(std::floor(noise_ref_lag_ + 1e-9)));
    noise_lag_[1] = noise_lag_[0] + 1;
    if (mode_ == DetectorMode::kOnline) {
        noise_lag_mean_ = {p_.noise_prior_deg, p_.noise_prior_deg};
        noise_weight_ = std::max(0.0, p_.noise_prior_samples);
    }
    // Offline until set_thresholds, online until the first measurement: the prior.
    set_noise(p_.noise_prior_deg, p_.noise_prior_deg * p_.noise_prior_ratio);
    peak_ = p_.initial_peak_dps;
    onset_ = std::max(p_.min_onset_dps(), stat_mean_ + p_.onset_sd * std::sqrt(stat_var_));
}

void EventDetector::set_thresholds(const VelocityThresholds& t) {
    if (std::isfinite(t.noise_deg) && t.noise_deg > 0) {
        const bool known2 = std::isfinite(t.noise2_deg) && t.noise2_deg > 0;
        set_noise(t.noise_deg, known2 ? t.noise2_deg : t.noise_deg * p_.noise_prior_ratio);
    }
    const bool sigmas = std::isfinite(t.microsaccade_sigma_x_dps) &&
                        std::isfinite(t.microsaccade_sigma_y_dps) &&
                        t.microsaccade_sigma_x_dps > 0 && t.microsaccade_sigma_y_dps > 0;
    ms_sigma_x_ = sigmas ? t.microsaccade_sigma_x_dps : 0.0;
    ms_sigma_y_ = sigmas ? t.microsaccade_sigma_y_dps : 0.0;
    peak_ = std::max(p_.min_peak_dps, t.peak_dps);
    onset_ = std::max(p_.min_onset_dps(), std::min(t.onset_dps, peak_));
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
    // Running sums for O(1) window regressions, re-anchored every kBlock samples so they stay
    // small (precision) however long the run.
    if (n_ % kBlock == 0) {
        anchor_t_ = e.t;
        anchor_x_ = e.x;
        anchor_y_ = e.y;
        run_ = {};
    }
    {
        add_moments(run_, e.t - anchor_t_, e.x - anchor_x_, e.y - anchor_y_);
        e.cum = run_;
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
                if (i < s2_next_ && i >= emit_next_) {
                    le.label = Label::kBlink;
                    invalidate(i);
                }
            }
        }
    }
    advance(false);
}

void EventDetector::flush() {
    flushing_ = true;
    advance(true);
}

void EventDetector::settle() {
    advance(true);
    settled_ = n_;
}

void EventDetector::advance(bool flushing) {
    while (vel_next_ < n_ && (vel_next_ + k_ < n_ || flushing)) compute_velocity(vel_next_++);
    while (s2_next_ < vel_next_ && (s2_next_ + 1 < vel_next_ || flushing)) {
        stage_saccades(s2_next_++);
    }
    if (mode_ == DetectorMode::kOnline) {
        // Thresholds learn from stage-2 labels once they are past the reach of a blink's
        // backward relabelling, not at emission: otherwise a longer look-ahead would delay
        // what the thresholds know and the first seconds would run on the prior.
        while (stats_next_ <= s2_next_ - 1 - stats_delay_) feed_stats(stats_next_++);
    }
    const int64_t newest = s2_next_ - 1;
    while (s3_next_ < s2_next_ && (s3_next_ + w_ <= newest || flushing)) {
        stage_smooth(s3_next_++, newest);
    }
    // The look-ahead bound: anything older than it is decided now, with what is known.
    const int64_t due = n_ - 1 - lookahead_;
    while (s3_next_ <= due && s3_next_ < s2_next_) stage_smooth(s3_next_++, newest);
    // Microsaccades need final fixation labels (a run must not cross into pursuit).
    // It lags stage 3 by the minimum intersaccadic interval, whose labels it checks after a run.
    if (ms_online()) {
        // The SD histograms take every sample as soon as its E&K window has arrived: the
        // estimate a label uses is then from the past plus the bounded look-ahead.
        while (ms_feed_next_ + km_ < n_) feed_microsaccade_stats(ms_feed_next_++);
    }
    const int64_t lag = ms_staged() ? ms_interval_ : 0;
    while (s4_next_ < s3_next_ && (s4_next_ + lag < s3_next_ || flushing)) {
        stage_microsaccades(s4_next_++);
    }
    if (flushing && ms_start_ >= 0) finish_microsaccade(s4_next_ - 1);
    ms_skip_ = ms_skip_ && !flushing;
}

Event EventDetector::flank_event(int64_t& sacc) const {
    // A sample trimmed off a saccade's bound is at rest: it belongs to the event on its other
    // side, the one before the saccade (onset) or after it (offset, when already labelled), and
    // to that event's saccade if it is a PSO.
    const int64_t next = emit_next_ + 1;
    const Label after = next < s4_next_ ? at(next).label : Label::kPending;
    if (after == Label::kSaccade && at(next).sacc == sacc) {  // the onset's side
        const bool pso = last_emitted_ == Event::kPso;
        sacc = pso ? last_emitted_sacc_ : -1;
        return pso || last_emitted_ == Event::kPursuit ? last_emitted_ : Event::kFixation;
    }
    if (after == Label::kPso) return Event::kPso;  // this saccade's own PSO
    sacc = -1;
    return after == Label::kPursuit ? Event::kPursuit : Event::kFixation;
}

bool EventDetector::pop(DetectorOutput& out) {
    if (emit_next_ >= s4_next_) return false;
    // Online, a sample this old leaves whatever the microsaccade stage still holds open: the
    // hold is bounded by lookahead_samples() (a run it cuts is dropped, finish_microsaccade).
    const bool due = ms_online() && emit_next_ <= n_ - 1 - lookahead_samples();
    // Microsaccades: a run may still join the previous one across the interval.
    if (ms_staged() && !due && !flushing_ && emit_next_ >= settled_ &&
        emit_next_ + ms_interval_ + 1 >= s4_next_) {
        return false;
    }
    // A microsaccade run is open.
    if (ms_start_ >= 0 && !due && emit_next_ >= ms_start_) return false;
    if (!flushing_ && emit_next_ >= settled_ && emit_next_ > n_ - 1 - lookahead_) return false;
    const Entry& e = at(emit_next_);
    out.index = emit_next_;
    out.saccade = SaccadeInfo{};
    out.saccade_id = -1;
    int64_t sacc = e.sacc;
    switch (e.label) {
        case Label::kInter:
        case Label::kFixation: out.event = Event::kFixation; break;
        case Label::kPursuit: out.event = Event::kPursuit; break;
        case Label::kSaccade: out.event = e.flank ? flank_event(sacc) : Event::kSaccade; break;
        case Label::kPso: out.event = Event::kPso; break;
        case Label::kBlink: out.event = Event::kBlink; break;
        default:  // kUndefined (tracking lost on and off) and the rest: no event
            out.event = Event::kUnknown;
            break;
    }
    // Offline threshold estimation sees final labels only, so blink edges never inflate it (nor
    // trimmed saccade samples: their speed is the saccade's).
    const bool inter = is_inter(e.label);
    if (velocity_sink_) velocity_sink_->push_back(inter ? e.v : kNaN);
    if (ms_sink_ && std::isfinite(e.mvx) && std::isfinite(e.mvy)) {
        ms_sink_->push_back({e.mvx, e.mvy});
    }
    if ((out.event == Event::kSaccade || out.event == Event::kPso) && sacc >= 0) {
        if (const Record* r = record(sacc)) out.saccade = r->info;
        out.saccade_id = sacc;
    }
    last_emitted_ = out.event;
    last_emitted_sacc_ = out.saccade_id;
    ++emit_next_;
    while (base_ < emit_next_ - history_ && !buf_.empty()) {
        buf_.pop_front();
        ++base_;
    }
    return true;
}

namespace {

// Least-squares slope (a Savitzky-Golay first derivative) of x and y over [lo, hi] around c:
// the velocity vector, deg/s.
template <typename Entries>
std::array<double, 2> window_slope(const Entries& at, int64_t lo, int64_t hi, double t0) {
    double st = 0, sx = 0, sy = 0;
    int m = 0;
    for (int64_t i = lo; i <= hi; ++i) {
        const auto& q = at(i);
        st += q.t - t0;
        sx += q.x;
        sy += q.y;
        ++m;
    }
    const double tm = st / m, xm = sx / m, ym = sy / m;
    double stt = 0, stx = 0, sty = 0;
    for (int64_t i = lo; i <= hi; ++i) {
        const auto& q = at(i);
        const double dt = q.t - t0 - tm;
        stt += dt * dt;
        stx += dt * (q.x - xm);
        sty += dt * (q.y - ym);
    }
    if (!(stt > 0)) return {0.0, 0.0};
    return {stx / stt, sty / stt};
}

}  // namespace

void EventDetector::compute_velocity(int64_t c) {
    const int64_t lo = std::max(base_, c - k_);
    const int64_t hi = std::min(n_ - 1, c + k_);
    Entry& e = at(c);
    for (int64_t i = lo; i <= hi; ++i) {
        if (at(i).lost) {
            e.v = e.vf = kNaN;
            e.vx = e.vy = e.vfx = e.vfy = kNaN;
            return;
        }
    }
    auto get = [this](int64_t i) -> const Entry& { return at(i); };
    const auto wide = window_slope(get, lo, hi, e.t);
    const auto sharp =
        kf_ == k_ ? wide
                  : window_slope(get, std::max(base_, c - kf_), std::min(n_ - 1, c + kf_), e.t);
    e.vx = wide[0];
    e.vy = wide[1];
    e.v = std::hypot(e.vx, e.vy);
    e.vfx = sharp[0];
    e.vfy = sharp[1];
    e.vf = std::hypot(e.vfx, e.vfy);
}

EventDetector::Record* EventDetector::record(int64_t id) {
    if (records_.empty() || id < records_.front().id || id > records_.back().id) return nullptr;
    return &records_[static_cast<size_t>(id - records_.front().id)];
}

void EventDetector::feed_stats(int64_t i) {
    if (i <= base_ || i >= n_) return;
    const Entry& e = at(i);
    const double bound = p_.stats_bound_dps > 0 ? p_.stats_bound_dps : peak_;
    if (!is_inter(e.label) || !std::isfinite(e.v) || !(e.v < bound)) return;
    if (p_.stats_exclude_flanks != 0 && wide_window_) {
        for (int64_t j = std::max(base_, i - k_); j <= std::min(n_ - 1, i + k_); ++j) {
            if (!is_inter(at(j).label) || !std::isfinite(at(j).v)) return;  // as offline
        }
    }
    update_stats(e.v, std::min(e.t - at(i - 1).t, 0.1));
}

void EventDetector::update_stats(double v, double dt) {
    stat_weight_ += dt;
    const double a = std::clamp(dt / std::min(stat_weight_, p_.threshold_horizon_s), 0.0, 1.0);
    const double d = v - stat_mean_;
    stat_mean_ += a * d;
    stat_var_ = (1.0 - a) * (stat_var_ + a * d * d);
    const double sd = std::sqrt(stat_var_);
    peak_ = std::max(p_.min_peak_dps, stat_mean_ + p_.peak_sd * sd);
    onset_ = std::max(p_.min_onset_dps(), std::min(peak_, stat_mean_ + p_.onset_sd * sd));
}

void EventDetector::mark_blink_back(int64_t c) {
    const double t_loss = at(c).t;
    // Before the lid's margin, a closing lid may make the tracker lose the pupil on and off:
    // samples among such dropouts (each within the margin of the next) are undefined, neither
    // blink nor the saccades their jumps would look like.
    double t_dropout = t_loss;
    bool undefined = false;
    for (int64_t i = c - 1; i >= emit_next_ && i >= base_; --i) {
        Entry& q = at(i);
        const bool in_margin = t_loss - q.t <= p_.blink_pre_s;
        const bool artefact = q.label == Label::kSaccade || q.label == Label::kPso;
        if (!in_margin && (q.lost || q.label == Label::kBlink)) break;  // an earlier blink
        const bool among_dropouts = t_dropout - q.t <= p_.blink_pre_s;
        if (!q.valid && among_dropouts) t_dropout = q.t;
        if (in_margin || (artefact && !undefined)) {
            q.label = Label::kBlink;
        } else if (among_dropouts) {
            q.label = Label::kUndefined;
            undefined = true;
        } else {
            break;
        }
        invalidate(i);
    }
}

void EventDetector::start_saccade(int64_t c, bool after_pso) {
    int64_t j = c;
    const int64_t lo = std::max(emit_next_, base_);
    // A saccade rising out of the previous one's PSO takes back its own rising flank.
    auto usable = [&](int64_t i) {
        if (i < lo) return false;  // before the buffer: at(i) would read outside it
        const Entry& q = at(i);
        return std::isfinite(q.v) && (is_inter(q.label) || (after_pso && q.label == Label::kPso));
    };
    while (usable(j - 1) && at(j - 1).v > onset_) --j;
    // Onset: the first sample above the onset threshold. (N&H walk on to the velocity minimum;
    // the derivative window already spreads the rise over k samples, so we stop here.)
    for (int extra = 0; extra < p_.onset_extra_samples && usable(j - 1) && at(j - 1).v < at(j).v;
         ++extra) {
        --j;
    }
    // A window wider than designed starts the rise early (trim_window_excess): the samples
    // before `moving` are emitted as what came before, and the onset is reported at it.
    const int64_t moving = std::min(c, j + bound_trim_);
    for (int64_t i = j; i < moving; ++i) at(i).flank = true;
    sacc_moving_ = moving;
    const int64_t id = next_id_++;
    records_.push_back({id, j, c, SaccadeInfo{}});
    while (records_.size() > 256) records_.pop_front();
    Record& r = records_.back();
    r.info.onset_ns = std::llround(at(moving).t * 1e9);
    r.info.peak_velocity_dps = at(c).v;
    const bool near_blink = at(j).t - last_lost_t_ < 2.0 * p_.blink_post_s;
    for (int64_t i = j; i <= c; ++i) {
        at(i).label = near_blink ? Label::kBlink : Label::kSaccade;
        invalidate(i);
        at(i).sacc = id;
    }
    sacc_blink_ = near_blink;
    sacc_local_noise_ = local_noise_before(j);
    state_ = State::kSaccade;
    sacc_onset_ = j;
    sacc_id_ = id;
    sacc_peak_ = at(c).v;
    set_saccade_direction(at(c));
}

void EventDetector::set_saccade_direction(const Entry& e) {
    const double norm = std::hypot(e.vx, e.vy);
    if (norm > 0) {
        sacc_dir_x_ = e.vx / norm;
        sacc_dir_y_ = e.vy / norm;
    }
}

EventDetector::LocalMotion EventDetector::motion_before(int64_t onset, double window_s) const {
    // The intersaccadic samples in the window before `onset`, up to the first that is not.
    LocalMotion lm;
    double s = 0, ss = 0;
    const double t0 = at(onset).t;
    for (int64_t i = onset - 1; i >= base_ && t0 - at(i).t <= window_s; --i) {
        const Entry& q = at(i);
        if (!is_inter(q.label) || !std::isfinite(q.v)) break;
        s += q.v;
        ss += q.v * q.v;
        lm.vx += q.vx;
        lm.vy += q.vy;
        ++lm.samples;
    }
    if (lm.samples == 0) return lm;
    const double m = lm.samples;
    lm.speed = s / m;
    lm.speed_sd = std::sqrt(std::max(0.0, ss / m - lm.speed * lm.speed));
    lm.vx /= m;
    lm.vy /= m;
    return lm;
}

double EventDetector::local_noise_before(int64_t onset) const {
    const LocalMotion lm = motion_before(onset, p_.local_noise_window_s);
    return lm.samples < 3 ? 0.0 : lm.speed + p_.local_noise_sd * lm.speed_sd;
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
    // ... and ends the fall late; the first sample after the onset's trim stays a saccade's.
    for (int64_t i = last; i > std::max({sacc_moving_, base_, last - bound_trim_}); --i) {
        at(i).flank = true;
    }
    finish_record(sacc_id_, last);
    state_ = State::kPostSaccade;
    post_start_ = last + 1;
    post_t0_ = at(last).t;
}

void EventDetector::update_noise(int64_t c) {
    // Position noise: second difference, blind to steady pursuit, at both noise lags. Sampled as
    // soon as a sample is intersaccadic so short recordings warm up quickly.
    std::array<double, 2> d2{};
    for (int l = 0; l < 2; ++l) {
        const int k = noise_lag_[l];
        if (c - k < base_ || c + k >= n_) return;
        const Entry& a = at(c - k);
        const Entry& e = at(c);
        const Entry& b = at(c + k);
        if (!a.valid || !b.valid || !e.valid) return;
        d2[l] = std::hypot(b.x - 2 * e.x + a.x, b.y - 2 * e.y + a.y);
    }
    if (noise_sink_) noise_sink_->push_back(d2);
    if (mode_ == DetectorMode::kOnline && d2[0] < 1.0 && d2[1] < 1.0) {
        noise_weight_ += 1.0;
        const double gain = 1.0 / std::min(noise_weight_, 4096.0);
        for (int l = 0; l < 2; ++l) noise_lag_mean_[l] += (d2[l] - noise_lag_mean_[l]) * gain;
        set_noise(noise_at_reference(noise_lag_mean_[0], noise_lag_mean_[1]),
                  noise_at_reference(noise_lag_mean_[0], noise_lag_mean_[1], 2.0));
    }
}

double EventDetector::noise_at_reference(double m1, double m2, double steps) const {
    if (!(m1 > 0.0) || !(m2 > 0.0)) return m1;
    const double k1 = noise_lag_[0], k2 = noise_lag_[1];
    const double ref = steps * noise_ref_lag_;
    if (ref == k1) return m1;
    if (ref == k2) return m2;
    // |d2| ~ lag^(alpha / 2), alpha from the two lags (0: white noise, 2: smooth motion).
    const double alpha = std::clamp(2.0 * std::log(m2 / m1) / std::log(k2 / k1), 0.0, 2.0);
    return m1 * std::pow(ref / k1, 0.5 * alpha);
}

void EventDetector::set_noise(double at_step, double at_two_steps) {
    // Per axis the second difference of Gaussian noise is Gaussian, so its 2-D length is
    // Rayleigh: variance = mean^2 x 2 / pi. White noise of SD s gives 6 s^2 at every lag; a
    // random walk of q deg^2/s gives 2 q h at lag h.
    constexpr double kRayleigh = 2.0 / 3.14159265358979323846;
    const double v1 = at_step * at_step * kRayleigh, v2 = at_two_steps * at_two_steps * kRayleigh;
    const double step_s = noise_ref_lag_ / rate_;
    const double q = std::isfinite(v2 - v1) ? std::max(0.0, v2 - v1) / (2.0 * step_s) : 0.0;
    const double white = std::isfinite(v1) ? std::max(0.0, 2.0 * v1 - v2) / 6.0 : 0.0;
    // Variance of a window's least-squares slope: 12 s^2 / (n span^2) with n = rate x span, and
    // 6 q / (5 span) for Brownian motion.
    white_slope_var_ = 12.0 * white / rate_;
    drift_slope_var_ = 6.0 * q / 5.0;
}

void EventDetector::stage_saccades(int64_t c) {
    Entry& e = at(c);
    if (e.lost || !std::isfinite(e.v)) {
        if (state_ != State::kIdle && sacc_onset_ >= 0) {
            for (int64_t i = std::max(sacc_onset_, emit_next_); i < c; ++i) {
                at(i).label = Label::kBlink;
                invalidate(i);
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
    const double pso_thr = p_.pso_onset_factor * onset_;
    // PSO wobbles last 5-20 ms: they are judged on the sharper derivative, which the wide
    // window would flatten below threshold.
    const double pv = e.vf;
    const bool pso_min = !((c + 1 < vel_next_ ? at(c + 1).vf : e.vf) < e.vf);
    // Faster than the saccade it would follow: a new saccade, not its wobble (PSO velocities
    // stay below the parent saccade's peak).
    const bool after_saccade = state_ == State::kPso || state_ == State::kPostSaccade;
    if (after_saccade && v > peak_ && v > sacc_peak_) {
        start_saccade(c, true);
        return;
    }
    switch (state_) {
        case State::kSaccade: {
            e.label = sacc_blink_ ? Label::kBlink : Label::kSaccade;
            e.sacc = sacc_id_;
            if (v > sacc_peak_) {
                sacc_peak_ = v;
                set_saccade_direction(e);
            }
            const double duration = e.t - at(std::max(sacc_onset_, base_)).t;
            // The saccade ends at the first velocity minimum once the eye has decelerated: what
            // follows a minimum that is still fast is the post-saccadic wobble, not the saccade.
            const double offset =
                std::max({onset_, p_.offset_peak_fraction * sacc_peak_, sacc_local_noise_});
            const double vf_next = c + 1 < vel_next_ ? at(c + 1).vf : e.vf;
            const bool sharp_min = !(vf_next < e.vf);
            const bool smooth_end = v < offset && local_min;
            // Either derivative may find the minimum; both must be below the threshold.
            // (A lid artefact next to a loss keeps the smooth rule: coders mark its full extent.)
            const bool sharp_end = !sacc_blink_ && e.vf < offset && sharp_min && v < offset;
            // Or the velocity reverses sign along the saccade's direction (taken at the peak
            // velocity): an overshoot turning back is the PSO (Larsson et al. 2013), although
            // the speed may still be high and never reach a minimum below the threshold. A mere
            // slowing keeps the minimum rule (the sharp component alone reverses on one
            // jittered sample, so the wide one must also have stopped advancing), and so does
            // a saccade shorter than the minimum duration (a small one's onset is found late;
            // the speed rules decide whether it was a saccade at all).
            const double forward_sharp = e.vfx * sacc_dir_x_ + e.vfy * sacc_dir_y_;
            const double forward_wide = e.vx * sacc_dir_x_ + e.vy * sacc_dir_y_;
            const bool turned_back = !sacc_blink_ && duration >= p_.min_saccade_s &&
                                     forward_sharp < 0.0 && forward_wide < offset;
            if (smooth_end || sharp_end || turned_back || duration > p_.max_saccade_s) {
                end_saccade(c);
            }
            return;
        }
        case State::kPso: {
            e.label = Label::kPso;
            e.sacc = sacc_id_;
            if (e.t - post_t0_ > 2.0 * p_.pso_window_s) {
                state_ = State::kIdle;
            } else if (pv < pso_thr && pso_min) {
                // One wobble is over; another inside the window belongs to the same PSO.
                state_ = State::kPostSaccade;
                post_start_ = c + 1;
            }
            return;
        }
        case State::kPostSaccade: {
            if (e.t - post_t0_ <= p_.pso_window_s) {
                if (pv > pso_thr) {
                    for (int64_t i = std::max(post_start_, emit_next_); i <= c; ++i) {
                        at(i).label = Label::kPso;
                        invalidate(i);
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
        case State::kIdle: break;
    }
    if (v > peak_ && relative_speed(c) > peak_) {
        start_saccade(c);
        return;
    }
    e.label = Label::kInter;
    update_noise(c);
}

double EventDetector::relative_speed(int64_t c) const {
    // The eye's own velocity just before the rise (the samples before the first one above the
    // onset threshold): during pursuit a saccade is a jump on top of that motion, and the
    // pursuit's speed alone must not pass the peak threshold. At fixation it is ~0.
    const Entry& e = at(c);
    if (p_.relative_window_s <= 0) return e.v;
    // The rise is at most a short saccade's length: during pursuit the speed may sit above the
    // onset threshold all along, and the walk must not reach back to the fixation before it.
    const int64_t lo = std::max(emit_next_, base_);
    int64_t j = c;
    while (j - 1 >= lo && is_inter(at(j - 1).label) && std::isfinite(at(j - 1).v) &&
           at(j - 1).v > onset_ && e.t - at(j - 1).t <= p_.min_saccade_s) {
        --j;
    }
    const LocalMotion lm = motion_before(j, p_.relative_window_s);
    if (lm.samples < 3) return e.v;
    return std::hypot(e.vx - lm.vx, e.vy - lm.vy);
}

EventDetector::WindowFit EventDetector::window_fit(int64_t lo, int64_t hi) const {
    if (lo / kBlock != hi / kBlock) return fit_of(direct_sums(lo, hi, false), hi - lo + 1);
    std::array<double, 6> sum = at(hi).cum;
    if (lo % kBlock != 0) {
        const auto& before = at(lo - 1).cum;
        for (size_t k = 0; k < sum.size(); ++k) sum[k] -= before[k];
    }
    return fit_of(sum, hi - lo + 1);
}

EventDetector::WindowFit EventDetector::window_fit_without_jumps(int64_t lo, int64_t hi) const {
    return fit_of(direct_sums(lo, hi, true), hi - lo + 1);
}

EventDetector::WindowFit EventDetector::fit_of(const std::array<double, 6>& sum, int64_t count) {
    const double m = static_cast<double>(count);
    WindowFit f;
    f.stt = sum[3] - sum[0] * sum[0] / m;
    if (!(f.stt > 0)) return {};
    f.stx = sum[4] - sum[0] * sum[1] / m;
    f.sty = sum[5] - sum[0] * sum[2] / m;
    return f;
}

std::array<double, 6> EventDetector::direct_sums(int64_t lo, int64_t hi, bool skip_jumps) const {
    // With skip_jumps: interval i runs from sample i - 1 to i. Its speed in excess of the mean
    // of the intervals either side is a jump the eye made within it; where that passes the peak
    // threshold the eye made a saccade between two samples, which smooth movement does not, and
    // the jump is taken out of every later position of the window.
    auto interval = [this](int64_t i) -> std::array<double, 2> {
        const Entry& p = at(i - 1);
        const Entry& q = at(i);
        const double dt = q.t - p.t;
        if (!(dt > 0)) return {kNaN, kNaN};  // no speed: never a jump
        return {(q.x - p.x) / dt, (q.y - p.y) / dt};
    };
    skip_jumps = skip_jumps && hi - lo >= 3;  // a jump needs an interval either side
    std::array<double, 2> u_prev{}, u_cur{};
    if (skip_jumps) {
        u_prev = interval(lo + 1);
        u_cur = interval(lo + 2);
    }
    std::array<double, 6> sum{};
    const Entry& a = at(lo);
    double ox = 0.0, oy = 0.0;
    for (int64_t i = lo; i <= hi; ++i) {
        const Entry& q = at(i);
        if (skip_jumps && i >= lo + 2 && i + 1 <= hi) {
            const auto u_next = interval(i + 1);
            const double ex = u_cur[0] - 0.5 * (u_prev[0] + u_next[0]);
            const double ey = u_cur[1] - 0.5 * (u_prev[1] + u_next[1]);
            if (std::hypot(ex, ey) > peak_) {
                const double dt = q.t - at(i - 1).t;
                ox += ex * dt;
                oy += ey * dt;
            }
            u_prev = u_cur;
            u_cur = u_next;
        }
        add_moments(sum, q.t - a.t, q.x - a.x - ox, q.y - a.y - oy);
    }
    return sum;
}

double EventDetector::pursuit_threshold(double span, bool was_pursuit) const {
    // A fixation stays within a bounded area (anti-persistent drift), so its apparent speed
    // falls as the window grows while pursuit keeps its speed: the threshold scales as
    // 1/window (pursuit_span_exponent 1), i.e. pursuit_dps x ref (1 deg by default) bounds the
    // fixation's displacement over the window. The floor is what noise and drift alone make a
    // still eye's window move (pursuit_floor_sd).
    const double ref = p_.pursuit_ref_window_s / span;
    const double floor = p_.pursuit_floor_sd * std::sqrt(white_slope_var_ / (span * span * span) +
                                                         drift_slope_var_ / span);
    double threshold = std::max(p_.pursuit_dps * std::pow(ref, p_.pursuit_span_exponent), floor);
    if (was_pursuit) threshold *= p_.pursuit_hysteresis;
    return threshold;
}

bool EventDetector::catch_up_pursuit(int64_t d, int64_t lo, int64_t hi, int64_t newest,
                                     const WindowFit& own, bool was_pursuit) const {
    // The window [lo, hi] failed the bound on its own. Pool it with the intersaccadic piece
    // across the saccade before it and the one after it (within the +-w_ window around d), each
    // only if both move at pursuit speed, the piece moves like the window (direction within
    // pursuit_join_cos, speed within 1 / pursuit_join_ratio) and the saccade between is a
    // catch-up saccade (the same way, at most pursuit_join_max_deg): pursuit carried on across
    // it. A fixation after a saccade has ~zero velocity and is not pooled with pursuit next to
    // it (nor pursuit with it).
    auto is_jump = [](Label l) { return l == Label::kSaccade || l == Label::kPso; };
    // Before: the window reaches its segment's start, a saccade (and its PSO) precedes it.
    // After: the window ends at a saccade, not at its +-w_ reach. Most windows have neither.
    const bool before = lo == seg_start_ && lo - 1 >= base_ && is_jump(at(lo - 1).label);
    const bool after = hi < d + w_ && hi + 1 <= newest && is_jump(at(hi + 1).label);
    if (!before && !after) return false;
    const double ovx = own.vx(), ovy = own.vy();
    const double own_speed = std::hypot(ovx, ovy);
    // Each piece moves at least at the bound's reference speed on its own: pursuit, only
    // too short to show it against the displacement bound.
    const double min_speed = p_.pursuit_dps * p_.pursuit_join_min_speed;
    if (!(own_speed > 0) || own_speed < min_speed) return false;
    auto agrees = [&](double vx, double vy) {
        const double sp = std::hypot(vx, vy);
        if (!(sp > 0)) return false;
        const double cos = (vx * ovx + vy * ovy) / (sp * own_speed);
        return cos > p_.pursuit_join_cos && std::min(sp, own_speed) >= min_speed &&
               std::min(sp, own_speed) >= p_.pursuit_join_ratio * std::max(sp, own_speed);
    };
    auto jump_agrees = [&](const Entry& from, const Entry& to) {
        const double jx = to.x - from.x, jy = to.y - from.y;
        const double jn = std::hypot(jx, jy);
        if (p_.pursuit_join_max_deg > 0 && jn > p_.pursuit_join_max_deg) return false;
        return jn > 0 && (jx * ovx + jy * ovy) / (jn * own_speed) > p_.pursuit_join_cos;
    };
    auto usable = [&](int64_t a, int64_t b) {
        return b - a + 1 >= 3 && at(b).t - at(a).t >= p_.min_pursuit_window_s;
    };
    WindowFit pooled = own;
    double span = at(hi).t - at(lo).t;
    bool joined = false;
    // Pools the piece [a, b] across the saccade from `from` to `to` if it moves like the window.
    auto join = [&](int64_t a, int64_t b, const Entry& from, const Entry& to) {
        const WindowFit f = window_fit(a, b);
        if (!(usable(a, b) && agrees(f.vx(), f.vy()) && jump_agrees(from, to))) return;
        pooled.stt += f.stt;
        pooled.stx += f.stx;
        pooled.sty += f.sty;
        span += at(b).t - at(a).t;
        joined = true;
    };
    if (before) {
        int64_t j = lo - 1;
        while (j >= base_ && j >= d - w_ && is_jump(at(j).label)) --j;
        if (j >= base_ && j >= d - w_ && is_inter(at(j).label)) {
            const int64_t pe = j;
            while (j - 1 >= base_ && j - 1 >= d - w_ && is_inter(at(j - 1).label)) --j;
            join(j, pe, at(pe), at(lo));
        }
    }
    if (after) {
        int64_t j = hi + 1;
        while (j <= newest && j <= d + w_ && is_jump(at(j).label)) ++j;
        if (j <= newest && j <= d + w_ && is_inter(at(j).label)) {
            const int64_t ns = j;
            while (j + 1 <= newest && j + 1 <= d + w_ && is_inter(at(j + 1).label)) ++j;
            join(ns, j, at(hi), at(ns));
        }
    }
    if (!joined || !(span > 0)) return false;
    return std::hypot(pooled.vx(), pooled.vy()) > pursuit_threshold(span, was_pursuit);
}

void EventDetector::stage_smooth(int64_t d, int64_t newest) {
    Entry& e = at(d);
    if (e.label != Label::kInter) return;
    // Segment bounds: labels behind d are final; ahead, the verified run is cached.
    if (d - 1 < base_ || !is_inter(at(d - 1).label)) seg_start_ = d;
    const int64_t lo = std::max({seg_start_, d - w_, base_});
    int64_t hi = std::max(d, std::min(verified_to_, d + w_));
    while (hi + 1 <= newest && hi + 1 <= d + w_ && is_inter(at(hi + 1).label)) ++hi;
    verified_to_ = hi;
    const double span = at(hi).t - at(lo).t;
    const bool was_pursuit = d - 1 >= base_ && at(d - 1).label == Label::kPursuit;
    if (hi - lo + 1 < 3 || span < p_.min_pursuit_window_s) {
        // Too little signal to see a slow drift: continue the previous decision.
        e.label = was_pursuit ? Label::kPursuit : Label::kFixation;
        e.pooled = was_pursuit && at(d - 1).pooled;
        return;
    }
    const WindowFit own = p_.pursuit_skip_jumps != 0 && wide_window_
                              ? window_fit_without_jumps(lo, hi)
                              : window_fit(lo, hi);
    const double speed = std::hypot(own.vx(), own.vy());
    // Hysteresis continues a test's own decision: a sample that is pursuit only by the
    // catch-up pooling does not lower the next sample's bar for its own window (else one pooled
    // sample would carry a fixation's whole remainder into pursuit).
    const bool own_was_pursuit = was_pursuit && !at(d - 1).pooled;
    bool pursuit = speed > pursuit_threshold(span, own_was_pursuit);
    e.pooled = false;
    if (!pursuit && p_.pursuit_catch_up != 0) {
        pursuit = catch_up_pursuit(d, lo, hi, newest, own, was_pursuit);
        e.pooled = pursuit;
    }
    e.label = pursuit ? Label::kPursuit : Label::kFixation;
}

void EventDetector::microsaccade_velocity(int64_t d) {
    // Engbert & Kliegl's moving average: sum_j (x[d+j] - x[d-j]) / sum_j (t[d+j] - t[d-j]) over
    // j = 1..km_; at 500 Hz (km_ = 2) exactly their (x[n+2] + x[n+1] - x[n-1] - x[n-2]) / 6 dt.
    Entry& e = at(d);
    e.mvx = e.mvy = kNaN;
    if (d - km_ < base_ || d + km_ >= n_) return;
    double sx = 0, sy = 0, st = 0;
    for (int j = 1; j <= km_; ++j) {
        const Entry& a = at(d - j);
        const Entry& b = at(d + j);
        if (!a.valid || !b.valid || a.lost || b.lost) return;
        sx += b.x - a.x;
        sy += b.y - a.y;
        st += b.t - a.t;
    }
    if (!e.valid || !(st > 0)) return;
    e.mvx = sx / st;
    e.mvy = sy / st;
}

// Online Engbert & Kliegl SDs. sigma = sqrt(median(v^2) - median(v)^2) per axis needs two
// running medians (median(v^2) = median(|v|)^2). A decaying histogram rather than a
// stochastic-approximation quantile tracker (median += eta sign(v - median)): the histogram's
// median is the exact weighted median of the past up to the bin width (5.9 % on a 40-per-decade
// log grid, interpolated within the bin), with the same exponential memory in seconds as the
// other online statistics at any rate and no step size that would have to suit both the
// tracker's scale (sigma 1-50 deg/s) and its rate (60-2000 Hz). Decay without touching every
// bin: each new value weighs ms_gain_, which grows by exp(dt / horizon); all weights are
// rescaled when it passes 1e30 (every ~69 horizons, ~35 min at 30 s), so nothing overflows or
// loses precision over hours (weights older than ~700 horizons underflow to 0, harmlessly). The
// grid spans 1e-3 to 1e4 deg/s (7 decades, 561 bins per axis); beyond it values land in the end
// bins, which the median hardly ever reaches.
void EventDetector::DecayingHistogram::add(double v, double weight) {
    const double a = std::fabs(v);
    int j = -1;  // -1: the 0 bin
    if (a >= kMin) j = std::min(kSide - 1, static_cast<int>(std::log10(a / kMin) * kPerDecade));
    const int idx = j < 0 ? kSide : (v > 0 ? kSide + 1 + j : kSide - 1 - j);
    w_[static_cast<size_t>(idx)] += weight;
    total_ += weight;
}

void EventDetector::DecayingHistogram::scale(double f) {
    for (double& w : w_) w *= f;
    total_ *= f;
}

double EventDetector::DecayingHistogram::median() const {
    const double half = 0.5 * total_;
    double cum = 0.0;
    for (int idx = 0; idx < 2 * kSide + 1; ++idx) {
        const double w = w_[static_cast<size_t>(idx)];
        if (w <= 0.0 || cum + w < half) {
            cum += w;
            continue;
        }
        const double f = std::clamp((half - cum) / w, 0.0, 1.0);
        if (idx == kSide) return kMin * (2.0 * f - 1.0);
        if (idx > kSide) return kMin * std::pow(10.0, (idx - kSide - 1 + f) / kPerDecade);
        return -kMin * std::pow(10.0, (kSide - idx - f) / kPerDecade);
    }
    return 0.0;
}

double EventDetector::DecayingHistogram::median_abs() const {
    const double half = 0.5 * total_;
    double cum = w_[kSide];
    if (cum >= half && cum > 0.0) return kMin * std::clamp(half / cum, 0.0, 1.0);
    for (int j = 0; j < kSide; ++j) {
        const double w =
            w_[static_cast<size_t>(kSide + 1 + j)] + w_[static_cast<size_t>(kSide - 1 - j)];
        if (w <= 0.0 || cum + w < half) {
            cum += w;
            continue;
        }
        const double f = std::clamp((half - cum) / w, 0.0, 1.0);
        return kMin * std::pow(10.0, (j + f) / kPerDecade);
    }
    return 0.0;
}

void EventDetector::feed_microsaccade_stats(int64_t i) {
    if (i <= base_ || i >= n_) return;
    microsaccade_velocity(i);
    const Entry& e = at(i);
    if (!std::isfinite(e.mvx) || !std::isfinite(e.mvy)) return;
    const double horizon = std::max(p_.threshold_horizon_s, 1e-3);
    ms_gain_ *= std::exp(std::min(e.t - at(i - 1).t, 0.1) / horizon);
    if (ms_gain_ > 1e30) {
        ms_hist_x_.scale(1.0 / ms_gain_);
        ms_hist_y_.scale(1.0 / ms_gain_);
        ms_gain_ = 1.0;
    }
    ms_hist_x_.add(e.mvx, ms_gain_);
    ms_hist_y_.add(e.mvy, ms_gain_);
    if (++ms_fed_ < ms_refresh_) return;
    ms_fed_ = 0;
    // Effective number of values in the memory (the newest weighs ms_gain_).
    if (ms_hist_x_.total() / ms_gain_ < ms_warmup_) return;
    auto sigma = [](const DecayingHistogram& h) {
        const double m = h.median(), a = h.median_abs();
        return std::sqrt(std::max(0.0, a * a - m * m));
    };
    ms_sigma_x_ = sigma(ms_hist_x_);
    ms_sigma_y_ = sigma(ms_hist_y_);
}

void EventDetector::stage_microsaccades(int64_t d) {
    const bool on = microsaccades_on();
    if (!on && !ms_sink_) return;
    microsaccade_velocity(d);
    if (!on) return;
    const Entry& e = at(d);
    const double ex = e.mvx / (p_.microsaccade_lambda * ms_sigma_x_);
    const double ey = e.mvy / (p_.microsaccade_lambda * ms_sigma_y_);
    // Inside fixations only: pursuit carries the eye above any fixational threshold.
    const bool above = e.label == Label::kFixation && ex * ex + ey * ey > 1.0;
    if (!above) {
        if (ms_start_ >= 0) finish_microsaccade(d - 1);
        ms_skip_ = false;
        return;
    }
    if (ms_skip_) return;
    if (ms_start_ < 0) ms_start_ = d;
    // Longer than any saccade: not a microsaccade (and emission must not wait on it).
    if (e.t - at(ms_start_).t > p_.max_saccade_s) {
        ms_start_ = -1;
        ms_skip_ = true;
    }
}

void EventDetector::finish_microsaccade(int64_t last) {
    const int64_t first = ms_start_;
    ms_start_ = -1;
    if (first < 0 || last < first || first - 1 < std::max(base_, emit_next_) || last + 1 >= n_) {
        return;
    }
    // Duration as E&K count it: samples x sampling interval (3 samples at 500 Hz = 6 ms).
    const double duration = at(last).t - at(first).t + 1.0 / rate_;
    if (duration < p_.microsaccade_min_s - 1e-9) return;
    // Inside a fixation, with no other event within the minimum intersaccadic interval on
    // either side. A run that touches a saccade, PSO, blink or pursuit is that event's flank
    // (N&H's onset is the first sample above their onset threshold; the E&K ellipse sits
    // lower) or its overshoot, and is left as it is; a run within the interval after the
    // previous microsaccade is that microsaccade's overshoot and joins it.
    const double interval = p_.microsaccade_min_interval_s + 1e-9;
    int64_t join = -1;  // first sample of the gap to the previous microsaccade
    for (int64_t i = first - 1; i >= base_ && at(first).t - at(i).t <= interval; --i) {
        const Entry& q = at(i);
        if (q.label == Label::kFixation) continue;
        if (i == first - 1 || q.label != Label::kSaccade || q.sacc != ms_last_id_ ||
            i < emit_next_) {
            return;
        }
        join = i + 1;
        break;
    }
    for (int64_t i = last + 1; i < s3_next_ && at(i).t - at(last).t <= interval; ++i) {
        if (at(i).label != Label::kFixation) return;
    }
    double peak = 0.0;
    for (int64_t i = first; i <= last; ++i) {
        if (std::isfinite(at(i).v)) peak = std::max(peak, at(i).v);
    }
    // A microsaccade is a saccade (Zuber, Stark & Cook 1965: one main sequence): its peak
    // speed (on the detector's +-4 ms derivative) must pass the peak floor every saccade
    // passes, min_peak_dps. (The onset floor, 10 deg/s, let through slow 0.1-0.3 deg movements
    // on a very quiet tracker that its coders had not labelled: daemon/eval/README.md.)
    if (!(peak >= p_.min_peak_dps)) return;
    Record* prev = join >= 0 ? record(ms_last_id_) : nullptr;
    const int64_t onset = prev ? prev->onset : first;
    // Displacement from the sample before the movement to the sample after it (the run's
    // edges are already moving).
    const Entry& a = at(std::max(base_, onset - 1));
    const Entry& b = at(last + 1);
    const double amplitude = std::hypot(b.x - a.x, b.y - a.y);
    if (!prev) {
        ms_last_id_ = next_id_++;
        records_.push_back({ms_last_id_, first, last, SaccadeInfo{}});
        while (records_.size() > 256) records_.pop_front();
        prev = &records_.back();
        prev->info.onset_ns = std::llround(at(first).t * 1e9);
    }
    prev->offset = last;
    prev->info.amplitude_deg = amplitude;
    prev->info.direction_deg = std::atan2(b.y - a.y, b.x - a.x) * kRadToDeg;
    prev->info.peak_velocity_dps = std::max(prev->info.peak_velocity_dps, peak);
    for (int64_t i = join >= 0 ? join : first; i <= last; ++i) {
        at(i).label = Label::kSaccade;
        at(i).sacc = ms_last_id_;
    }
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
        while (d.pop(out)) {}
    }
    d.flush();
    while (d.pop(out)) {}
    return v;
}

namespace {

// Mean and SD of the velocities below `bound`; false for fewer than two.
bool moments_below(const std::vector<double>& v, double bound, double& mean, double& sd) {
    double s = 0, ss = 0;
    size_t m = 0;
    for (double x : v) {
        if (std::isfinite(x) && x < bound) {
            s += x;
            ss += x * x;
            ++m;
        }
    }
    if (m < 2) return false;
    mean = s / static_cast<double>(m);
    sd = std::sqrt(std::max(0.0, ss / static_cast<double>(m) - mean * mean));
    return true;
}

// N&H's fixed point: peak = mean + 6 SD of the velocities below peak. With a bound
// (stats_bound_dps), one pass below it instead.
VelocityThresholds nh_iterate(const std::vector<double>& v, const DetectorParams& params,
                              double bound = 0.0) {
    double peak = params.initial_peak_dps;
    double mean = 0, sd = 0;
    if (bound > 0) {
        if (moments_below(v, bound, mean, sd)) peak = mean + params.peak_sd * sd;
    } else {
        for (int iter = 0; iter < 100; ++iter) {
            if (!moments_below(v, peak, mean, sd)) break;
            const double next = mean + params.peak_sd * sd;
            const bool done = std::fabs(next - peak) < 0.1;
            peak = next;
            if (done) break;
        }
    }
    VelocityThresholds t;
    t.peak_dps = std::max(params.min_peak_dps, peak);
    t.onset_dps =
        std::max(params.min_onset_dps(), std::min(t.peak_dps, mean + params.onset_sd * sd));
    return t;
}

}  // namespace

VelocityThresholds EventDetector::estimate_thresholds(std::span<const DetectorInput> samples,
                                                      const DetectorParams& params,
                                                      double nominal_rate_hz) {
    // Start from N&H over every non-blink sample, then re-estimate from the samples the
    // detector leaves as fixation/pursuit: the same statistic online mode tracks, and immune to
    // lid artefacts and saccade flanks that drag a noisy recording's threshold up.
    VelocityThresholds t = nh_iterate(velocities(samples, params, nominal_rate_hz), params);
    // From below: a high start leaves saccades unlabelled and the statistic stuck high.
    t.peak_dps = std::min(t.peak_dps, params.initial_peak_dps);
    t.onset_dps = std::min(t.onset_dps, 0.5 * t.peak_dps);
    // Engbert & Kliegl's velocity at every sample whose window is measured (their SD is taken
    // over the whole trial; the median keeps saccades and blinks' edges from inflating it).
    std::vector<std::array<double, 2>> ms;
    for (int pass = 0; pass < 4; ++pass) {
        std::vector<double> v;
        v.reserve(samples.size());
        EventDetector d(params, nominal_rate_hz, DetectorMode::kOffline);
        d.set_thresholds(t);
        d.velocity_sink_ = &v;
        std::vector<std::array<double, 2>> noise;
        d.noise_sink_ = &noise;
        if (pass == 0) d.ms_sink_ = &ms;  // the velocities do not depend on the labels
        DetectorOutput out;
        for (const auto& s : samples) {
            d.push(s);
            while (d.pop(out)) {}
        }
        d.flush();
        while (d.pop(out)) {}
        if (params.stats_exclude_flanks != 0 && d.wide_window_) {
            // A velocity whose window reaches a saccade (or a lost sample) measures that.
            std::vector<double> clean(v.size(), kNaN);
            for (size_t i = 0; i < v.size(); ++i) {
                const size_t lo = i >= static_cast<size_t>(d.k_) ? i - d.k_ : 0;
                const size_t hi = std::min(v.size() - 1, i + d.k_);
                bool ok = true;
                for (size_t j = lo; j <= hi && ok; ++j) ok = std::isfinite(v[j]);
                if (ok) clean[i] = v[i];
            }
            v.swap(clean);
        }
        VelocityThresholds next = nh_iterate(v, params, params.stats_bound_dps);
        std::array<double, 2> sum{};
        size_t m = 0;
        for (const auto& x : noise) {
            if (x[0] < 1.0 && x[1] < 1.0) {
                sum[0] += x[0];
                sum[1] += x[1];
                ++m;
            }
        }
        const double count = static_cast<double>(m);
        next.noise_deg = m ? d.noise_at_reference(sum[0] / count, sum[1] / count) : t.noise_deg;
        next.noise2_deg =
            m ? d.noise_at_reference(sum[0] / count, sum[1] / count, 2.0) : t.noise2_deg;
        const bool done = std::fabs(next.peak_dps - t.peak_dps) < 0.5;
        t = next;
        if (done) break;
    }
    if (!ms.empty()) {
        // sigma = sqrt(median(v^2) - median(v)^2) per axis (Engbert & Kliegl 2003, eq. 2).
        auto median = [](std::vector<double> v) {
            const size_t mid = v.size() / 2;
            std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
            return v[mid];
        };
        auto sigma = [&](size_t axis) {
            std::vector<double> v, v2;
            v.reserve(ms.size());
            v2.reserve(ms.size());
            for (const auto& m : ms) {
                v.push_back(m[axis]);
                v2.push_back(m[axis] * m[axis]);
            }
            const double med = median(v);
            return std::sqrt(std::max(0.0, median(v2) - med * med));
        };
        t.microsaccade_sigma_x_dps = sigma(0);
        t.microsaccade_sigma_y_dps = sigma(1);
    }
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
