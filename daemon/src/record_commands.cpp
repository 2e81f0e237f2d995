#include "record_commands.hpp"

#include <signal.h>

#include <cerrno>

#include <algorithm>
#include <array>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <utility>

#include <spdlog/spdlog.h>

#include "daemon.hpp"
#include "fovea/json_integer.hpp"
#include "fovea/record/latency_stats.hpp"
#include "fovea/record/recorder.hpp"

namespace fovea::daemon {

namespace {

using nlohmann::json;

constexpr std::size_t kMaxClients = 64;
// Raw samples kept for a recording's pre-roll: 64 s at 1 kHz, ~6 MB. While the daemon has
// seen fewer, the pre-roll is the chain's whole history and replay is exact by construction.
constexpr std::size_t kPrerollSamples = 65536;

std::shared_ptr<spdlog::logger> log() {
    auto l = spdlog::get("daemon");
    return l ? l : spdlog::default_logger();
}

json stats_json(const record::RecorderStats& s) {
    json j = {{"path", s.path},
              {"active", s.recording},
              {"raw_samples", s.raw_samples},
              {"gaze_samples", s.gaze_samples},
              {"latency_samples", s.latency_samples},
              {"dropped_samples", s.dropped_samples},
              {"bytes", s.bytes_written},
              {"flushes", s.flushes},
              {"buffer_bytes", s.buffer_bytes}};
    if (s.failed) j["error"] = s.error;
    return j;
}

// Device info for the stream headers: build the device's driver from its configuration without
// opening it (factories only parse their table), as Daemon::start() does.
record::RecordingInfo recording_info(const Daemon& d) {
    record::RecordingInfo info;
    toml::table table;
    if (!d.config().devices.empty()) {
        table = d.config().devices.front();
    } else {
        table.insert("driver", "sim");
    }
    if (auto drv = drivers::make_driver(table, 0)) {
        const auto di = (*drv)->describe();
        info.device_name = di.name;
        info.driver = di.driver;
        info.address = di.address;
        info.nominal_rate_hz = di.nominal_rate_hz;
        info.clock = di.clock;
        info.binocular = di.binocular;
        info.has_pupil = di.has_pupil;
    }
    info.display = d.config().display;
    return info;
}

// The SDK's gaze-age hops (fovea_render_hop in fovea/client.h) beyond record::Hop's pipeline.
constexpr std::array<const char*, 3> kGazeAgeHops = {
    "capture_to_frame_begin", "publish_to_frame_begin", "capture_to_present"};

// What one SDK client last reported with latency.report (cumulative since it started).
struct ClientReport {
    record::LatencyStats hops;
    std::array<LatencyHistogram, kGazeAgeHops.size()> gaze_age;
    uint64_t frames = 0, stale_frames = 0, frames_without_gaze = 0;
    int64_t stale_threshold_ns = 0;

    static ClientReport parse(const json& req) {
        if (!req.contains("hops")) throw std::runtime_error("latency.report needs \"hops\"");
        auto s = record::LatencyStats::from_json(req["hops"]);
        if (!s) throw std::runtime_error(s.error().message);
        ClientReport r;
        r.hops = std::move(s).value();
        for (std::size_t i = 0; i < kGazeAgeHops.size(); ++i) {
            if (!req["hops"].contains(kGazeAgeHops[i])) continue;
            if (auto h = record::histogram_from_json(req["hops"][kGazeAgeHops[i]], r.gaze_age[i]);
                !h)
                throw std::runtime_error(std::string(kGazeAgeHops[i]) + ": " + h.error().message);
        }
        for (auto [key, out] :
             {std::pair{"frames", &r.frames}, std::pair{"stale_frames", &r.stale_frames},
              std::pair{"frames_without_gaze", &r.frames_without_gaze}}) {
            const auto c = json_count(req, key, 0);
            if (!c)
                throw std::runtime_error(std::string("latency.report: \"") + key +
                                         "\" must be a non-negative integer");
            *out = *c;
        }
        const auto stale = req.contains("stale_threshold_ns")
                               ? json_integer(req["stale_threshold_ns"], 0, INT64_MAX)
                               : std::optional<int64_t>(0);
        if (!stale)
            throw std::runtime_error(
                "latency.report: \"stale_threshold_ns\" must be a non-negative integer");
        r.stale_threshold_ns = *stale;
        return r;
    }
};

struct RecordingService {
    Daemon& daemon;
    record::LatencyStats device_hops;
    std::map<int, ClientReport> clients;  // by peer pid
    std::unique_ptr<record::Recorder> recorder;
    json last;  // counters of the last finished recording
    std::deque<std::pair<gaze::RawSample, bool>> preroll;  // (raw, predict_landing)
    uint64_t raw_seen = 0;

    void on_raw(const gaze::RawSample& raw) {
        const bool predict = daemon.landing_prediction();
        ++raw_seen;
        if (preroll.size() == kPrerollSamples) preroll.pop_front();
        preroll.emplace_back(raw, predict);
        if (recorder) recorder->push_raw(raw, predict);
    }

    explicit RecordingService(Daemon& d) : daemon(d) {}

    json start(const json& req) {
        if (recorder)
            throw std::runtime_error("already recording to " + recorder->path() +
                                     " (record.stop first)");
        const std::string path = req.value("path", std::string());
        if (path.empty() || path.front() != '/') {
            throw std::runtime_error(
                "record.start needs an absolute \"path\" (the daemon's working "
                "directory is not yours)");
        }
        record::RecorderOptions o;
        o.path = path;
        o.info = recording_info(daemon);
        o.info.preroll_from_start = raw_seen <= kPrerollSamples;
        if (req.contains("flush_ms")) {
            o.flush_interval_ns = static_cast<int64_t>(req["flush_ms"].get<double>() * 1e6);
        }
        o.on_error = [path](const std::string& e) { log()->error("recording: {}", e); };
        auto r = record::Recorder::start(std::move(o));
        if (!r) throw std::runtime_error(r.error().message);
        recorder = std::move(r).value();
        // samples the chain has already processed: replay needs them to rebuild its state
        for (const auto& [raw, predict] : preroll) recorder->push_raw(raw, predict, true);
        log()->info("recording to {}", path);
        return {{"recording", true},
                {"path", path},
                {"preroll_samples", preroll.size()},
                {"preroll_from_start", raw_seen <= kPrerollSamples}};
    }

    json stop() {
        if (!recorder) throw std::runtime_error("not recording");
        auto r = recorder->stop();
        json j = stats_json(recorder->stats());
        recorder.reset();
        last = j;
        log()->info("recording stopped: {}", j.dump());
        if (!r) j["error"] = r.error().message;
        return j;
    }

    json report(const json& req, const PeerCredentials& peer) {
        ClientReport r = ClientReport::parse(req);
        if (clients.size() >= kMaxClients && !clients.count(peer.pid)) {
            // forget clients that have exited before refusing anyone
            for (auto it = clients.begin(); it != clients.end();) {
                it =
                    ::kill(it->first, 0) != 0 && errno == ESRCH ? clients.erase(it) : std::next(it);
            }
            if (clients.size() >= kMaxClients)
                throw std::runtime_error("too many reporting clients");
        }
        clients[peer.pid] = std::move(r);
        return {{"accepted", true}};
    }

    json status_recording() const {
        if (recorder) return stats_json(recorder->stats());
        json j = last.is_null() ? json{{"active", false}} : last;
        j["active"] = false;
        return j;
    }

    // Every client's hops merged; the gaze-age hops under "gaze_age", the frame counters summed
    // under "frames" (the stale thresholds are per client: the smallest and largest are shown).
    json status_clients() const {
        record::LatencyStats all;
        std::array<LatencyHistogram, kGazeAgeHops.size()> age;
        json frames = {{"frames", 0}, {"stale", 0}, {"without_gaze", 0}};
        int64_t thr_min = 0, thr_max = 0;
        for (const auto& [pid, c] : clients) {
            all.merge(c.hops);
            for (std::size_t i = 0; i < age.size(); ++i) age[i].merge(c.gaze_age[i]);
            frames["frames"] = frames["frames"].get<uint64_t>() + c.frames;
            frames["stale"] = frames["stale"].get<uint64_t>() + c.stale_frames;
            frames["without_gaze"] = frames["without_gaze"].get<uint64_t>() + c.frames_without_gaze;
            if (c.stale_threshold_ns > 0) {
                thr_min =
                    thr_min == 0 ? c.stale_threshold_ns : std::min(thr_min, c.stale_threshold_ns);
                thr_max = std::max(thr_max, c.stale_threshold_ns);
            }
        }
        json j = all.to_json(false);
        json ages = json::object();
        for (std::size_t i = 0; i < age.size(); ++i)
            if (age[i].count()) ages[kGazeAgeHops[i]] = record::histogram_to_json(age[i], false);
        if (!ages.empty()) j["gaze_age"] = ages;
        if (thr_max > 0) {
            frames["stale_threshold_ms_min"] = static_cast<double>(thr_min) / 1e6;
            frames["stale_threshold_ms_max"] = static_cast<double>(thr_max) / 1e6;
        }
        j["frames"] = frames;
        j["clients"] = clients.size();
        return j;
    }
};

}  // namespace

void attach_recording(Daemon& daemon) {
    auto svc = std::make_shared<RecordingService>(daemon);
    daemon.add_raw_observer([svc](const gaze::RawSample& raw) { svc->on_raw(raw); });
    daemon.add_published_observer([svc](const gaze::GazeSample& s, const fovea_gaze_record& r) {
        svc->device_hops.record_published(s, r.t_publish_ns);
        if (svc->recorder) svc->recorder->push_gaze(s, r.t_publish_ns, r.index);
    });
    auto& c = daemon.control();
    c.add_command(
        "record.start", [svc](const json& req, const PeerCredentials&) { return svc->start(req); },
        true, "start an XDF recording: {\"path\": \"/abs/file.xdf\"}");
    c.add_command(
        "record.stop", [svc](const json&, const PeerCredentials&) { return svc->stop(); }, true,
        "stop the XDF recording");
    c.add_command(
        "latency.report",
        [svc](const json& req, const PeerCredentials& peer) { return svc->report(req, peer); },
        false, "an SDK client's render-side latency histograms: {\"hops\": {...}}");
    c.add_command(
        "latency.reset",
        [svc](const json&, const PeerCredentials&) {
            svc->device_hops.reset();
            svc->clients.clear();
            return json{{"reset", true}};
        },
        true, "zero the latency histograms");
    daemon.add_status_section("latency", [svc] { return svc->device_hops.to_json(false); });
    daemon.add_status_section("latency_clients", [svc] { return svc->status_clients(); });
    daemon.add_status_section("recording", [svc] { return svc->status_recording(); });
}

}  // namespace fovea::daemon
