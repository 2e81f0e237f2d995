#include "fovea/gaze/clock_sync.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace fovea::gaze {

ClockSync::ClockSync(const DeviceClock& clock, const ClockSyncParams& params)
    : clock_(clock), params_(params) {
    const int bits = std::clamp(clock.counter_bits, 8, 64);
    clock_.counter_bits = bits;
    if (!(clock_.tick_hz > 0.0) || !std::isfinite(clock_.tick_hz)) clock_.tick_hz = 1e9;
    mask_ = bits >= 64 ? ~uint64_t{0} : (uint64_t{1} << bits) - 1;
}

void ClockSync::restart(double dev_s) {
    bins_.clear();
    have_estimate_ = false;
    pending_steps_ = 0;
    a_ = skew_ = 0.0;
    tc_ = dev_s;
}

ClockMapping ClockSync::update(uint64_t device_ticks, int64_t receive_ns) {
    if (clock_.host_synced) {
        (void)receive_ns;
        return {static_cast<int64_t>(device_ticks), clock_.sync_uncertainty_us, true};
    }
    device_ticks &= mask_;
    if (!have_raw_) {
        have_raw_ = true;
        host_epoch_ns_ = receive_ns;
        have_epoch_ = true;
    } else {
        // Shortest signed step modulo 2^bits: wraps go forward, resets show as steps.
        uint64_t delta = (device_ticks - last_raw_) & mask_;
        int64_t step;
        if (clock_.counter_bits >= 64) {
            step = static_cast<int64_t>(delta);
        } else {
            const uint64_t half = uint64_t{1} << (clock_.counter_bits - 1);
            step = delta >= half ? static_cast<int64_t>(delta) - static_cast<int64_t>(mask_ + 1)
                                 : static_cast<int64_t>(delta);
        }
        unwrapped_ += step;
    }
    last_raw_ = device_ticks;

    const double dev_s = static_cast<double>(unwrapped_) / clock_.tick_hz;
    const double host_s = static_cast<double>(receive_ns - host_epoch_ns_) * 1e-9;
    const double offset = host_s - dev_s;

    ClockMapping out;
    if (have_estimate_ || !bins_.empty()) {
        const double expected = have_estimate_ ? predict(dev_s) : bins_.back().offset_s;
        const double residual = offset - expected;
        const bool early = residual < -params_.step_threshold_s - 4.0 * fit_sd_;
        const bool late = residual > params_.late_threshold_s;
        if (early || late) {
            ++inconsistent_;
            if (++pending_steps_ < params_.step_confirm) {
                // Fall back to the receive time until the step is confirmed or dismissed.
                out.host_ns = receive_ns;
                out.uncertainty_us = 1e6 * std::fabs(residual);
                out.converged = false;
                return out;
            }
            ++resets_;
            restart(dev_s);
        } else {
            pending_steps_ = 0;
        }
    }

    // A bin closes after bin_s and at least min_bin_samples: slow devices get longer bins so
    // every minimum is taken over enough receive jitter.
    const bool close = bins_.empty() || (dev_s - bin_start_ >= params_.bin_s &&
                                         bin_count_ >= params_.min_bin_samples);
    if (close) {
        const bool closed_one = !bins_.empty();
        bins_.push_back({0, dev_s, offset});
        bin_start_ = dev_s;
        bin_count_ = 1;
        while (!bins_.empty() && dev_s - bins_.front().dev_s > params_.window_s) bins_.pop_front();
        if (closed_one) fit();
    } else {
        ++bin_count_;
        Bin& b = bins_.back();
        if (offset < b.offset_s) {
            b.offset_s = offset;
            b.dev_s = dev_s;
        }
    }

    double est;
    if (have_estimate_) {
        est = predict(dev_s);
        // The open bin's minimum may undercut the fit (e.g. right after a skew change).
        if (bins_.back().offset_s < predict(bins_.back().dev_s)) {
            est -= predict(bins_.back().dev_s) - bins_.back().offset_s;
        }
        const double dt = dev_s - tc_;
        const double var =
            fit_sd_ * fit_sd_ * (1.0 / fit_n_ + (fit_sxx_ > 0 ? dt * dt / fit_sxx_ : 0.0));
        out.uncertainty_us = 1e6 * std::sqrt(var);
        out.converged = static_cast<int>(bins_.size()) >= params_.min_bins;
    } else {
        est = bins_.front().offset_s;
        for (const auto& b : bins_) est = std::min(est, b.offset_s);
        out.uncertainty_us = 1e6 * params_.bin_s * 1e-2 + 1e3;  // not yet known: ~ms
        out.converged = false;
    }
    out.host_ns = host_epoch_ns_ + std::llround((dev_s + est) * 1e9);
    return out;
}

void ClockSync::fit() {
    // Closed bins only: the newest one is still collecting its minimum.
    const size_t n = bins_.size() - 1;
    if (n < 2) {
        if (n == 1) {
            a_ = bins_.front().offset_s;
            tc_ = bins_.front().dev_s;
            skew_ = 0.0;
            fit_sd_ = 1e-3;
            fit_n_ = 1;
            fit_sxx_ = 0.0;
            have_estimate_ = true;
        }
        return;
    }
    std::vector<char> use(n, 1);
    for (int pass = 0; pass < 2; ++pass) {
        double st = 0, so = 0;
        int m = 0;
        for (size_t i = 0; i < n; ++i) {
            if (!use[i]) continue;
            st += bins_[i].dev_s;
            so += bins_[i].offset_s;
            ++m;
        }
        if (m < 2) break;
        const double tm = st / m, om = so / m;
        double sxx = 0, sxy = 0;
        for (size_t i = 0; i < n; ++i) {
            if (!use[i]) continue;
            const double dt = bins_[i].dev_s - tm;
            sxx += dt * dt;
            sxy += dt * (bins_[i].offset_s - om);
        }
        const double b = sxx > 0 ? sxy / sxx : 0.0;
        std::vector<double> res;
        res.reserve(n);
        double ss = 0;
        for (size_t i = 0; i < n; ++i) {
            const double r = bins_[i].offset_s - (om + b * (bins_[i].dev_s - tm));
            res.push_back(r);
            if (use[i]) ss += r * r;
        }
        // Through the lowest minimum rather than the mean of the minima: each bin minimum
        // still carries some latency, the lowest one the least.
        double lowest = 0.0;
        for (size_t i = 0; i < n; ++i) {
            if (use[i])
                lowest = std::min(lowest, bins_[i].offset_s - (om + b * (bins_[i].dev_s - tm)));
        }
        a_ = om + lowest;
        skew_ = b;
        tc_ = tm;
        fit_n_ = m;
        fit_sxx_ = sxx;
        fit_sd_ = std::sqrt(ss / std::max(1, m - 2)) + 1e-7;
        have_estimate_ = true;
        // One robust pass: bins whose minimum sits far above the line caught no fast sample.
        std::vector<double> abs_res;
        for (double r : res) abs_res.push_back(std::fabs(r));
        std::nth_element(abs_res.begin(), abs_res.begin() + n / 2, abs_res.end());
        const double mad = abs_res[n / 2] + 1e-7;
        bool dropped = false;
        for (size_t i = 0; i < n; ++i) {
            if (use[i] && res[i] > 3.0 * mad) {
                use[i] = 0;
                dropped = true;
            }
        }
        if (!dropped) break;
    }
}

}  // namespace fovea::gaze
