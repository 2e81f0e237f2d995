// The simulated tracker as a Driver: a steady_timer on the daemon's io_context emits the samples
// that are due. Copy this file to start a new driver: a factory that turns the `[[device]]` table
// into a validated config, open() that arms the I/O, close() that disarms it, and counters.
#include "sim/sim_driver.hpp"

#include "fovea/drivers/support.hpp"

#include <time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <boost/asio/steady_timer.hpp>

#include "sim/sim_tracker.hpp"

namespace fovea::drivers::sim {
namespace {

constexpr auto kMinBatch = std::chrono::milliseconds(1);  // at most ~1000 wake-ups a second
constexpr auto kMaxLag = std::chrono::seconds(1);         // beyond this, skip rather than burst

std::shared_ptr<spdlog::logger> logger() {
    static const auto log = driver_logger("sim");  // FOVEA_LOG_DRV_SIM=debug
    return log;
}

Result<SimConfig> parse_config(const toml::table& t) {
    SimConfig c;
    int64_t seed = static_cast<int64_t>(c.seed), bits = c.counter_bits;
    ConfigKeys keys("sim", t);
    keys.read("seed", seed);
    keys.read("rate_hz", c.rate_hz);
    keys.read("binocular", c.binocular);
    keys.read("noise_deg", c.noise_deg);
    keys.read("tremor_deg", c.tremor_deg);
    keys.read("drift_dps", c.drift_dps);
    keys.read("vergence_deg", c.vergence_deg);
    keys.read("fixation_mean_ms", c.fixation_mean_ms);
    keys.read("saccade_median_deg", c.saccade_median_deg);
    keys.read("blink_rate_hz", c.blink_rate_hz);
    keys.read("pursuit_share", c.pursuit_share);
    keys.read("pupil_mm", c.pupil_mm);
    keys.read("distortion", c.distortion);
    keys.read("counter_bits", bits);
    keys.read("tick_hz", c.tick_hz);
    keys.read("drift_ppm", c.drift_ppm);
    keys.read("counter_offset", c.counter_offset);
    if (const toml::table* d = t["display"].as_table()) {
        int64_t w = c.display.width_px, h = c.display.height_px;
        keys.read(*d, "width_px", w);
        keys.read(*d, "height_px", h);
        keys.read(*d, "width_m", c.display.width_m);
        keys.read(*d, "height_m", c.display.height_m);
        keys.read(*d, "distance_m", c.display.distance_m);
        c.display.width_px = static_cast<int>(std::clamp<int64_t>(w, 0, 1 << 20));
        c.display.height_px = static_cast<int>(std::clamp<int64_t>(h, 0, 1 << 20));
    }
    if (!keys.result().ok()) return keys.result().error();
    c.seed = static_cast<uint64_t>(seed);
    c.counter_bits = static_cast<int>(bits);
    if (auto v = validate(c); !v.ok()) return v.error();
    return c;
}

class SimDriver final : public Driver {
public:
    SimDriver(const SimConfig& config, uint32_t device_id)
        : config_(config), device_id_(device_id) {}
    ~SimDriver() override { close(); }

    Result<void> open(boost::asio::io_context& io, SampleSink sink) override {
        sink_ = std::move(sink);
        // The generator's true time starts now, so t_true_ns is comparable with host time.
        SimConfig c = config_;
        c.start_ns = monotonic_ns();
        tracker_.emplace(c);
        if (target_) tracker_->look_at(target_->first, target_->second);
        timer_.emplace(io);
        alive_ = std::make_shared<int>(0);
        start_ = std::chrono::steady_clock::now();
        emitted_ = 0;
        connected_ = true;
        logger()->info("sim tracker {} Hz, seed {}", config_.rate_hz, config_.seed);
        schedule(start_);
        return {};
    }

    void close() override {
        alive_.reset();  // handlers already queued see the token expire and return
        if (timer_) timer_->cancel();
        timer_.reset();
        connected_ = false;
    }

    DriverInfo describe() const override {
        DriverInfo info;
        info.driver = "sim";
        info.name = "Fovea simulated tracker (seed " + std::to_string(config_.seed) + ")";
        info.address = "sim:" + std::to_string(config_.seed);
        info.nominal_rate_hz = config_.rate_hz;
        info.clock = {config_.counter_bits, config_.tick_hz};
        info.binocular = config_.binocular;
        info.has_pupil = true;
        return info;
    }

    // The simulated eyes look where a calibration target is shown (tracker_.hpp, look_at).
    bool follow_target(bool shown, double x, double y) override {
        if (shown && std::isfinite(x) && std::isfinite(y)) {
            double dx = 0, dy = 0;
            config_.display.to_degrees(x, y, dx, dy);
            target_.emplace(dx, dy);
            if (tracker_) tracker_->look_at(dx, dy);
        } else {
            target_.reset();
            if (tracker_) tracker_->release();
        }
        return true;
    }

    DriverStats stats() const override {
        DriverStats s;
        s.samples = samples_.load(std::memory_order_relaxed);
        s.frames_lost = lost_.load(std::memory_order_relaxed);
        s.connected = connected_.load(std::memory_order_relaxed);
        return s;
    }

private:
    // Sample n is due at start_ + n / rate: deadlines are absolute, so the rate never drifts.
    std::chrono::steady_clock::time_point due(uint64_t n) const {
        return start_ + std::chrono::nanoseconds(static_cast<int64_t>(n * 1e9 / config_.rate_hz));
    }

    void schedule(std::chrono::steady_clock::time_point at) {
        timer_->expires_at(at);
        timer_->async_wait(
            [this, token = std::weak_ptr<int>(alive_)](boost::system::error_code ec) {
                if (ec || token.expired()) return;
                on_tick();
            });
    }

    void on_tick() {
        const auto now = std::chrono::steady_clock::now();
        if (now - due(emitted_) > kMaxLag) {
            // The loop was blocked (debugger, suspend): skip the backlog and count it as lost.
            uint64_t skip = 0;
            while (now - due(emitted_ + skip) > kMinBatch) ++skip;
            for (uint64_t i = 0; i < skip; ++i) tracker_->next();
            emitted_ += skip;
            lost_ += skip;
            logger()->warn("loop stalled: skipped {} samples", skip);
        }
        const int64_t t_receive = monotonic_ns();
        const std::weak_ptr<int> token = alive_;
        while (due(emitted_) <= now) {
            SimTracker::Frame f = tracker_->next();
            f.raw.t_receive_ns = t_receive;
            f.raw.device_id = device_id_;
            ++emitted_;
            samples_.fetch_add(1, std::memory_order_relaxed);
            sink_(f.raw);
            if (token.expired()) return;  // the sink closed us
        }
        schedule(std::max(due(emitted_), now + kMinBatch));
    }

    SimConfig config_;
    uint32_t device_id_;
    SampleSink sink_;
    std::optional<SimTracker> tracker_;
    std::optional<std::pair<double, double>> target_;  // degrees; kept across close()/open()
    std::optional<boost::asio::steady_timer> timer_;
    std::shared_ptr<int> alive_;
    std::chrono::steady_clock::time_point start_;
    uint64_t emitted_ = 0;
    std::atomic<uint64_t> samples_{0}, lost_{0};
    std::atomic<bool> connected_{false};
};

}  // namespace

Result<std::unique_ptr<Driver>> make_driver(const toml::table& config, uint32_t device_id) {
    auto c = parse_config(config);
    if (!c.ok()) return c.error();
    return std::unique_ptr<Driver>(std::make_unique<SimDriver>(*c, device_id));
}

}  // namespace fovea::drivers::sim
