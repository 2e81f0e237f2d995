// The serial driver: open the port, ask for the hello, parse frames as bytes arrive, reconnect
// with exponential backoff when the port goes away (unplugged, pty closed).
#include "serial/serial_driver.hpp"

#include "fovea/drivers/reconnecting_driver.hpp"
#include "fovea/drivers/support.hpp"

#include <sys/ioctl.h>
#include <time.h>

#include <array>
#include <chrono>
#include <cstdlib>
#include <mutex>
#include <optional>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <boost/asio/serial_port.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/write.hpp>

#include "serial/protocol.hpp"

namespace fovea::drivers::serial {
namespace {

constexpr auto kHelloRetry = std::chrono::milliseconds(250);

std::shared_ptr<spdlog::logger> logger() {
    static const auto log = driver_logger("serial");  // FOVEA_LOG_DRV_SERIAL=debug
    return log;
}

class SerialDriver final : public ReconnectingDriver {
public:
    SerialDriver(const SerialConfig& config, uint32_t device_id)
        : ReconnectingDriver(device_id, config.reconnect_min_ms, config.reconnect_max_ms),
          config_(config) {}
    ~SerialDriver() override { close(); }

    DriverInfo describe() const override {
        std::lock_guard lock(mutex_);
        DriverInfo info;
        info.driver = "serial";
        info.address = config_.port;
        info.name = hello_ ? hello_->name : "serial tracker (no hello yet)";
        info.nominal_rate_hz = hello_ ? hello_->rate_mhz / 1000.0 : config_.rate_hz;
        info.clock =
            hello_ ? gaze::DeviceClock{hello_->counter_bits, static_cast<double>(hello_->tick_hz)}
                   : gaze::DeviceClock{config_.counter_bits, config_.tick_hz};
        info.binocular = hello_ ? hello_->binocular : true;
        info.has_pupil = hello_ ? hello_->has_pupil : false;
        return info;
    }

private:
    void on_open(boost::asio::io_context& io) override { hello_timer_.emplace(io); }

    void on_close() override {
        if (hello_timer_) hello_timer_->cancel();
        drop_port();
        hello_timer_.reset();
    }

    void connect() override {
        boost::system::error_code ec;
        port_.emplace(io());
        port_->open(config_.port, ec);
        if (!ec) {
            // Keep a second process (another daemon, a terminal program) off the port.
            if (::ioctl(port_->native_handle(), TIOCEXCL) != 0) {
                ec.assign(errno, boost::system::system_category());
            }
        }
        if (!ec) port_->set_option(boost::asio::serial_port::baud_rate(config_.baud), ec);
        if (!ec) port_->set_option(boost::asio::serial_port::character_size(8), ec);
        if (!ec) {
            port_->set_option(boost::asio::serial_port::flow_control(
                                  boost::asio::serial_port::flow_control::none),
                              ec);
        }
        if (ec) {
            drop_port();
            set_error(config_.port + ": " + ec.message());
            open_failures_.warn("cannot open " + config_.port + ": " + ec.message() + "; retrying");
            reconnect_.retry_later();
            return;
        }
        ++generation_;
        decoder_.reset();
        sequence_.reset();
        {
            std::lock_guard lock(mutex_);
            count_connected_locked();
            hello_.reset();
        }
        logger()->info("{} open, {} baud", config_.port, config_.baud);
        request_hello();
        read();
    }

    void request_hello() {
        std::vector<uint8_t> bytes;
        encode_hello_request(host_seq_++, bytes);
        if (config_.rate_hz > 0) {
            Configure c;
            c.rate_mhz = static_cast<uint32_t>(std::lround(config_.rate_hz * 1000.0));
            encode_configure(c, host_seq_++, bytes);
        }
        send(std::move(bytes));
        hello_timer_->expires_after(kHelloRetry);
        hello_timer_->async_wait([this, token = reconnect_.token()](auto ec) {
            if (ec || token.expired() || !port_) return;
            bool have;
            {
                std::lock_guard lock(mutex_);
                have = hello_.has_value();
            }
            if (!have) request_hello();
        });
    }

    void send(std::vector<uint8_t> bytes) {
        auto buf = std::make_shared<std::vector<uint8_t>>(std::move(bytes));
        // A failed write shows up as a failed read too; `buf` lives until the write completes.
        boost::asio::async_write(*port_, boost::asio::buffer(*buf), [buf](auto, std::size_t) {});
    }

    void read() {
        port_->async_read_some(boost::asio::buffer(buffer_),
                               [this, token = reconnect_.token(), gen = generation_](
                                   boost::system::error_code ec, std::size_t n) {
                                   // A read of an earlier connection completing late: ignore.
                                   if (token.expired() || !port_ || gen != generation_) return;
                                   if (ec) {
                                       lost_port(ec.message());
                                       return;
                                   }
                                   on_bytes(n);
                                   if (!token.expired() && port_) read();
                               });
    }

    void on_bytes(std::size_t n) {
        const int64_t t_receive = monotonic_ns();
        {
            std::lock_guard lock(mutex_);
            stats_.bytes += n;
        }
        const auto token = reconnect_.token();
        decoder_.feed(
            std::span<const uint8_t>(buffer_.data(), n),
            [&](const Frame& f) {
                if (!token.expired()) on_frame(f, t_receive);
            },
            [&](FrameDecoder::Reject r) {
                {
                    std::lock_guard lock(mutex_);
                    ++stats_.frames_dropped;
                    stats_.resyncs = decoder_.stats().resyncs;
                }
                bad_frames_.warn(config_.port + ": dropped a frame (" + to_string(r) + ")");
            });
    }

    void on_frame(const Frame& f, int64_t t_receive) {
        const uint32_t missing = sequence_.on_seq(f.seq);
        std::string why;
        std::optional<gaze::RawSample> sample;
        {
            std::lock_guard lock(mutex_);
            stats_.frames_lost += missing;
            stats_.resyncs = decoder_.stats().resyncs;
            if (f.type == static_cast<uint8_t>(FrameType::kHello)) {
                if (auto h = decode_hello(f.payload, &why)) {
                    if (h->counter_bits != config_.counter_bits ||
                        h->tick_hz != static_cast<uint32_t>(config_.tick_hz)) {
                        bad_frames_.warn(config_.port +
                                         ": device clock differs from the configured "
                                         "counter_bits/tick_hz; set them in the [[device]] table");
                    }
                    if (!hello_) {
                        logger()->info("{}: '{}' protocol v{}, {} Hz, {}-bit counter at {} Hz",
                                       config_.port, h->name, h->protocol_version,
                                       h->rate_mhz / 1000.0, h->counter_bits, h->tick_hz);
                    }
                    hello_ = std::move(*h);
                    stats_.last_error.clear();
                    reconnect_.reset_delay();  // the device answers: the link works
                } else {
                    ++stats_.frames_dropped;
                }
            } else if (f.type == static_cast<uint8_t>(FrameType::kSample)) {
                sample = decode_sample(f.payload, &why);
                if (!sample) {
                    ++stats_.frames_dropped;
                } else if (!hello_) {
                    // Without the hello the counter width and tick rate are unknown.
                    ++stats_.frames_dropped;
                    why = "sample before hello";
                    sample.reset();
                } else {
                    if (hello_->counter_bits < 64)
                        sample->device_ticks &= (1ULL << hello_->counter_bits) - 1;
                    ++stats_.samples;
                }
            }
            // Unknown frame types are newer protocol features: skipped, not errors.
        }
        if (!why.empty()) bad_frames_.warn(config_.port + ": dropped a frame (" + why + ")");
        if (sample) { deliver(*sample, t_receive); }
    }

    void lost_port(const std::string& why) {
        logger()->warn("{}: lost ({}); reconnecting", config_.port, why);
        set_error(config_.port + ": " + why);
        drop_port();
        reconnect_.retry_later();
    }

    void drop_port() {
        if (port_) {
            boost::system::error_code ignored;
            port_->cancel(ignored);
            port_->close(ignored);
            port_.reset();
        }
        decoder_.reset();
        mark_disconnected();
    }

    SerialConfig config_;
    std::optional<boost::asio::serial_port> port_;
    std::optional<boost::asio::steady_timer> hello_timer_;
    std::array<uint8_t, 4096> buffer_{};
    FrameDecoder decoder_;
    SequenceTracker sequence_;
    uint16_t host_seq_ = 0;
    uint64_t generation_ = 0;  // connection number
    LogLimiter open_failures_{logger()}, bad_frames_{logger()};

    std::optional<Hello> hello_;  // guarded by mutex_ (describe() is any-thread)
};

}  // namespace

Result<SerialConfig> parse_config(const toml::table& t) {
    SerialConfig c;
    int64_t baud = c.baud, rmin = c.reconnect_min_ms, rmax = c.reconnect_max_ms;
    int64_t bits = c.counter_bits;
    ConfigKeys keys("serial", t);
    keys.read("port", c.port);
    keys.read("baud", baud);
    keys.read("rate_hz", c.rate_hz);
    keys.read("reconnect_min_ms", rmin);
    keys.read("reconnect_max_ms", rmax);
    keys.read("counter_bits", bits);
    keys.read("tick_hz", c.tick_hz);
    if (!keys.result().ok()) return keys.result().error();
    if (bits != 16 && bits != 32 && bits != 64)
        return make_error("serial: counter_bits must be 16, 32 or 64");
    if (!(c.tick_hz >= 1 && c.tick_hz <= 1e10))
        return make_error("serial: tick_hz must be 1..1e10");
    c.counter_bits = static_cast<int>(bits);
    if (c.port.empty())
        return make_error("serial: 'port' is required (e.g. port = \"/dev/ttyACM0\")");
    if (baud < 50 || baud > 20'000'000) return make_error("serial: baud must be 50..20000000");
    if (c.rate_hz != 0 && !(c.rate_hz >= 1 && c.rate_hz <= 10000))
        return make_error("serial: rate_hz must be 1..10000 (or 0 to keep the device's)");
    if (auto v = check_reconnect_range("serial", rmin, rmax); !v.ok()) return v.error();
    c.baud = static_cast<uint32_t>(baud);
    c.reconnect_min_ms = static_cast<int>(rmin);
    c.reconnect_max_ms = static_cast<int>(rmax);
    return c;
}

std::unique_ptr<Driver> make_serial_driver(const SerialConfig& config, uint32_t device_id) {
    return std::make_unique<SerialDriver>(config, device_id);
}

Result<std::unique_ptr<Driver>> make_driver(const toml::table& config, uint32_t device_id) {
    auto c = parse_config(config);
    if (!c.ok()) return c.error();
    return make_serial_driver(*c, device_id);
}

}  // namespace fovea::drivers::serial
