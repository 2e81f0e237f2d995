// `fovea report`, stage 1: the numbers (report_parts.hpp).
#include <algorithm>
#include <cmath>

#include "report_parts.hpp"

namespace fovea::record::report {
namespace {

// The pre-roll (chain history from before the recording started) is for replay only.
void drop_preroll(Recording& rec) {
    std::size_t keep = 0;
    for (std::size_t i = 0; i < rec.raw.size(); ++i) {
        if (rec.raw_preroll[i]) continue;
        rec.raw[keep] = rec.raw[i];
        rec.raw_predict_landing[keep] = rec.raw_predict_landing[i];
        rec.raw_preroll[keep++] = false;
    }
    rec.raw.resize(keep);
    rec.raw_predict_landing.resize(keep);
    rec.raw_preroll.resize(keep);
}

// Saccades as the detector labelled them: each run of saccade samples, with the largest amplitude
// and peak velocity it reported.
std::vector<Saccade> find_saccades(const Recording& rec, int64_t t0) {
    std::vector<Saccade> sacc;
    for (std::size_t i = 0; i < rec.gaze.size();) {
        if (rec.gaze[i].event != gaze::Event::kSaccade) {
            ++i;
            continue;
        }
        std::size_t j = i;
        double amp = 0, peak = 0;
        while (j < rec.gaze.size() && rec.gaze[j].event == gaze::Event::kSaccade) {
            if (std::isfinite(rec.gaze[j].saccade.amplitude_deg))
                amp = std::max(amp, rec.gaze[j].saccade.amplitude_deg);
            if (std::isfinite(rec.gaze[j].saccade.peak_velocity_dps))
                peak = std::max(peak, rec.gaze[j].saccade.peak_velocity_dps);
            ++j;
        }
        if (amp > 0 && peak > 0)
            sacc.push_back({static_cast<double>(rec.gaze[i].t_capture_ns - t0) * 1e-9, amp, peak});
        i = j;
    }
    return sacc;
}

// Drops and validity per 100 ms bin; adds the device counter gaps to `missing_samples`.
Timeline make_timeline(const Recording& rec, int64_t t0, double rate, double duration_s,
                       uint64_t& missing_samples) {
    Timeline tl;
    const double bin_s = tl.bin_s;
    const std::size_t nb = static_cast<std::size_t>(duration_s / bin_s) + 1;
    tl.lo.resize(nb);
    tl.hi.resize(nb);
    tl.missing.assign(nb, 0);
    tl.total.assign(nb, 0);
    tl.valid_left.assign(nb, 0);
    tl.valid_right.assign(nb, 0);
    tl.ring_gap.assign(nb, 0);
    for (std::size_t b = 0; b < nb; ++b) {
        tl.lo[b] = static_cast<double>(b) * bin_s;
        tl.hi[b] = tl.lo[b] + bin_s;
    }
    const double tick_period = 1.0 / rec.info.clock.tick_hz;
    const uint64_t mask = rec.info.clock.counter_bits >= 64
                              ? ~uint64_t{0}
                              : (uint64_t{1} << rec.info.clock.counter_bits) - 1;
    for (std::size_t i = 0; i < rec.raw.size(); ++i) {
        const auto& r = rec.raw[i];
        const std::size_t b = std::min(
            nb - 1,
            static_cast<std::size_t>(static_cast<double>(r.t_receive_ns - t0) * 1e-9 / bin_s));
        tl.total[b] += 1;
        tl.valid_left[b] += r.left.valid;
        tl.valid_right[b] += r.right.valid;
        if (i > 0 && rec.raw[i - 1].device_id == r.device_id) {
            // gaps in the device's own clock: samples the device took that never arrived
            const double dt =
                static_cast<double>((r.device_ticks - rec.raw[i - 1].device_ticks) & mask) *
                tick_period;
            const double lost = std::round(dt * rate) - 1;
            if (lost > 0 && lost < 1e6) {
                tl.missing[b] += lost;
                missing_samples += static_cast<uint64_t>(lost);
            }
        }
    }
    for (std::size_t i = 1; i < rec.ring_index.size(); ++i) {
        const double gap =
            static_cast<double>(rec.ring_index[i]) - static_cast<double>(rec.ring_index[i - 1]) - 1;
        if (gap > 0) {
            const std::size_t b = std::min(
                nb - 1,
                static_cast<std::size_t>(std::max(
                    0.0, static_cast<double>(rec.gaze[i].t_capture_ns - t0) * 1e-9 / bin_s)));
            tl.ring_gap[b] += gap;
        }
    }
    return tl;
}

}  // namespace

const char* event_label(gaze::Event e) {
    switch (e) {
        case gaze::Event::kFixation: return "fixation";
        case gaze::Event::kSaccade: return "saccade";
        case gaze::Event::kPso: return "PSO";
        case gaze::Event::kPursuit: return "pursuit";
        case gaze::Event::kBlink: return "blink";
        default: return "unknown";
    }
}

Analysis analyse(Recording rec) {
    Analysis a;
    drop_preroll(rec);
    a.rec = std::move(rec);
    const Recording& r = a.rec;
    ReportSummary& sum = a.summary;
    sum.raw_samples = r.raw.size();
    sum.gaze_samples = r.gaze.size();
    a.rate = r.info.nominal_rate_hz > 0 ? r.info.nominal_rate_hz : 1000.0;
    a.t0 = !r.raw.empty()    ? r.raw.front().t_receive_ns
           : !r.gaze.empty() ? r.gaze.front().t_capture_ns
                             : r.info.time_origin_ns;
    if (!r.raw.empty())
        sum.duration_s = static_cast<double>(r.raw.back().t_receive_ns - a.t0) * 1e-9;

    for (std::size_t i = 0; i < r.gaze.size(); ++i) {
        const auto& g = r.gaze[i];
        a.hops[0].record(g.t_receive_ns - g.t_capture_ns);
        a.hops[1].record(g.t_processed_ns - g.t_receive_ns);
        a.hops[2].record(r.t_publish_ns[i] - g.t_processed_ns);
        a.hops[3].record(r.t_publish_ns[i] - g.t_capture_ns);
    }

    a.saccades = find_saccades(r, a.t0);
    sum.saccades = a.saccades.size();
    std::vector<double> ratios;
    for (const auto& s : a.saccades)
        ratios.push_back(s.peak / kExpectedMainSequence.peak_velocity_dps(s.amplitude));
    if (!ratios.empty()) {
        std::nth_element(ratios.begin(), ratios.begin() + static_cast<long>(ratios.size() / 2),
                         ratios.end());
        sum.main_sequence_median_ratio = ratios[ratios.size() / 2];
    }

    if (!r.raw.empty())
        a.timeline = make_timeline(r, a.t0, a.rate, sum.duration_s, sum.missing_samples);
    for (const auto& g : r.gaze)
        a.event_samples[std::min<std::size_t>(5, static_cast<std::size_t>(g.event))]++;
    return a;
}

}  // namespace fovea::record::report
