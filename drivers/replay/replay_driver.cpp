// The replay driver: the sim driver's absolute-deadline timer, fed one sample ahead from a
// fovea::import::Reader. As fast as possible means batches of samples, yielding to the loop
// between batches. Looping reopens the file.
#include "replay/replay_driver.hpp"

#include "fovea/drivers/support.hpp"

#include <time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <mutex>
#include <optional>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>

namespace fovea::drivers::replay {
namespace {

using Clock = std::chrono::steady_clock;
constexpr auto kMinBatch = std::chrono::milliseconds(1);
constexpr std::size_t kFastBatch = 1024;  // samples per loop turn when replaying at full speed
constexpr std::size_t kIssuesLogged = 5;  // per pass over the file; the rest are counted

std::shared_ptr<spdlog::logger> logger() {
    static const auto log = driver_logger("replay");  // FOVEA_LOG_DRV_REPLAY=debug
    return log;
}

// Spelled fovea::import: clang-format 14 takes a line that begins with `import` for a C++20
// module import and leaves it unformatted.
fovea::import::Options import_options(const ReplayConfig& c) {
    fovea::import::Options o;
    o.format = c.format;
    o.min_confidence = c.min_confidence;
    return o;
}

class ReplayDriver final : public Driver {
public:
    ReplayDriver(const ReplayConfig& config, std::unique_ptr<import::Reader> reader,
                 uint32_t device_id)
        : config_(config),
          reader_(std::move(reader)),
          info_(reader_->info()),
          device_id_(device_id) {}
    ~ReplayDriver() override { close(); }

    Result<void> open(boost::asio::io_context& io, SampleSink sink) override {
        io_ = &io;
        sink_ = std::move(sink);
        timer_.emplace(io);
        alive_ = std::make_shared<int>(0);
        start_ = Clock::now();
        connected_ = true;
        logger()->info("replaying {} ({}, {}, {} Hz) at {}", config_.path,
                       import::format_name(info_.format), info_.variant, info_.rate_hz(),
                       config_.speed > 0 ? std::to_string(config_.speed) + "x" : "full speed");
        if (!fetch()) {
            finish();
            return {};
        }
        if (config_.speed > 0) {
            schedule(start_);
        } else {
            post_fast();
        }
        return {};
    }

    void close() override {
        alive_.reset();
        if (timer_) timer_->cancel();
        timer_.reset();
        connected_ = false;
    }

    DriverInfo describe() const override {
        DriverInfo info;
        info.driver = "replay";
        info.name = "replay of " + config_.path + " (" + import::format_name(info_.format) +
                    (info_.device.empty() ? "" : ", " + info_.device) + ")";
        info.address = config_.path;
        // Scaled replay: the device clock appears to run `speed` times faster.
        const double scale = config_.speed > 0 ? config_.speed : 1.0;
        info.nominal_rate_hz = info_.rate_hz() * scale;
        info.clock = {64, info_.clock.tick_hz * scale};
        info.binocular = info_.binocular;
        info.has_pupil = info_.has_pupil;
        return info;
    }

    DriverStats stats() const override {
        DriverStats s;
        s.samples = samples_.load(std::memory_order_relaxed);
        s.frames_dropped = dropped_.load(std::memory_order_relaxed);
        s.connected = connected_.load(std::memory_order_relaxed);
        s.reconnects = loops_.load(std::memory_order_relaxed);
        std::lock_guard lock(error_mutex_);
        s.last_error = last_error_;
        return s;
    }

private:
    Clock::time_point due(double t_s) const {
        const double ns = (t_s - first_s_) * 1e9 / config_.speed;
        return start_ + std::chrono::nanoseconds(static_cast<int64_t>(ns));
    }

    // Reads ahead to the next sample; false at the end of the file.
    bool fetch() {
        for (auto item = reader_->next(); item != import::Item::kEnd; item = reader_->next()) {
            if (item != import::Item::kSample) continue;
            const import::Sample& s = reader_->sample();
            pending_ = s.raw;
            pending_s_ = s.time_s;
            if (!have_first_) {
                first_s_ = s.time_s;
                first_ticks_ = s.raw.device_ticks;
                have_first_ = true;
            }
            return true;
        }
        report_pass();
        return false;
    }

    void report_pass() {
        const import::ReadStats& st = reader_->stats();
        dropped_.fetch_add(st.skipped, std::memory_order_relaxed);
        for (std::size_t i = 0; i < std::min(kIssuesLogged, st.issues.size()); ++i)
            logger()->warn("{}", st.issues[i]);
        if (st.issue_count > kIssuesLogged)
            logger()->warn("{}: {} more issues", config_.path, st.issue_count - kIssuesLogged);
        const std::string err = reader_->error();
        if (!err.empty()) {
            logger()->error("{}", err);
            std::lock_guard lock(error_mutex_);
            last_error_ = err;
        }
    }

    void schedule(Clock::time_point at) {
        timer_->expires_at(at);
        timer_->async_wait(
            [this, token = std::weak_ptr<int>(alive_)](boost::system::error_code ec) {
                if (ec || token.expired()) return;
                on_tick();
            });
    }

    void post_fast() {
        boost::asio::post(*io_, [this, token = std::weak_ptr<int>(alive_)] {
            if (token.expired()) return;
            const int64_t t_receive = monotonic_ns();
            for (std::size_t i = 0; i < kFastBatch; ++i) {
                if (!emit(t_receive) || token.expired()) return;
            }
            post_fast();
        });
    }

    void on_tick() {
        const auto now = Clock::now();
        const int64_t t_receive = monotonic_ns();
        const auto token = std::weak_ptr<int>(alive_);
        while (due(pending_s_) <= now) {
            if (!emit(t_receive) || token.expired()) return;
        }
        schedule(std::max(due(pending_s_), now + kMinBatch));
    }

    // Delivers the pending sample and reads the next; false when the replay is over (or
    // restarted on its own schedule with loop).
    bool emit(int64_t t_receive) {
        gaze::RawSample s = pending_;
        last_ticks_ = s.device_ticks;
        last_s_ = pending_s_;
        s.device_ticks += tick_offset_;
        s.t_receive_ns = t_receive;
        s.device_id = device_id_;
        samples_.fetch_add(1, std::memory_order_relaxed);
        const auto token = std::weak_ptr<int>(alive_);
        sink_(s);
        if (token.expired()) return false;
        if (fetch()) return true;
        if (!config_.loop || !restart()) finish();
        return false;
    }

    void finish() {
        logger()->info("replay of {} finished: {} samples", config_.path, samples_.load());
        connected_ = false;
    }

    // Loop: reopen the file; the device counter keeps counting, one period after the last.
    bool restart() {
        import::Options o = import_options(config_);
        o.format = info_.format;
        o.rate_hz = info_.measured_rate_hz;
        auto reader = import::open(config_.path, o);
        if (!reader) {
            logger()->error("replay: cannot reopen for the next loop: {}", reader.error().message);
            std::lock_guard lock(error_mutex_);
            last_error_ = reader.error().message;
            return false;
        }
        reader_ = std::move(*reader);
        const double rate = std::max(1.0, info_.rate_hz());
        tick_offset_ +=
            last_ticks_ - first_ticks_ + static_cast<uint64_t>(info_.clock.tick_hz / rate);
        const double period_ns = 1e9 / rate / std::max(config_.speed, 1e-9);
        start_ = (config_.speed > 0 ? due(last_s_) : Clock::now()) +
                 std::chrono::nanoseconds(static_cast<int64_t>(period_ns));
        have_first_ = false;
        ++loops_;
        if (!fetch()) return false;
        if (config_.speed > 0) {
            schedule(start_);
        } else {
            post_fast();
        }
        return true;
    }

    ReplayConfig config_;
    std::unique_ptr<import::Reader> reader_;
    const import::SourceInfo info_;  // of the first pass
    uint32_t device_id_;
    boost::asio::io_context* io_ = nullptr;
    SampleSink sink_;
    std::optional<boost::asio::steady_timer> timer_;
    std::shared_ptr<int> alive_;
    Clock::time_point start_;
    gaze::RawSample pending_;
    double pending_s_ = 0, first_s_ = 0, last_s_ = 0;
    uint64_t first_ticks_ = 0, last_ticks_ = 0;
    bool have_first_ = false;
    uint64_t tick_offset_ = 0;
    std::atomic<uint64_t> samples_{0}, loops_{0}, dropped_{0};
    std::atomic<bool> connected_{false};
    mutable std::mutex error_mutex_;
    std::string last_error_;
};

}  // namespace

Result<ReplayConfig> parse_config(const toml::table& t) {
    ReplayConfig c;
    if (auto r = read_key("replay", t, "path", c.path); !r) return r.error();
    if (c.path.empty())
        return make_error("replay: 'path' is required (a recording file or Pupil folder)");
    std::string format;
    if (auto r = read_key("replay", t, "format", format); !r) return r.error();
    if (!format.empty()) {
        c.format = import::format_from_name(format);
        if (!c.format) {
            std::string known;
            for (auto f : import::all_formats())
                known += std::string(known.empty() ? "" : ", ") + import::format_name(f);
            return make_error("replay: unknown format '" + format + "' (known: " + known + ")");
        }
    }
    if (auto r = read_key("replay", t, "speed", c.speed); !r)
        return make_error("replay: key 'speed' must be a number (0 = as fast as possible)");
    if (!(c.speed >= 0 && c.speed <= 1000)) return make_error("replay: speed must be 0..1000");
    if (auto r = read_key("replay", t, "loop", c.loop); !r)
        return make_error("replay: key 'loop' must be true or false");
    if (auto r = read_key("replay", t, "min_confidence", c.min_confidence); !r) return r.error();
    if (!(c.min_confidence >= 0 && c.min_confidence <= 1))
        return make_error("replay: min_confidence must be 0..1");
    return c;
}

Result<std::unique_ptr<Driver>> make_replay_driver(const ReplayConfig& config, uint32_t device_id) {
    auto reader = import::open(config.path, import_options(config));
    if (!reader) return make_error("replay: " + reader.error().message);
    return std::unique_ptr<Driver>(
        std::make_unique<ReplayDriver>(config, std::move(*reader), device_id));
}

Result<std::unique_ptr<Driver>> make_driver(const toml::table& config, uint32_t device_id) {
    auto c = parse_config(config);
    if (!c.ok()) return c.error();
    return make_replay_driver(*c, device_id);
}

}  // namespace fovea::drivers::replay
