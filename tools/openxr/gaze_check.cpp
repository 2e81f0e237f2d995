#include "gaze_check.hpp"

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <thread>

#include "gaze_geometry.hpp"
#include "pose_math.hpp"

namespace fovea::xr {
namespace {

using openxr::Vec3;

int64_t now_ns() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

Vec3 forward_of(const XrPosef& p) { return openxr::forward(openxr::from_xr(p).q); }

// Every record fovead publishes, across restarts of the daemon.
class RingReader {
public:
    RingReader(fovea_client* c, CheckRun& run) : c_(c), run_(run) {
        if (!c_) return;
        fovea_client_eye_geometry(c_, &run_.eyes);
        const uint64_t head = fovea_client_head(c_);
        cursor_ = head > 256 ? head - 256 : 0;
    }
    ~RingReader() { fovea_client_close(&c_); }
    void pull() {
        if (!c_) return;
        fovea_gaze_record batch[256];
        for (;;) {
            uint32_t n = 0;
            const int s = fovea_client_read(c_, &cursor_, batch, 256, &n, nullptr);
            if (s == FOVEA_E_WRITER_RESTARTED) {
                ++run_.ring_restarts;
                cursor_ = 0;
                continue;
            }
            if (s != FOVEA_OK) return;
            run_.records.insert(run_.records.end(), batch, batch + n);
            if (n < 256) return;
        }
    }

private:
    fovea_client* c_;
    CheckRun& run_;
    uint64_t cursor_ = 0;
};

fovea_client* open_ring(const std::string& instance, int timeout_ms) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    for (;;) {
        fovea_client* c = nullptr;
        if (fovea_client_open(instance.c_str(), FOVEA_STREAM_GAZE, &c) == FOVEA_OK &&
            fovea_client_head(c) > 0)
            return c;
        fovea_client_close(&c);
        if (std::chrono::steady_clock::now() >= end) return nullptr;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
}

// A small deterministic generator for where between two samples the probe falls.
double next_fraction(uint64_t& state) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return 0.05 + 0.9 * static_cast<double>(state >> 11) / 9007199254740992.0;
}

}  // namespace

Result<CheckRun> run_check(const CheckOptions& o) {
    CheckRun run;
    auto offer = query_offer();
    if (!offer) return offer.error();
    run.offer = *offer;
    fovea_client* ring = open_ring(o.instance, o.ring_timeout_ms);
    if (!ring && !o.allow_no_gaze)
        return make_error("no gaze from fovead instance '" + o.instance + "' within " +
                          std::to_string(o.ring_timeout_ms) + " ms: " + fovea_last_error());
    RingReader reader(ring, run);
    auto session = HeadlessSession::create({"fovea openxr-check", true});
    if (!session) return session.error();
    HeadlessSession& s = **session;
    run.runtime = s.runtime_name();
    run.eye_gaze = s.eye_gaze();
    run.supports_eye_gaze_interaction = s.supports_eye_gaze_interaction();
    if (!run.eye_gaze && !o.allow_no_gaze)
        return make_error(
            "XR_EXT_eye_gaze_interaction is not offered: is XR_APILAYER_FOVEA_eye_gaze installed "
            "where the loader finds implicit layers (…/share/openxr/1/api_layers/implicit.d) and "
            "not disabled (DISABLE_XR_APILAYER_FOVEA_eye_gaze)?");
    if (auto f = s.wait_until_focused(o.focus_timeout_ms); !f) return f.error();

    uint64_t rng = 0x9E3779B97F4A7C15ull;
    run.frames.reserve(static_cast<std::size_t>(o.frames));
    for (int i = 0; i < o.frames; ++i) {
        auto f = s.begin_frame();
        if (!f) return f.error();
        FrameRecord fr;
        fr.begin_ns = now_ns();
        fr.display_ns = s.to_monotonic_ns(f->display_time);
        reader.pull();
        if (!run.records.empty()) fr.newest_before_ns = run.records.back().t_capture_ns;
        if (run.eye_gaze) {
            fr.active = s.gaze_action_active();
            const auto t0 = std::chrono::steady_clock::now();
            const GazeLocation g = s.locate_gaze(s.view_space(), f->display_time);
            const auto t1 = std::chrono::steady_clock::now();
            fr.locate_us = std::chrono::duration<double, std::micro>(t1 - t0).count();
            fr.valid = g.valid();
            const Vec3 d = forward_of(g.pose);
            std::copy(d.begin(), d.end(), fr.dir);
            fr.sample_ns = g.sample_time ? s.to_monotonic_ns(g.sample_time) : 0;
        }
        reader.pull();
        const std::size_t n = run.records.size();
        if (n > 0) {
            fr.newest_capture_ns = run.records[n - 1].t_capture_ns;
            fr.newest_event = run.records[n - 1].event;
        }
        // Probe between the two newest samples while they are fresh (not across an outage).
        if (run.eye_gaze && n >= 2 && now_ns() - fr.newest_capture_ns < 50'000'000) {
            const int64_t ta = run.records[n - 2].t_capture_ns,
                          tb = run.records[n - 1].t_capture_ns;
            if (tb > ta) {
                const int64_t t = ta + static_cast<int64_t>(next_fraction(rng) * (tb - ta));
                const XrTime xt = s.to_xr_time(t);
                const GazeLocation gv = s.locate_gaze(s.view_space(), xt);
                fr.probe_ns = t;
                fr.probe_valid = gv.valid();
                const Vec3 pd = forward_of(gv.pose);
                std::copy(pd.begin(), pd.end(), fr.probe_dir);
                const GazeLocation gl = s.locate_gaze(s.local_space(), xt);
                const XrSpaceLocation vl = s.locate(s.view_space(), s.local_space(), xt);
                if (gv.valid() && gl.valid() &&
                    (vl.locationFlags & XR_SPACE_LOCATION_ORIENTATION_VALID_BIT)) {
                    const openxr::Pose composed =
                        openxr::compose(openxr::from_xr(vl.pose), openxr::from_xr(gv.pose));
                    fr.probe_local_error_deg =
                        openxr::angle_deg(openxr::forward(composed.q), forward_of(gl.pose));
                }
            }
        }
        if (auto e = s.end_frame(*f); !e) return e.error();
        run.frames.push_back(fr);
    }
    // The gaze at the last frames' display times arrives shortly after them.
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
    reader.pull();
    return run;
}

namespace {

struct Ref {
    int64_t t = 0;
    bool valid = false;
    bool blink = false;
    bool saccade = false;
    Vec3 d{0, 0, -1};
};

struct RefState {
    bool valid = false;
    bool blink = false;
    Vec3 d{0, 0, -1};
};

// The ring's gaze at time t, nullopt outside the records or across a gap (daemon down).
std::optional<RefState> ref_at(const std::vector<Ref>& refs, int64_t t) {
    if (refs.size() < 2 || t < refs.front().t || t > refs.back().t) return std::nullopt;
    auto hi = std::upper_bound(refs.begin(), refs.end(), t,
                               [](int64_t v, const Ref& r) { return v < r.t; });
    if (hi == refs.end()) hi = refs.end() - 1;
    if (hi == refs.begin()) hi = refs.begin() + 1;
    const Ref& b = *hi;
    const Ref& a = *(hi - 1);
    if (b.t - a.t > 50'000'000 || b.t <= a.t) return std::nullopt;
    RefState s;
    if (a.valid && b.valid) {
        s.valid = true;
        s.d =
            openxr::slerp(a.d, b.d, static_cast<double>(t - a.t) / static_cast<double>(b.t - a.t));
        return s;
    }
    const Ref& near = (t - a.t) <= (b.t - t) ? a : b;
    s.valid = near.valid;
    s.blink = near.blink;
    s.d = near.d;
    return s;
}

double quantile(std::vector<double> v, double q) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    const double pos = q * static_cast<double>(v.size() - 1);
    const auto lo = static_cast<std::size_t>(std::floor(pos));
    const std::size_t hi = std::min(lo + 1, v.size() - 1);
    return v[lo] + (v[hi] - v[lo]) * (pos - static_cast<double>(lo));
}

Vec3 vec(const double (&d)[3]) { return {d[0], d[1], d[2]}; }

// Frames until each saccade shows in the pose at display time, against the frames until it
// shows in the gaze recorded at those display times; the worst over saccades >= 2 deg.
void score_saccades(const std::vector<Ref>& refs, const std::vector<FrameRecord>& frames,
                    CheckReport& rep) {
    constexpr double kMovedDeg = 1.0;
    for (std::size_t i = 1; i < refs.size(); ++i) {
        if (!refs[i].saccade || refs[i - 1].saccade || !refs[i - 1].valid) continue;
        const Vec3 d0 = refs[i - 1].d;
        std::size_t end = i;
        while (end + 1 < refs.size() && refs[end + 1].saccade) ++end;
        const std::size_t settle = std::min(refs.size() - 1, end + 20);
        if (!refs[settle].valid || openxr::angle_deg(d0, refs[settle].d) < 2.0) continue;
        std::size_t cross = i;
        while (cross <= settle &&
               (!refs[cross].valid || openxr::angle_deg(d0, refs[cross].d) < kMovedDeg))
            ++cross;
        if (cross > settle) continue;
        const int64_t t_cross = refs[cross].t;
        // The first frame displayed after the gaze had moved, and the first whose pose moved.
        std::size_t k_truth = 0;
        while (k_truth < frames.size() && frames[k_truth].display_ns < t_cross) ++k_truth;
        if (k_truth == 0 || k_truth >= frames.size()) continue;
        std::size_t k_layer = k_truth - 1;
        while (k_layer < frames.size() && frames[k_layer].display_ns < refs[i].t) ++k_layer;
        const std::size_t limit = std::min(frames.size(), k_truth + 6);
        bool any_invalid = false;
        while (k_layer < limit) {
            const FrameRecord& f = frames[k_layer];
            any_invalid |= !f.valid;
            if (f.valid && openxr::angle_deg(d0, vec(f.dir)) >= kMovedDeg) break;
            ++k_layer;
        }
        if (any_invalid && k_layer >= limit) continue;  // a blink or an outage hid it
        ++rep.saccades;
        // The first frame located with the moved sample already in the ring: a later one means
        // the data came late (tracker, fovead or scheduling), which no layer can make up for.
        std::size_t k_avail = k_truth > 0 ? k_truth - 1 : 0;
        while (k_avail < frames.size() && frames[k_avail].newest_before_ns < t_cross) ++k_avail;
        const int layer_lag = static_cast<int>(k_layer) - static_cast<int>(k_avail);
        rep.saccade_layer_lag_frames_max = std::max(rep.saccade_layer_lag_frames_max, layer_lag);
        if (k_avail > k_truth + 1) {
            ++rep.late_data_saccades;
            continue;
        }
        const int lag = static_cast<int>(k_layer) - static_cast<int>(k_truth);
        if (lag > rep.saccade_lag_frames_max) {
            rep.saccade_lag_frames_max = lag;
            const FrameRecord& ft = frames[k_truth];
            char why[256];
            std::snprintf(why, sizeof why,
                          "frame %zu: gaze moved %.0f deg, 1 deg by %.1f ms before display; the "
                          "frame (begun %.1f ms before display) had a sample %.1f ms old at "
                          "display, pose moved %.2f deg",
                          k_truth, openxr::angle_deg(d0, refs[settle].d),
                          (ft.display_ns - t_cross) / 1e6, (ft.display_ns - ft.begin_ns) / 1e6,
                          (ft.display_ns - ft.newest_capture_ns) / 1e6,
                          ft.valid ? openxr::angle_deg(d0, vec(ft.dir)) : -1.0);
            rep.worst_saccade = why;
        }
    }
}

}  // namespace

CheckReport evaluate(const CheckRun& run, const CheckLimits& limits) {
    CheckReport rep;
    const openxr::GazeGeometry geometry(run.eyes);
    std::vector<Ref> refs;
    refs.reserve(run.records.size());
    for (const fovea_gaze_record& r : run.records) {
        Ref x;
        x.t = r.t_capture_ns;
        const auto d = geometry.combined(r);
        x.valid = d.has_value();
        if (d) x.d = *d;
        x.blink = r.event == FOVEA_EVENT_BLINK;
        x.saccade = r.event == FOVEA_EVENT_SACCADE;
        if (!refs.empty() && x.t <= refs.back().t) continue;  // keep the times increasing
        refs.push_back(x);
    }

    rep.frames = static_cast<int>(run.frames.size());
    rep.display_error_deg.assign(run.frames.size(), -1);
    rep.hold_error_deg.assign(run.frames.size(), -1);
    rep.probe_error_deg.assign(run.frames.size(), -1);
    std::vector<double> probe_err, ages, locates, display_err, hold_err, sac_display, sac_hold;
    int run_len = 0;
    std::size_t longest_end = 0;  // index after the longest run of invalid frames
    for (std::size_t k = 0; k < run.frames.size(); ++k) {
        const FrameRecord& f = run.frames[k];
        if (k > 0)
            rep.frame_interval_max_ms = std::max(rep.frame_interval_max_ms,
                                                 (f.begin_ns - run.frames[k - 1].begin_ns) / 1e6);
        if (run.eye_gaze) locates.push_back(f.locate_us);
        if (f.valid) {
            ++rep.valid_frames;
            if (run_len > rep.longest_invalid_run) {
                rep.longest_invalid_run = run_len;
                longest_end = k;
            }
            run_len = 0;
            if (f.newest_capture_ns > 0) ages.push_back((f.display_ns - f.newest_capture_ns) / 1e6);
            if (const auto truth = ref_at(refs, f.display_ns); truth && truth->valid) {
                display_err.push_back(openxr::angle_deg(vec(f.dir), truth->d));
                rep.display_error_deg[k] = display_err.back();
                if (const auto held = ref_at(refs, f.newest_capture_ns); held && held->valid) {
                    hold_err.push_back(openxr::angle_deg(held->d, truth->d));
                    rep.hold_error_deg[k] = hold_err.back();
                    if (f.newest_event == FOVEA_EVENT_SACCADE) {
                        sac_display.push_back(display_err.back());
                        sac_hold.push_back(hold_err.back());
                    }
                }
            }
        } else {
            ++rep.invalid_frames;
            if (run_len++ == 0) ++rep.invalid_runs;
        }
        if (f.probe_ns != 0) {
            ++rep.probes;
            if (const auto ref = ref_at(refs, f.probe_ns)) {
                ++rep.probes_compared;
                if (ref->valid != f.probe_valid && rep.validity_mismatches++ == 0) {
                    auto hi = std::upper_bound(refs.begin(), refs.end(), f.probe_ns,
                                               [](int64_t v, const Ref& r) { return v < r.t; });
                    if (hi == refs.end()) --hi;  // the probe at the newest sample (as ref_at)
                    char b[256];
                    std::snprintf(
                        b, sizeof b,
                        "frame %zu: probe %s, ring %s; ring neighbours %+.3f ms %s, "
                        "%+.3f ms %s; newest read %+.3f ms",
                        k, f.probe_valid ? "valid" : "invalid", ref->valid ? "valid" : "untracked",
                        ((hi - 1)->t - f.probe_ns) / 1e6, (hi - 1)->valid ? "valid" : "untracked",
                        (hi->t - f.probe_ns) / 1e6, hi->valid ? "valid" : "untracked",
                        (f.newest_capture_ns - f.probe_ns) / 1e6);
                    rep.first_validity_mismatch = b;
                }
                if (!ref->valid) ++rep.blink_probes;
                if (ref->valid && f.probe_valid) {
                    probe_err.push_back(openxr::angle_deg(vec(f.probe_dir), ref->d));
                    rep.probe_error_deg[k] = probe_err.back();
                }
            }
            rep.max_local_error_deg = std::max(rep.max_local_error_deg, f.probe_local_error_deg);
        }
    }
    if (run_len > rep.longest_invalid_run) {
        rep.longest_invalid_run = run_len;
        longest_end = run.frames.size();
    }
    for (std::size_t k = longest_end; rep.longest_invalid_run > 0 && k < run.frames.size(); ++k)
        rep.valid_after_longest_invalid_run += run.frames[k].valid ? 1 : 0;
    rep.max_angle_error_deg = probe_err.empty() ? 0 : quantile(probe_err, 1.0);
    rep.median_angle_error_deg = quantile(probe_err, 0.5);
    rep.median_gaze_age_ms = quantile(ages, 0.5);
    rep.p95_gaze_age_ms = quantile(ages, 0.95);
    rep.locate_p50_us = quantile(locates, 0.5);
    rep.locate_p99_us = quantile(locates, 0.99);
    rep.locate_max_us = locates.empty() ? 0 : quantile(locates, 1.0);
    rep.display_compared = static_cast<int>(display_err.size());
    rep.display_error_p50_deg = quantile(display_err, 0.5);
    rep.display_error_p95_deg = quantile(display_err, 0.95);
    rep.hold_error_p50_deg = quantile(hold_err, 0.5);
    rep.hold_error_p95_deg = quantile(hold_err, 0.95);
    rep.saccade_frames = static_cast<int>(sac_display.size());
    rep.saccade_display_error_p50_deg = quantile(sac_display, 0.5);
    rep.saccade_hold_error_p50_deg = quantile(sac_hold, 0.5);
    if (run.eye_gaze) score_saccades(refs, run.frames, rep);

    auto fail = [&](std::string why) { rep.failures.push_back(std::move(why)); };
    if (!run.eye_gaze) {
        fail("XR_EXT_eye_gaze_interaction was not offered");
        return rep;
    }
    if (rep.probes_compared == 0) fail("no matching-time probe could be compared with the ring");
    if (rep.max_angle_error_deg > limits.max_angle_error_deg)
        fail("pose differs from the ring's gaze by up to " +
             std::to_string(rep.max_angle_error_deg) + " deg at matching times (limit " +
             std::to_string(limits.max_angle_error_deg) + ")");
    if (rep.validity_mismatches > 0)
        fail(std::to_string(rep.validity_mismatches) +
             " matching-time poses were valid where the ring says untracked, or the reverse "
             "(first: " +
             rep.first_validity_mismatch + ")");
    if (rep.saccade_layer_lag_frames_max > 0)
        fail("a saccade already in the ring took " +
             std::to_string(rep.saccade_layer_lag_frames_max) + " more frames to show in the pose");
    if (rep.saccade_lag_frames_max > limits.max_saccade_lag_frames)
        fail("a saccade took " + std::to_string(rep.saccade_lag_frames_max) +
             " frames longer to show in the pose than in the gaze (" + rep.worst_saccade + ")");
    if (rep.max_local_error_deg > limits.max_local_error_deg)
        fail("gaze located in LOCAL differs from VIEW-in-LOCAL x gaze-in-VIEW by " +
             std::to_string(rep.max_local_error_deg) + " deg");
    return rep;
}

}  // namespace fovea::xr
