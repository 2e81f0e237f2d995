#include "fovea/gaze/pipeline.hpp"

#include <time.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <optional>

namespace fovea::gaze {

namespace {

int64_t monotonic_ns() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

bool finite_eye(const EyeSample& e) {
    return e.valid && std::isfinite(e.x) && std::isfinite(e.y) && std::fabs(e.x) < 1e6 &&
           std::fabs(e.y) < 1e6;
}

// Per-eye smoothing of the degree coordinates.
class EyeFilter {
public:
    EyeFilter(const PipelineConfig& c)
        : kind_(c.filter), ex_(c.one_euro), ey_(c.one_euro), kx_(c.kalman), ky_(c.kalman) {}
    void apply(double t_s, double& x, double& y) {
        switch (kind_) {
            case FilterKind::kOneEuro:
                x = ex_.filter(x, t_s);
                y = ey_.filter(y, t_s);
                break;
            case FilterKind::kKalman:
                x = kx_.filter(x, t_s);
                y = ky_.filter(y, t_s);
                break;
            case FilterKind::kNone: break;
        }
    }

private:
    FilterKind kind_;
    OneEuroFilter ex_, ey_;
    KalmanCv kx_, ky_;
};

}  // namespace

struct Pipeline::Impl {
    explicit Impl(const PipelineConfig& c)
        : config(c),
          clock(c.clock, c.clock_sync),
          left_filter(c),
          right_filter(c),
          detector(c.detector, c.nominal_rate_hz, c.detector_mode),
          predictor(c.landing) {
        if (c.detector_mode == DetectorMode::kOffline)
            detector.set_thresholds(c.offline_thresholds);
    }

    void eye(EyeSide side, const EyeSample& raw, double t_s, EyeSample& out, double& dx,
             double& dy) {
        EyeSample e = raw;
        if (!finite_eye(e)) {
            ++stats.eyes_invalid;
            out = EyeSample{kNaN, kNaN, e.pupil_mm, false};
            return;
        }
        if (calibration) e = calibration->apply(side, e);
        if (!e.valid) {
            ++stats.eyes_invalid;
            out = EyeSample{kNaN, kNaN, e.pupil_mm, false};
            return;
        }
        config.display.to_degrees(e.x, e.y, dx, dy);
        raw_dx = dx;
        raw_dy = dy;
        (side == EyeSide::kLeft ? left_filter : right_filter).apply(t_s, dx, dy);
        out = e;
        config.display.to_normalized(dx, dy, out.x, out.y);
    }

    void process(const RawSample& raw, std::vector<GazeSample>& out) {
        ++stats.samples_in;
        GazeSample g;
        const ClockMapping m = clock.update(raw.device_ticks, raw.t_receive_ns);
        if (!m.converged && m.uncertainty_us > 1e5) ++stats.clock_fallbacks;
        stats.clock_resets = clock.resets();
        g.t_capture_ns = m.host_ns;
        g.t_receive_ns = raw.t_receive_ns;
        g.clock_uncertainty_us = m.uncertainty_us;
        g.clock_converged = m.converged;
        g.device_id = raw.device_id;
        g.truth = raw.truth;
        g.calibrated = calibration.has_value();
        if (!have_t0) {
            t0_ns = g.t_capture_ns;
            have_t0 = true;
        }
        const double t_s = static_cast<double>(g.t_capture_ns - t0_ns) * 1e-9;

        double lx = kNaN, ly = kNaN, rx = kNaN, ry = kNaN;
        double lrx = kNaN, lry = kNaN, rrx = kNaN, rry = kNaN;
        eye(EyeSide::kLeft, raw.left, t_s, g.left, lx, ly);
        lrx = g.left.valid ? raw_dx : kNaN;
        lry = g.left.valid ? raw_dy : kNaN;
        eye(EyeSide::kRight, raw.right, t_s, g.right, rx, ry);
        rrx = g.right.valid ? raw_dx : kNaN;
        rry = g.right.valid ? raw_dy : kNaN;
        if (g.left.valid) {
            g.left_deg_x = lx;
            g.left_deg_y = ly;
        }
        if (g.right.valid) {
            g.right_deg_x = rx;
            g.right_deg_y = ry;
        }
        // Combined: mean of the valid eyes (filtered for publishing, raw for detection).
        DetectorInput in;
        in.t_s = t_s;
        if (g.left.valid && g.right.valid) {
            g.combined_deg_x = 0.5 * (lx + rx);
            g.combined_deg_y = 0.5 * (ly + ry);
            in.x_deg = 0.5 * (lrx + rrx);
            in.y_deg = 0.5 * (lry + rry);
        } else if (g.left.valid) {
            g.combined_deg_x = lx;
            g.combined_deg_y = ly;
            in.x_deg = lrx;
            in.y_deg = lry;
        } else if (g.right.valid) {
            g.combined_deg_x = rx;
            g.combined_deg_y = ry;
            in.x_deg = rrx;
            in.y_deg = rry;
        }
        in.valid = g.left.valid || g.right.valid;
        if (in.valid) {
            g.combined.valid = true;
            config.display.to_normalized(g.combined_deg_x, g.combined_deg_y, g.combined.x,
                                         g.combined.y);
            const int n = (g.left.valid ? 1 : 0) + (g.right.valid ? 1 : 0);
            g.combined.pupil_mm = ((g.left.valid ? g.left.pupil_mm : 0.0) +
                                   (g.right.valid ? g.right.pupil_mm : 0.0)) /
                                  n;
        }
        detector.push(in);
        pending.push_back(g);
        history.push_back({t_s, in.x_deg, in.y_deg, g.t_capture_ns});
        if (history.size() > kHistory) history.pop_front();
        ++pushed;
        predict();
        newest = g;
        newest.t_processed_ns = monotonic_ns();
        have_newest = true;
        drain(out);
    }

    // Capture time of the sample the detector numbered `index`; 0 once it left the history.
    int64_t capture_ns_of(int64_t index) const {
        const int64_t first_kept = pushed - static_cast<int64_t>(history.size());
        if (index < first_kept || index >= pushed) return 0;
        return history[static_cast<size_t>(index - first_kept)].t_ns;
    }

    // Landing prediction at the newest sample while the detector sees a saccade in flight.
    void predict() {
        if (!predict_landing || !detector.saccade_in_flight()) return;
        const int64_t onset = detector.saccade_onset_index();
        const int64_t first_kept = pushed - static_cast<int64_t>(history.size());
        if (onset < first_kept) return;
        const size_t from = static_cast<size_t>(onset - first_kept);
        const size_t n = history.size() - from;
        if (n < 3 || n > kMaxFit) return;
        double ts[kMaxFit], xs[kMaxFit], ys[kMaxFit];
        for (size_t i = 0; i < n; ++i) {
            const auto& h = history[from + i];
            ts[i] = h.t - history[from].t;
            xs[i] = h.x;
            ys[i] = h.y;
            if (!std::isfinite(xs[i]) || !std::isfinite(ys[i])) return;
        }
        const LandingEstimate e = predictor.predict({ts, n}, {xs, n}, {ys, n});
        if (!e.valid) return;
        ++stats.predictions;
        landing_id = detector.saccade_id();
        landing = e;
    }

    void attach(GazeSample& g, const DetectorOutput& o) {
        g.event = o.event;
        g.saccade = o.saccade;
        if (o.event == Event::kSaccade || o.event == Event::kPso) {
            g.saccade.onset_ns = o.saccade.onset_ns + t0_ns;
        }
        // The newest prediction made while this saccade was in flight.
        if (o.event == Event::kSaccade && o.saccade_id >= 0 && landing_id == o.saccade_id &&
            landing.valid) {
            g.saccade.landing_valid = true;
            g.saccade.landing_deg_x = landing.x_deg;
            g.saccade.landing_deg_y = landing.y_deg;
            g.saccade.landing_uncertainty_deg = landing.uncertainty_deg;
            config.display.to_normalized(landing.x_deg, landing.y_deg, g.saccade.landing_x,
                                         g.saccade.landing_y);
        }
    }

    void drain(std::vector<GazeSample>& out) {
        DetectorOutput o;
        while (!pending.empty() && detector.pop(o)) {
            GazeSample& g = pending.front();
            attach(g, o);
            g.t_processed_ns = monotonic_ns();
            out.push_back(g);
            pending.pop_front();
            ++stats.samples_out;
        }
    }

    struct Hist {
        double t, x, y;
        int64_t t_ns;  // capture time, for the provisional saccade onset
    };
    static constexpr size_t kHistory = 512;
    static constexpr size_t kMaxFit = 512;

    PipelineConfig config;
    ClockSync clock;
    std::optional<Calibration> calibration;
    EyeFilter left_filter, right_filter;
    EventDetector detector;
    LandingPredictor predictor;
    bool predict_landing = true;
    std::deque<GazeSample> pending;
    std::deque<Hist> history;
    int64_t pushed = 0;
    bool have_t0 = false;
    int64_t t0_ns = 0;
    double raw_dx = kNaN, raw_dy = kNaN;
    int64_t landing_id = -1;
    LandingEstimate landing;
    GazeSample newest;  // the last processed sample, before the look-ahead labels it
    bool have_newest = false;
    PipelineStats stats;
};

Pipeline::Pipeline(const PipelineConfig& config) : impl_(std::make_unique<Impl>(config)) {
    impl_->predict_landing = config.predict_landing;
}
Pipeline::~Pipeline() = default;
Pipeline::Pipeline(Pipeline&&) noexcept = default;
Pipeline& Pipeline::operator=(Pipeline&&) noexcept = default;

void Pipeline::process(const RawSample& raw, std::vector<GazeSample>& out) {
    out.clear();
    impl_->process(raw, out);
}

void Pipeline::flush(std::vector<GazeSample>& out) {
    out.clear();
    impl_->detector.flush();
    impl_->drain(out);
}

void Pipeline::settle(std::vector<GazeSample>& out) {
    out.clear();
    impl_->detector.settle();
    impl_->drain(out);
}

const PipelineConfig& Pipeline::config() const { return impl_->config; }
void Pipeline::set_predict_landing(bool on) { impl_->predict_landing = on; }
int Pipeline::lookahead_samples() const { return impl_->detector.lookahead_samples(); }
void Pipeline::set_calibration(const Calibration& c) { impl_->calibration = c; }
void Pipeline::clear_calibration() { impl_->calibration.reset(); }
PipelineStats Pipeline::stats() const { return impl_->stats; }

bool Pipeline::latest_landing(SaccadeInfo& out) const {
    const Impl& m = *impl_;
    if (!m.detector.saccade_in_flight() || m.landing_id != m.detector.saccade_id() ||
        !m.landing.valid) {
        return false;
    }
    out = SaccadeInfo{};
    out.landing_valid = true;
    out.landing_deg_x = m.landing.x_deg;
    out.landing_deg_y = m.landing.y_deg;
    out.amplitude_deg = m.landing.amplitude_deg;
    out.landing_uncertainty_deg = m.landing.uncertainty_deg;
    m.config.display.to_normalized(m.landing.x_deg, m.landing.y_deg, out.landing_x, out.landing_y);
    return true;
}

bool Pipeline::latest(GazeSample& out) const {
    const Impl& m = *impl_;
    if (!m.have_newest) return false;
    out = m.newest;
    out.event = Event::kUnknown;
    out.saccade = SaccadeInfo{};
    // Causal labels only: what the detector knows at this very sample.
    if (!out.combined.valid) {
        out.event = Event::kBlink;
    } else if (m.detector.saccade_in_flight()) {
        out.event = Event::kSaccade;
        latest_landing(out.saccade);
        out.saccade.onset_ns = m.capture_ns_of(m.detector.saccade_onset_index());
    }
    return true;
}

}  // namespace fovea::gaze
