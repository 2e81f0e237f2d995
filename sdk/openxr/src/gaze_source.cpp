#include "gaze_source.hpp"

#include <time.h>

#include <algorithm>

#include "layer_log.hpp"

namespace fovea::openxr {

int64_t monotonic_now_ns() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

GazeSample to_sample(const fovea_gaze_record& r, const GazeGeometry& geometry) {
    GazeSample s;
    s.t_ns = r.t_capture_ns != 0 ? r.t_capture_ns : r.t_receive_ns;
    const std::optional<Vec3> d = geometry.combined(r);
    s.valid = d.has_value();
    if (!s.valid) return s;
    s.direction = *d;
    s.pursuit = r.event == FOVEA_EVENT_PURSUIT;
    if (r.event == FOVEA_EVENT_SACCADE && r.saccade_onset_ns > 0 && r.saccade_onset_ns <= s.t_ns) {
        if (const std::optional<Vec3> l = geometry.landing(r, *d)) {
            s.saccade = true;
            s.landing = *l;
            s.saccade_onset_ns = r.saccade_onset_ns;
            s.saccade_amplitude_deg =
                std::isfinite(r.saccade_amplitude_deg) ? r.saccade_amplitude_deg : 0.0;
        }
    }
    return s;
}

GazeSource::GazeSource(GazeSourceOptions options)
    : options_(std::move(options)), timeline_(options_.timeline) {}

GazeSource::~GazeSource() { fovea_client_close(&client_); }

GazeSource::Counters GazeSource::counters() const {
    std::lock_guard<std::mutex> lock(mu_);
    return counters_;
}

void GazeSource::reset_to(fovea_client* c) {
    fovea_eye_geometry eyes{};
    fovea_client_eye_geometry(c, &eyes);
    geometry_ = GazeGeometry(eyes);
    timeline_.clear();
    // Start a little back in the ring: interpolation wants the samples just before "now".
    const uint64_t head = fovea_client_head(c);
    cursor_ = head > 64 ? head - 64 : 0;
}

void GazeSource::try_attach(int64_t now) {
    if (now < next_attach_ns_) return;
    next_attach_ns_ = now + options_.retry_ns;
    fovea_client* c = nullptr;
    if (fovea_client_open(options_.instance.c_str(), FOVEA_STREAM_GAZE, &c) != FOVEA_OK) {
        if (!said_absent_)
            log_info("no gaze yet: %s; eye gaze poses stay invalid until fovead starts",
                     fovea_last_error());
        said_absent_ = true;
        return;
    }
    client_ = c;
    reset_to(c);
    ++counters_.attaches;
    fovea_ring_info info{};
    fovea_client_info(c, &info);
    if (geometry_.has_eye_views())
        log_info("gaze from fovead instance '%s' (%s, %u Hz), HMD eye views, IPD %.1f mm",
                 options_.instance.c_str(), info.device_name, info.nominal_rate_hz,
                 geometry_.ipd_m() * 1e3);
    else
        log_info(
            "gaze from fovead instance '%s' (%s, %u Hz); fovead has no HMD display_profile, so "
            "its degrees from the display centre are taken as view directions",
            options_.instance.c_str(), info.device_name, info.nominal_rate_hz);
    said_absent_ = false;
}

void GazeSource::poll(int64_t now) {
    if (!client_) try_attach(now);
    if (!client_) return;
    fovea_gaze_record batch[64];
    for (int round = 0; round < 64; ++round) {
        const uint64_t head = fovea_client_head(client_);
        // Behind by more than the timeline keeps: skip what would be dropped anyway.
        if (head > cursor_ + 512) cursor_ = head - 512;
        uint32_t n = 0;
        uint64_t dropped = 0;
        int s = fovea_client_read(client_, &cursor_, batch, 64, &n, &dropped);
        // Nothing new: ask now (one fstat) whether fovead was restarted. The read asks by itself
        // only every 100 ms, and until then a restarted fovead's fresh gaze would read as stale.
        if ((s == FOVEA_OK && n == 0) || s == FOVEA_E_NO_DATA) {
            if (fovea_client_check(client_) == FOVEA_E_WRITER_RESTARTED)
                s = FOVEA_E_WRITER_RESTARTED;
        }
        if (s == FOVEA_E_WRITER_RESTARTED) {
            ++counters_.restarts;
            log_info("fovead instance '%s' restarted: following its new ring",
                     options_.instance.c_str());
            reset_to(client_);
            continue;
        }
        if (s != FOVEA_OK) return;
        counters_.dropped += dropped;
        for (uint32_t i = 0; i < n; ++i) timeline_.push(to_sample(batch[i], geometry_));
        counters_.records += n;
        if (n < 64) return;
    }
}

void GazeSource::note_state(const GazeEstimate& e) {
    const bool stale = e.status == GazeStatus::kStale;
    if (stale && !said_stale_)
        log_info("no new gaze from fovead instance '%s' for over %lld ms: eye gaze poses invalid",
                 options_.instance.c_str(),
                 static_cast<long long>(options_.timeline.stale_ns / 1'000'000));
    else if (!stale && said_stale_ && e.status != GazeStatus::kNoData)
        log_info("gaze from fovead instance '%s' again", options_.instance.c_str());
    said_stale_ = stale;
}

GazeEstimate GazeSource::at(int64_t t_ns) {
    std::lock_guard<std::mutex> lock(mu_);
    const int64_t now = monotonic_now_ns();
    poll(now);
    const GazeEstimate e = timeline_.at(t_ns, now);
    note_state(e);
    return e;
}

}  // namespace fovea::openxr
