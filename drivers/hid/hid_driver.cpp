#include "hid/hid_driver.hpp"

#include "fovea/drivers/support.hpp"

#include <time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include <hidapi.h>
#include <spdlog/spdlog.h>
#include <boost/asio/post.hpp>

#include "hid/enumerate.hpp"
#include "hid/session.hpp"

namespace fovea::drivers::hid {
namespace {

std::shared_ptr<spdlog::logger> logger() {
    static const auto log = driver_logger("hid");  // FOVEA_LOG_DRV_HID=debug
    return log;
}

struct Config {
    std::string path;
    std::optional<uint16_t> vid, pid;
    std::string serial;
    double screen_w_um = 0, screen_h_um = 0;
};

// What posted handlers may touch after close(): the sinks and a liveness flag.
struct Shared {
    std::mutex mu;
    SampleSink sink;
    HeadSink head_sink;
    bool alive = true;
};

class HidDriver final : public Driver {
public:
    HidDriver(Config cfg, uint32_t device_id) : cfg_(std::move(cfg)), device_id_(device_id) {}
    ~HidDriver() override { close(); }

    Result<void> open(boost::asio::io_context& io, SampleSink sink) override {
        if (auto r = ensure_hidapi(); !r) return r;
        io_ = &io;
        shared_ = std::make_shared<Shared>();
        shared_->sink = std::move(sink);
        shared_->head_sink = head_sink_;
        stop_ = false;
        thread_ = std::thread([this] { run(); });
        return {};
    }

    void close() override {
        if (!thread_.joinable()) return;
        {
            std::lock_guard lk(wake_mu_);
            stop_ = true;
        }
        wake_.notify_all();
        thread_.join();
        std::lock_guard lk(shared_->mu);
        shared_->alive = false;
    }

    void set_head_sink(HeadSink sink) override { head_sink_ = std::move(sink); }

    DriverInfo describe() const override {
        std::lock_guard lk(stats_mu_);
        return info_;
    }

    DriverStats stats() const override {
        std::lock_guard lk(stats_mu_);
        return stats_;
    }

private:
    void run() {
        auto backoff = std::chrono::milliseconds(250);
        while (!stop_) {
            hid_device* dev = connect();
            if (dev == nullptr) {
                std::unique_lock lk(wake_mu_);
                wake_.wait_for(lk, backoff, [this] { return stop_.load(); });
                backoff = std::min(backoff * 2, std::chrono::milliseconds(5000));
                continue;
            }
            backoff = std::chrono::milliseconds(250);
            read_loop(dev);
            hid_close(dev);
            std::lock_guard lk(stats_mu_);
            stats_.connected = false;
        }
    }

    // Finds the configured tracker, opens it, parses its descriptor and reads its features.
    hid_device* connect() {
        std::string path = cfg_.path;
        if (path.empty()) {
            auto list = enumerate_trackers();
            if (!list) return fail(list.error().message);
            for (const auto& d : *list) {
                if (cfg_.vid && d.vendor_id != *cfg_.vid) continue;
                if (cfg_.pid && d.product_id != *cfg_.pid) continue;
                if (!cfg_.serial.empty() && d.serial != cfg_.serial) continue;
                path = d.path;
                break;
            }
            if (path.empty()) return fail("no HID eye/head tracker (usage page 0x12) found");
        }
        auto bytes = read_report_descriptor(path);
        if (!bytes) return fail(bytes.error().message);
        auto session = TrackerSession::create(*bytes, cfg_.screen_w_um, cfg_.screen_h_um);
        if (!session) return fail(path + ": " + session.error().message);
        hid_device* dev = hid_open_path(path.c_str());
        if (dev == nullptr)
            return fail("cannot open " + path + " (permissions? see udev/README.md)");
        std::vector<uint8_t> buf(4097);
        for (uint8_t id : session->layout().features.report_ids) {
            buf.assign(buf.size(), 0);
            buf[0] = id;
            const int n = hid_get_feature_report(dev, buf.data(), buf.size());
            if (n <= 0) continue;
            // hidraw returns the report number first even for unnumbered reports.
            std::span<const uint8_t> rep(buf.data(), static_cast<std::size_t>(n));
            session->apply_feature(session->layout().numbered ? rep : rep.subspan(1));
        }
        hid_set_nonblocking(dev, 0);
        session_ = std::move(*session);
        const auto& info = session_->info();
        if (info.configuration_status != ConfigurationStatus::kUnknown &&
            info.configuration_status != ConfigurationStatus::kReady)
            logger()->warn("{}: tracker reports '{}'", path, to_string(info.configuration_status));
        if (!(session_->screen_width_um() > 0))
            logger()->warn("{}: no calibrated screen size; set screen_width_mm/screen_height_mm",
                           path);
        std::lock_guard lk(stats_mu_);
        if (ever_connected_) ++stats_.reconnects;
        ever_connected_ = true;
        stats_.connected = true;
        info_.address = path;
        info_.clock = session_->clock();
        info_.nominal_rate_hz = info.sampling_frequency_hz.value_or(0);
        info_.name = session_->layout().head_tracker && !session_->layout().eye_tracker
                         ? "HID head tracker"
                         : "HID eye tracker";
        logger()->info("{}: connected ({} tracking report(s), {} Hz)", path,
                       session_->layout().tracking.size(), info_.nominal_rate_hz);
        return dev;
    }

    hid_device* fail(const std::string& why) {
        std::lock_guard lk(stats_mu_);
        if (why != stats_.last_error) logger()->info("{}", why);  // one line per new condition
        stats_.last_error = why;
        return nullptr;
    }

    void read_loop(hid_device* dev) {
        std::vector<uint8_t> buf(std::max<uint32_t>(session_->layout().max_input_bytes, 64) + 64);
        while (!stop_) {
            const int n = hid_read_timeout(dev, buf.data(), buf.size(), 100);
            if (n == 0) continue;
            if (n < 0) {
                fail("read failed (device unplugged?)");
                return;
            }
            handle(std::span<const uint8_t>(buf.data(), static_cast<std::size_t>(n)));
        }
    }

    void handle(std::span<const uint8_t> report) {
        gaze::RawSample sample;
        HeadPose pose;
        const auto out = session_->on_report(report, monotonic_ns(), device_id_, sample, pose);
        {
            std::lock_guard lk(stats_mu_);
            stats_.bytes += report.size();
            if (out.status == DecodeStatus::kTooShort) ++stats_.frames_dropped;
            if (out.gaze) ++stats_.samples;
        }
        if (out.status == DecodeStatus::kTooShort)
            logger()->debug("dropped a {}-byte report shorter than declared", report.size());
        if (!out.gaze && !out.head) return;
        boost::asio::post(*io_, [shared = shared_, out, sample, pose] {
            std::lock_guard lk(shared->mu);
            if (!shared->alive) return;
            if (out.gaze && shared->sink) shared->sink(sample);
            if (out.head && shared->head_sink) shared->head_sink(pose);
        });
    }

    Config cfg_;
    uint32_t device_id_;
    boost::asio::io_context* io_ = nullptr;
    HeadSink head_sink_;
    std::shared_ptr<Shared> shared_;
    std::thread thread_;
    std::atomic<bool> stop_{false};
    std::mutex wake_mu_;
    std::condition_variable wake_;
    std::optional<TrackerSession> session_;  // reader thread only
    mutable std::mutex stats_mu_;
    DriverStats stats_;
    DriverInfo info_{"hid", "HID eye tracker", "", 0.0, {}, false, false};
    bool ever_connected_ = false;
};

}  // namespace

Result<std::unique_ptr<Driver>> make_driver(const toml::table& config, uint32_t device_id) {
    Config cfg;
    cfg.path = config["path"].value_or(std::string());
    if (config.contains("vid")) {
        cfg.vid = parse_usb_id(config["vid"]);
        if (!cfg.vid) return make_error("hid: 'vid' must be 0..0xFFFF (integer or hex string)");
    }
    if (config.contains("pid")) {
        cfg.pid = parse_usb_id(config["pid"]);
        if (!cfg.pid) return make_error("hid: 'pid' must be 0..0xFFFF (integer or hex string)");
    }
    cfg.serial = config["serial"].value_or(std::string());
    cfg.screen_w_um = config["screen_width_mm"].value_or(0.0) * 1000.0;
    cfg.screen_h_um = config["screen_height_mm"].value_or(0.0) * 1000.0;
    if (cfg.screen_w_um < 0 || cfg.screen_h_um < 0)
        return make_error("hid: screen_width_mm/screen_height_mm must be positive");
    return std::unique_ptr<Driver>(std::make_unique<HidDriver>(std::move(cfg), device_id));
}

}  // namespace fovea::drivers::hid
