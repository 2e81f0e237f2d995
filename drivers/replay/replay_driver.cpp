// The replay driver: the sim driver's absolute-deadline timer, fed from a recording. As fast as
// possible means batches of samples, yielding to the loop between batches.
#include "replay/replay_driver.hpp"

#include "fovea/drivers/support.hpp"

#include <time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <optional>

#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "replay/recording.hpp"

namespace fovea::drivers::replay {
namespace {

using Clock = std::chrono::steady_clock;
constexpr auto kMinBatch = std::chrono::milliseconds(1);
constexpr std::size_t kFastBatch = 1024;  // samples per loop turn when replaying at full speed

std::shared_ptr<spdlog::logger> logger() {
    static const auto log = driver_logger("replay");  // FOVEA_LOG_DRV_REPLAY=debug
    return log;
}

class ReplayDriver final : public Driver {
public:
    ReplayDriver(const ReplayConfig& config, Recording rec, uint32_t device_id)
        : config_(config), rec_(std::move(rec)), device_id_(device_id) {}
    ~ReplayDriver() override { close(); }

    Result<void> open(boost::asio::io_context& io, SampleSink sink) override {
        io_ = &io;
        sink_ = std::move(sink);
        timer_.emplace(io);
        alive_ = std::make_shared<int>(0);
        next_ = 0;
        start_ = Clock::now();
        connected_ = true;
        logger()->info("replaying {} ({}, {} samples, {} Hz) at {}", config_.path, rec_.format,
                       rec_.samples.size(), rec_.nominal_rate_hz,
                       config_.speed > 0 ? std::to_string(config_.speed) + "x" : "full speed");
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
        info.name = "replay of " + config_.path + " (" + rec_.format + ")";
        info.address = config_.path;
        // Scaled replay: the device clock appears to run `speed` times faster.
        const double scale = config_.speed > 0 ? config_.speed : 1.0;
        info.nominal_rate_hz = rec_.nominal_rate_hz * scale;
        info.clock = {64, rec_.clock.tick_hz * scale};
        info.binocular = rec_.binocular;
        info.has_pupil = rec_.has_pupil;
        return info;
    }

    DriverStats stats() const override {
        DriverStats s;
        s.samples = samples_.load(std::memory_order_relaxed);
        s.frames_dropped = rec_.skipped_rows;
        s.connected = connected_.load(std::memory_order_relaxed);
        s.reconnects = loops_.load(std::memory_order_relaxed);
        return s;
    }

private:
    Clock::time_point due(std::size_t i) const {
        const double ns = static_cast<double>(rec_.t_ns[i]) / config_.speed;
        return start_ + std::chrono::nanoseconds(static_cast<int64_t>(ns));
    }

    void schedule(Clock::time_point at) {
        timer_->expires_at(at);
        timer_->async_wait([this, token = std::weak_ptr<int>(alive_)](boost::system::error_code ec) {
            if (ec || token.expired()) return;
            on_tick();
        });
    }

    void post_fast() {
        boost::asio::post(*io_, [this, token = std::weak_ptr<int>(alive_)] {
            if (token.expired()) return;
            const std::size_t end = std::min(next_ + kFastBatch, rec_.samples.size());
            const int64_t t_receive = monotonic_ns();
            while (next_ < end) {
                emit(t_receive);
                if (token.expired()) return;
            }
            if (at_end()) return;
            post_fast();
        });
    }

    void on_tick() {
        const auto now = Clock::now();
        const int64_t t_receive = monotonic_ns();
        const auto token = std::weak_ptr<int>(alive_);
        while (next_ < rec_.samples.size() && due(next_) <= now) {
            emit(t_receive);
            if (token.expired()) return;
        }
        if (at_end()) return;
        schedule(std::max(due(next_), now + kMinBatch));
    }

    void emit(int64_t t_receive) {
        gaze::RawSample s = rec_.samples[next_++];
        s.device_ticks += tick_offset_;
        s.t_receive_ns = t_receive;
        s.device_id = device_id_;
        samples_.fetch_add(1, std::memory_order_relaxed);
        sink_(s);
    }

    // True when the replay is over; with loop, rewinds instead.
    bool at_end() {
        if (next_ < rec_.samples.size()) return false;
        if (!config_.loop) {
            logger()->info("replay of {} finished: {} samples", config_.path, samples_.load());
            connected_ = false;
            return true;
        }
        // The device counter keeps counting across the loop: one nominal period after the last.
        const auto& first = rec_.samples.front();
        const auto& last = rec_.samples.back();
        const double period_ticks = rec_.clock.tick_hz / std::max(1.0, rec_.nominal_rate_hz);
        tick_offset_ += last.device_ticks - first.device_ticks + static_cast<uint64_t>(period_ticks);
        const double period_ns = 1e9 / std::max(1.0, rec_.nominal_rate_hz) / std::max(config_.speed, 1e-9);
        start_ = (config_.speed > 0 ? due(rec_.samples.size() - 1) : Clock::now()) +
                 std::chrono::nanoseconds(static_cast<int64_t>(period_ns));
        next_ = 0;
        ++loops_;
        if (config_.speed > 0) {
            schedule(start_);
        } else {
            post_fast();
        }
        return true;
    }

    ReplayConfig config_;
    Recording rec_;
    uint32_t device_id_;
    boost::asio::io_context* io_ = nullptr;
    SampleSink sink_;
    std::optional<boost::asio::steady_timer> timer_;
    std::shared_ptr<int> alive_;
    Clock::time_point start_;
    std::size_t next_ = 0;
    uint64_t tick_offset_ = 0;
    std::atomic<uint64_t> samples_{0}, loops_{0};
    std::atomic<bool> connected_{false};
};

}  // namespace

Result<ReplayConfig> parse_config(const toml::table& t) {
    ReplayConfig c;
    if (const toml::node* n = t.get("path")) {
        const auto v = n->value<std::string>();
        if (!v) return make_error("replay: key 'path' must be a string");
        c.path = *v;
    }
    if (c.path.empty()) return make_error("replay: 'path' is required (a lund2013 or fovea CSV file)");
    if (const toml::node* n = t.get("speed")) {
        const auto v = n->value<double>();
        if (!v) return make_error("replay: key 'speed' must be a number (0 = as fast as possible)");
        c.speed = *v;
    }
    if (!(c.speed >= 0 && c.speed <= 1000)) return make_error("replay: speed must be 0..1000");
    if (const toml::node* n = t.get("loop")) {
        const auto v = n->value<bool>();
        if (!v) return make_error("replay: key 'loop' must be true or false");
        c.loop = *v;
    }
    return c;
}

Result<std::unique_ptr<Driver>> make_replay_driver(const ReplayConfig& config, uint32_t device_id) {
    auto rec = load_recording(config.path);
    if (!rec.ok()) return make_error("replay: " + rec.error().message);
    if (rec->skipped_rows != 0) {
        logger()->warn("{}: skipped {} of {} rows (unparseable or time going backwards)", config.path,
                       rec->skipped_rows, rec->rows);
    }
    return std::unique_ptr<Driver>(std::make_unique<ReplayDriver>(config, std::move(*rec), device_id));
}

Result<std::unique_ptr<Driver>> make_driver(const toml::table& config, uint32_t device_id) {
    auto c = parse_config(config);
    if (!c.ok()) return c.error();
    return make_replay_driver(*c, device_id);
}

}  // namespace fovea::drivers::replay
