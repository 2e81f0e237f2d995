#include "daemon.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <boost/asio/post.hpp>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <deque>
#include <filesystem>
#include <optional>

#include <spdlog/spdlog.h>

#ifdef FOVEA_HAVE_SYSTEMD
#include <systemd/sd-daemon.h>
#endif

#include "calibration_commands.hpp"
#include "paths.hpp"
#include "record_commands.hpp"
#include "ring_record.hpp"
#include "zmq_publisher.hpp"

namespace fovea::daemon {

namespace asio = boost::asio;
using nlohmann::json;

namespace {

int64_t now_ns() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

void notify(const char* state) {
#ifdef FOVEA_HAVE_SYSTEMD
    sd_notify(0, state);
#else
    (void)state;
#endif
}

// The ring header's rate: whole hertz, 0 while unknown.
uint32_t ring_rate_hz(const drivers::DriverInfo& info) {
    const double hz = info.nominal_rate_hz;
    return std::isfinite(hz) && hz > 0 && hz < 4e9 ? static_cast<uint32_t>(std::lround(hz)) : 0;
}

std::shared_ptr<spdlog::logger> log() {
    auto l = spdlog::get("daemon");
    return l ? l : spdlog::default_logger();
}

}  // namespace

struct Daemon::Device {
    uint32_t id = 0;
    toml::table config;
    std::unique_ptr<drivers::Driver> driver;
    std::unique_ptr<gaze::Pipeline> pipeline;
    std::optional<gaze::Calibration> calibration;  // survives pipeline rebuilds
    drivers::DriverInfo info;
    bool open = false;
    std::string open_error;
    std::unique_ptr<asio::steady_timer> retry;
    std::chrono::milliseconds backoff{250};
    uint64_t raw_samples = 0;
    uint64_t published = 0;
    uint64_t rate_mark = 0;
    double measured_rate_hz = 0.0;
    // Live mode: how each sample went out to the ring, in order, until its final version (one
    // per raw sample, FIFO) reaches the observers carrying the same stamps and ring index.
    struct LivePublication {
        int64_t t_processed_ns, t_publish_ns;
        uint64_t index;
    };
    std::deque<LivePublication> live;
};

Daemon::Daemon(DaemonConfig config, std::string config_path)
    : config_(std::move(config)),
      config_path_(std::move(config_path)),
      signals_(io_),
      tick_timer_(io_),
      control_(io_) {}

Daemon::~Daemon() { shutdown(); }

Result<void> Daemon::take_instance_lock() {
    const std::string dir = runtime_dir();
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) return make_error("cannot create runtime directory " + dir + ": " + ec.message());
    const std::string path = lock_file_path(config_.instance);
    lock_fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (lock_fd_ < 0)
        return make_error("cannot open lock file " + path + ": " + std::strerror(errno));
    if (flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
        char pid[32] = {};
        [[maybe_unused]] auto n = ::pread(lock_fd_, pid, sizeof pid - 1, 0);
        ::close(lock_fd_);
        lock_fd_ = -1;
        return make_error("another fovead is already running for instance '" + config_.instance +
                          "' (pid " + std::string(pid[0] ? pid : "?") + ", lock " + path + ")");
    }
    const std::string me = std::to_string(getpid()) + "\n";
    [[maybe_unused]] int r = ftruncate(lock_fd_, 0);
    [[maybe_unused]] auto w = ::pwrite(lock_fd_, me.data(), me.size(), 0);
    return {};
}

Result<void> Daemon::start() {
    started_ns_ = now_ns();
    if (auto r = take_instance_lock(); !r) return r;

    ring::WriterOptions ro;
    ro.instance = config_.instance;
    ro.slot_count = config_.ring_slots;
    std::vector<toml::table> device_tables = config_.devices;
    if (device_tables.empty()) {
        toml::table sim;
        sim.insert("driver", "sim");
        device_tables.push_back(sim);
    }
    // Build every driver first: a configuration that can never work fails the start.
    for (std::size_t i = 0; i < device_tables.size(); ++i) {
        auto d = std::make_unique<Device>();
        d->id = static_cast<uint32_t>(i);
        d->config = device_tables[i];
        // The simulated tracker draws on the same screen the chain maps gaze onto.
        if (d->config["driver"].value_or(std::string("sim")) == "sim" &&
            !d->config.contains("display")) {
            const auto& g = config_.display;
            d->config.insert("display", toml::table{{"width_px", g.width_px},
                                                    {"height_px", g.height_px},
                                                    {"width_m", g.width_m},
                                                    {"height_m", g.height_m},
                                                    {"distance_m", g.distance_m}});
        }
        auto drv = drivers::make_driver(d->config, d->id);
        if (!drv) return make_error("device " + std::to_string(i) + ": " + drv.error().message);
        d->driver = std::move(drv).value();
        d->info = d->driver->describe();
        // Landing prediction stays off until a reader attaches (tick()).
        d->pipeline = std::make_unique<gaze::Pipeline>(pipeline_config(d->info, false));
        devices_.push_back(std::move(d));
    }
    ro.nominal_rate_hz = ring_rate_hz(devices_.front()->info);
    ro.device_name = devices_.front()->info.name;
    ro.eyes = config_.eyes;
    auto ring = ring::RingWriter::create(ro);
    if (!ring) return make_error("ring: " + ring.error().message);
    gaze_ring_ = std::move(ring).value();
    ro.kind = FOVEA_STREAM_HEAD;
    auto head = ring::RingWriter::create(ro);
    if (!head) return make_error("head ring: " + head.error().message);
    head_ring_ = std::move(head).value();
    for (auto& d : devices_) {
        Device* dev = d.get();
        dev->driver->set_head_sink(
            [this, dev](const drivers::HeadPose& p) { publish_head(*dev, p); });
    }

    register_commands();
    attach_recording(*this);    // record.* / latency.* commands and status sections
    attach_calibration(*this);  // calibrate.* commands, the configured user's calibration
    if (auto r = attach_zmq_publisher(*this); !r) return r;  // [zmq] fan-out, when configured
    bool socket_from_systemd = false;
#ifdef FOVEA_HAVE_SYSTEMD
    if (sd_listen_fds(1) >= 1) {
        if (auto r = control_.adopt(SD_LISTEN_FDS_START); !r) return r;
        socket_from_systemd = true;
    }
#endif
    if (!socket_from_systemd)
        if (auto r = control_.listen(control_socket_path(config_.instance)); !r) return r;

    for (auto& d : devices_) open_device(*d);

    signals_.add(SIGINT);
    signals_.add(SIGTERM);
    signals_.add(SIGHUP);
    signals_.async_wait([this](boost::system::error_code ec, int signo) {
        if (!ec) on_signal(signo);
    });
#ifdef FOVEA_HAVE_SYSTEMD
    if (sd_watchdog_enabled(0, &watchdog_usec_) <= 0) watchdog_usec_ = 0;
#endif
    tick();
    log()->info("fovead ready: instance '{}', ring {}, control {}, {} device(s)", config_.instance,
                gaze_ring_.name(), socket_from_systemd ? "(systemd socket)" : control_.path(),
                devices_.size());
    notify("READY=1\nSTATUS=publishing gaze");
    return {};
}

void Daemon::open_device(Device& d) {
    auto r = d.driver->open(io_, [this, &d](const gaze::RawSample& raw) { on_raw(d, raw); });
    if (r) {
        d.open = true;
        d.open_error.clear();
        d.backoff = std::chrono::milliseconds(250);
        log()->info("device {} ({}): opened {}", d.id, d.info.driver, d.info.address);
        return;
    }
    // Keep the others running; retry this one with exponential backoff up to 10 s.
    if (d.open_error != r.error().message)
        log()->warn("device {} ({}): {}; retrying", d.id, d.info.driver, r.error().message);
    d.open_error = r.error().message;
    if (!d.retry) d.retry = std::make_unique<asio::steady_timer>(io_);
    d.retry->expires_after(d.backoff);
    d.backoff = std::min(d.backoff * 2, std::chrono::milliseconds(10'000));
    d.retry->async_wait([this, &d](boost::system::error_code ec) {
        if (!ec && !stopping_) open_device(d);
    });
}

gaze::PipelineConfig Daemon::pipeline_config(const drivers::DriverInfo& info,
                                             bool predict_landing) const {
    gaze::PipelineConfig pc;
    pc.clock = info.clock;
    pc.display = config_.display;
    pc.nominal_rate_hz = info.nominal_rate_hz > 0 ? info.nominal_rate_hz : 1000.0;
    pc.predict_landing = predict_landing;
    pc.detector.lookahead_s = config_.lookahead_ms * 1e-3;
    return pc;
}

void Daemon::on_raw(Device& d, const gaze::RawSample& raw) {
    // Serial trackers state their clock and rate in the handshake that precedes the first
    // sample: start the chain on what the device says, not the defaults.
    if (d.raw_samples == 0) adopt_description(d);
    ++d.raw_samples;
    for (auto& o : raw_observers_) o(raw);
    d.pipeline->process(raw, scratch_);
    if (config_.publish == PublishMode::kLive && d.pipeline->latest(live_scratch_))
        publish_live(d, live_scratch_);
    for (auto& s : scratch_) emit_final(d, s);
}

void Daemon::adopt_description(Device& d) {
    const drivers::DriverInfo now = d.driver->describe();
    // A measured rate wobbles by a hertz or so (a lost sample in its window): only a change
    // of more than 10 % is a different tracker mode.
    const double chain_rate = d.pipeline->config().nominal_rate_hz;
    const double rate = pipeline_config(now, false).nominal_rate_hz;
    if (now.clock.counter_bits != d.info.clock.counter_bits ||
        now.clock.tick_hz != d.info.clock.tick_hz ||
        std::fabs(rate - chain_rate) > 0.1 * chain_rate) {
        // The chain counts its windows and look-ahead in samples: a new rate needs a new chain.
        // The old one hands over what it holds first, so nothing is lost or reordered.
        if (d.raw_samples > 0) {
            d.pipeline->flush(scratch_);
            for (auto& s : scratch_) emit_final(d, s);
            log()->info("device {} ({}): {} Hz, clock {} Hz: gaze chain rebuilt", d.id, now.driver,
                        now.nominal_rate_hz, now.clock.tick_hz);
        }
        d.pipeline = std::make_unique<gaze::Pipeline>(pipeline_config(now, readers_attached_));
        if (d.calibration) d.pipeline->set_calibration(*d.calibration);
    }
    // The rings describe the first device: its readers learn a rate measured after the start.
    if (const uint32_t hz = ring_rate_hz(now);
        &d == devices_.front().get() && hz != ring_rate_hz(d.info)) {
        gaze_ring_.set_nominal_rate_hz(hz);
        head_ring_.set_nominal_rate_hz(hz);
    }
    d.info = now;
}

void Daemon::settle(Device& d) {
    d.pipeline->settle(scratch_);
    for (auto& s : scratch_) emit_final(d, s);
}

void Daemon::publish_live(Device& d, gaze::GazeSample& s) {
    s.device_id = d.id;
    fovea_gaze_record rec = to_ring_record(s, d.info.driver == "sim");
    rec.flags |= FOVEA_FLAG_PROVISIONAL;
    gaze_ring_.publish(rec);
    ++d.published;
    d.live.push_back({s.t_processed_ns, rec.t_publish_ns, rec.index});
    // Bounded even if a chain ever emitted fewer samples than it took in.
    static constexpr std::size_t kMaxPending = 1 << 16;
    if (d.live.size() > kMaxPending) d.live.pop_front();
}

void Daemon::emit_final(Device& d, gaze::GazeSample& s) {
    if (config_.publish == PublishMode::kFinal) {
        publish(d, s);
        return;
    }
    // The ring already carries this sample's position: observers (recording, zmq, the latency
    // histograms) get the final labels with the stamps of that live publication, so the hop
    // statistics describe what readers of the ring actually saw.
    s.device_id = d.id;
    fovea_gaze_record rec = to_ring_record(s, d.info.driver == "sim");
    if (!d.live.empty()) {
        const Device::LivePublication p = d.live.front();
        d.live.pop_front();
        s.t_processed_ns = p.t_processed_ns;
        rec.t_processed_ns = p.t_processed_ns;
        rec.t_publish_ns = p.t_publish_ns;
        rec.index = p.index;
    } else {
        if (s.t_processed_ns == 0) s.t_processed_ns = now_ns();
        rec.t_processed_ns = s.t_processed_ns;
        rec.t_publish_ns = now_ns();
    }
    for (auto& o : published_observers_) o(s, rec);
}

void Daemon::publish(Device& d, gaze::GazeSample& s) {
    if (s.t_processed_ns == 0) s.t_processed_ns = now_ns();
    s.device_id = d.id;
    fovea_gaze_record rec = to_ring_record(s, d.info.driver == "sim");
    gaze_ring_.publish(rec);
    ++d.published;
    for (auto& o : published_observers_) o(s, rec);
}

void Daemon::publish_head(Device& d, const drivers::HeadPose& pose) {
    fovea_head_record rec{};
    // Head reports carry the device counter, but only the gaze chain maps it to host time: the
    // receive stamp stands in for capture until head streams get their own ClockSync.
    rec.t_capture_ns = pose.t_receive_ns;
    rec.t_receive_ns = pose.t_receive_ns;
    rec.t_processed_ns = now_ns();
    for (int i = 0; i < 3; ++i) {
        rec.position_m[i] = static_cast<float>(pose.position_m[i]);
        rec.direction[i] = static_cast<float>(pose.direction[i]);
    }
    for (int i = 0; i < 4; ++i) rec.rotation_quat[i] = static_cast<float>(pose.rotation_quat[i]);
    rec.valid = (pose.position_valid ? 1u : 0u) | (pose.direction_valid ? 2u : 0u) |
                (pose.rotation_valid ? 4u : 0u);
    rec.device_id = d.id;
    head_ring_.publish(rec);
    ++head_poses_;
}

void Daemon::register_commands() {
    control_.add_command(
        "status", [this](const json&, const PeerCredentials&) { return status(); }, false,
        "daemon, devices, rates, drops, latency, uptime");
    control_.add_command(
        "devices",
        [this](const json&, const PeerCredentials&) {
            return json{{"devices", status()["devices"]}};
        },
        false, "the configured devices and their counters");
    control_.add_command(
        "shutdown",
        [this](const json&, const PeerCredentials& peer) {
            log()->info("shutdown requested over the control socket by pid {}", peer.pid);
            asio::post(io_, [this] { request_stop(); });
            return json{{"stopping", true}};
        },
        true, "stop the daemon");
}

bool Daemon::set_calibration(uint32_t device, const gaze::Calibration* calibration) {
    if (device >= devices_.size()) return false;
    Device& d = *devices_[device];
    if (calibration) {
        d.calibration = *calibration;
        d.pipeline->set_calibration(*calibration);
    } else {
        d.calibration.reset();
        d.pipeline->clear_calibration();
    }
    return true;
}

int Daemon::show_target(bool shown, double x, double y) {
    int following = 0;
    for (auto& d : devices_) following += d->driver->follow_target(shown, x, y) ? 1 : 0;
    return following;
}

double Daemon::lookahead_ms(const Device& d) const {
    const double rate = d.info.nominal_rate_hz > 0 ? d.info.nominal_rate_hz : 1000.0;
    return d.pipeline->lookahead_samples() * 1000.0 / rate;
}

json Daemon::status() const {
    json devices = json::array();
    for (const auto& d : devices_) {
        const drivers::DriverStats st = d->driver->stats();
        devices.push_back({
            {"id", d->id},
            {"driver", d->info.driver},
            {"name", d->info.name},
            {"address", d->info.address},
            {"open", d->open},
            {"connected", st.connected},
            {"nominal_rate_hz", d->info.nominal_rate_hz},
            {"measured_rate_hz", d->measured_rate_hz},
            {"samples", st.samples},
            {"published", d->published},
            {"frames_dropped", st.frames_dropped},
            {"frames_lost", st.frames_lost},
            {"resyncs", st.resyncs},
            {"reconnects", st.reconnects},
            {"bytes", st.bytes},
            {"last_error", d->open ? st.last_error : d->open_error},
            {"lookahead_samples", d->pipeline->lookahead_samples()},
            {"lookahead_ms", lookahead_ms(*d)},
        });
        if (!st.figures.empty() || !st.notes.empty()) {
            json details = json::object();
            for (const auto& [k, v] : st.figures) details[k] = v;
            for (const auto& [k, v] : st.notes) details[k] = v;
            devices.back()["details"] = details;
        }
    }
    json s = {
        {"instance", config_.instance},
        {"pid", getpid()},
        {"version", FOVEA_VERSION},
        {"uptime_s", static_cast<double>(now_ns() - started_ns_) / 1e9},
        {"config", config_path_},
        {"display_profile", config_.display_profile},
        {"ring",
         {{"name", gaze_ring_.name()},
          {"generation", gaze_ring_.generation()},
          {"head", gaze_ring_.head()},
          {"slots", config_.ring_slots},
          {"readers_attached", readers_attached_},
          {"head_ring", head_ring_.name()},
          {"head_poses", head_poses_}}},
        {"processing",
         {{"landing_prediction", readers_attached_ ? "on" : "skipped: no reader attached"},
          {"publish", config_.publish == PublishMode::kLive ? "live" : "final"},
          // How late the ring's samples would be in "final" mode (first device).
          {"lookahead_ms", devices_.empty() ? 0.0 : lookahead_ms(*devices_.front())}}},
        {"devices", devices},
        {"control", {{"requests", control_.requests()}, {"rejected", control_.rejected()}}},
    };
    for (const auto& [key, fn] : status_sections_) s[key] = fn();
    return s;
}

void Daemon::tick() {
    // Landing prediction only matters to someone reading the ring (DESIGN.md §5, issue 8).
    const bool readers = gaze_ring_.readers_attached();
    if (readers != readers_attached_) {
        readers_attached_ = readers;
        for (auto& d : devices_) d->pipeline->set_predict_landing(readers);
        log()->info("{}", readers ? "a reader attached: landing prediction on"
                                  : "no reader attached: landing prediction skipped");
    }
    static constexpr auto kTick = std::chrono::milliseconds(250);
    for (auto& d : devices_) {
        // Names from the handshake; a rate some drivers measure only after the first samples.
        if (d->raw_samples > 0) adopt_description(*d);
        const uint64_t n = d->raw_samples;
        // A whole tick without a sample: the tracker paused. Its look-ahead would otherwise
        // keep the last samples from the recording and the fan-out until it resumes.
        if (n > 0 && n == d->rate_mark) settle(*d);
        d->measured_rate_hz =
            0.8 * d->measured_rate_hz + 0.2 * static_cast<double>(n - d->rate_mark) * 4.0;
        d->rate_mark = n;
    }
    if (watchdog_usec_) notify("WATCHDOG=1");
    tick_timer_.expires_after(kTick);
    tick_timer_.async_wait([this](boost::system::error_code ec) {
        if (!ec) tick();
    });
}

void Daemon::on_signal(int signo) {
    if (signo == SIGHUP) {
        reload();
        signals_.async_wait([this](boost::system::error_code ec, int s) {
            if (!ec) on_signal(s);
        });
        return;
    }
    log()->info("{} received: shutting down", signo == SIGINT ? "SIGINT" : "SIGTERM");
    request_stop();
}

void Daemon::reload() {
    if (config_path_.empty()) {
        log()->info("SIGHUP: no configuration file to reload");
        return;
    }
    notify("RELOADING=1");
    auto cfg = load_config(config_path_);
    if (!cfg) {
        log()->error("SIGHUP: keeping the running configuration: {}", cfg.error().message);
    } else {
        spdlog::set_level(spdlog::level::from_str(cfg->log_level));
        config_.log_level = cfg->log_level;
        log()->info("SIGHUP: reloaded {} (log level {}); the ring and devices keep running",
                    config_path_, cfg->log_level);
    }
    notify("READY=1");
}

void Daemon::request_stop() {
    asio::post(io_, [this] {
        if (stopping_) return;
        stopping_ = true;
        notify("STOPPING=1");
        io_.stop();
    });
}

int Daemon::run() {
    io_.run();
    shutdown();
    return 0;
}

void Daemon::shutdown() {
    for (auto& d : devices_) {
        if (d->retry) d->retry->cancel();
        if (d->open) {
            d->driver->close();
            d->open = false;
            std::vector<gaze::GazeSample> rest;
            d->pipeline->flush(rest);
            if (gaze_ring_.is_open())
                for (auto& s : rest) emit_final(*d, s);
        }
    }
    control_.close();
    gaze_ring_.close();
    head_ring_.close();
    tick_timer_.cancel();
    if (lock_fd_ >= 0) {
        // The lock file stays: unlinking it would let two daemons lock two different inodes.
        ::close(lock_fd_);
        lock_fd_ = -1;
    }
}

}  // namespace fovea::daemon
