// The Gazepoint driver: connect, enable the fields we use (ENABLE_SEND_DATA last), parse REC
// elements as they arrive, count CNT gaps, reconnect with backoff when the server goes away.
#include "gazepoint/gazepoint_driver.hpp"

#include "fovea/drivers/rate_meter.hpp"
#include "fovea/drivers/reconnecting_driver.hpp"
#include "fovea/drivers/support.hpp"

#include <time.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <mutex>
#include <optional>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/write.hpp>

namespace fovea::drivers::gazepoint {
namespace {

using boost::asio::ip::tcp;
constexpr auto kConnectTimeout = std::chrono::seconds(2);

std::shared_ptr<spdlog::logger> logger() {
    static const auto log = driver_logger("gazepoint");  // FOVEA_LOG_DRV_GAZEPOINT=debug
    return log;
}

class GazepointDriver final : public ReconnectingDriver {
public:
    GazepointDriver(const GazepointConfig& config, uint32_t device_id)
        : ReconnectingDriver(device_id, config.reconnect_min_ms, config.reconnect_max_ms),
          config_(config) {}
    ~GazepointDriver() override { close(); }

    DriverInfo describe() const override {
        std::lock_guard lock(mutex_);
        DriverInfo info;
        info.driver = "gazepoint";
        info.name = "Gazepoint (Open Gaze API)";
        info.address = config_.host + ":" + config_.port;
        info.nominal_rate_hz = config_.rate_hz > 0 ? config_.rate_hz : rate_.rate_hz();
        info.clock = {64, clock_.tick_hz > 0 ? clock_.tick_hz : config_.tick_hz};
        info.binocular = config_.gaze == GazeSource::kEyes;
        info.has_pupil = true;
        return info;
    }

private:
    void on_open(boost::asio::io_context& io) override {
        connect_timer_.emplace(io);
        resolver_.emplace(io);
    }

    void on_close() override {
        if (connect_timer_) connect_timer_->cancel();
        if (resolver_) resolver_->cancel();
        drop_socket();
        connect_timer_.reset();
        resolver_.reset();
    }

    void connect() override {
        ++generation_;
        resolver_->async_resolve(
            config_.host, config_.port,
            [this, token = reconnect_.token(), gen = generation_](
                boost::system::error_code ec, tcp::resolver::results_type results) {
                if (token.expired() || gen != generation_) return;
                if (ec) {
                    fail("resolve " + config_.host + ": " + ec.message());
                    return;
                }
                socket_.emplace(io());
                connect_timer_->expires_after(kConnectTimeout);
                connect_timer_->async_wait([this, token, gen](boost::system::error_code tec) {
                    if (tec || token.expired() || gen != generation_) return;
                    if (socket_) socket_->close();  // completes the connect with an error
                });
                boost::asio::async_connect(
                    *socket_, results,
                    [this, token, gen](boost::system::error_code cec, const tcp::endpoint&) {
                        if (token.expired() || gen != generation_) return;
                        connect_timer_->cancel();
                        if (cec) {
                            fail("connect " + address() + ": " + cec.message());
                            return;
                        }
                        on_connected();
                    });
            });
    }

    void on_connected() {
        boost::system::error_code ignored;
        socket_->set_option(tcp::no_delay(true), ignored);
        stream_.reset();
        have_cnt_ = false;
        {
            std::lock_guard lock(mutex_);
            count_connected_locked();
            stats_.last_error.clear();
            clock_ = {};
        }
        logger()->info("connected to {}", address());
        auto cmds = std::make_shared<std::string>();
        for (const auto& c : startup_commands()) *cmds += format_element(c);
        boost::asio::async_write(*socket_, boost::asio::buffer(*cmds),
                                 [cmds](boost::system::error_code, std::size_t) {});
        read();
    }

    void read() {
        socket_->async_read_some(boost::asio::buffer(buffer_),
                                 [this, token = reconnect_.token(), gen = generation_](
                                     boost::system::error_code ec, std::size_t n) {
                                     if (token.expired() || gen != generation_ || !socket_) return;
                                     if (ec) {
                                         logger()->warn("{}: connection lost ({}); reconnecting",
                                                        address(), ec.message());
                                         fail(address() + ": " + ec.message());
                                         return;
                                     }
                                     on_bytes(n);
                                     if (!token.expired() && gen == generation_ && socket_) read();
                                 });
    }

    void on_bytes(std::size_t n) {
        const int64_t t_receive = monotonic_ns();
        const auto token = reconnect_.token();
        const auto before = stream_.stats();
        stream_.feed(std::string_view(buffer_.data(), n), [&](const Element& e) {
            if (!token.expired()) on_element(e, t_receive);
        });
        const auto& after = stream_.stats();
        std::lock_guard lock(mutex_);
        stats_.bytes += n;
        stats_.frames_dropped += after.dropped - before.dropped;
        stats_.resyncs += after.resyncs - before.resyncs;
        if (after.garbage_bytes != before.garbage_bytes) {
            bad_.warn(address() + ": skipped " +
                      std::to_string(after.garbage_bytes - before.garbage_bytes) +
                      " bytes of garbage");
        }
    }

    void on_element(const Element& e, int64_t t_receive) {
        if (e.tag == "ACK") {
            const std::string* id = e.get("ID");
            if (id && *id == "TIME_TICK_FREQUENCY") {
                const std::string* f = e.get("FREQ");
                const double hz = f ? std::strtod(f->c_str(), nullptr) : 0.0;
                std::lock_guard lock(mutex_);
                if (hz > 0 && std::isfinite(hz)) clock_.tick_hz = hz;
            }
            return;
        }
        if (e.tag == "NACK") {
            const std::string* id = e.get("ID");
            logger()->info("{}: server does not support {}", address(), id ? *id : "?");
            return;
        }
        if (e.tag != "REC") return;  // CAL and other records are not gaze
        std::optional<uint64_t> cnt;
        std::string why;
        ServerClock clock;
        {
            std::lock_guard lock(mutex_);
            clock = clock_;
        }
        auto s = decode_record(e, clock, config_.gaze, &cnt, &why);
        {
            std::lock_guard lock(mutex_);
            if (cnt) {
                // CNT counts records at the server: a jump forward is that many lost.
                if (have_cnt_ && *cnt > last_cnt_ && *cnt - last_cnt_ < (1u << 30))
                    stats_.frames_lost += *cnt - last_cnt_ - 1;
                have_cnt_ = true;
                last_cnt_ = *cnt;
            }
            if (!s) {
                ++stats_.frames_dropped;
            } else {
                ++stats_.samples;
                update_rate(s->device_ticks);
            }
        }
        if (!s) {
            bad_.warn(address() + ": dropped a record (" + why + ")");
            return;
        }
        deliver(*s, t_receive);
    }

    // The record's device time into the rate meter (mutex held).
    void update_rate(uint64_t ticks) {
        const double hz = clock_.tick_hz > 0 ? clock_.tick_hz : 1e6;
        rate_.add(static_cast<double>(ticks) / hz);
    }

    void fail(const std::string& why) {
        set_error(why);
        connect_failures_.warn(why + "; retrying");
        drop_socket();
        reconnect_.retry_later();
    }

    void drop_socket() {
        ++generation_;  // late completions of this socket's operations are ignored
        if (socket_) {
            boost::system::error_code ignored;
            socket_->shutdown(tcp::socket::shutdown_both, ignored);
            socket_->close(ignored);
            socket_.reset();
        }
        stream_.reset();
        if (mark_disconnected()) reconnect_.reset_delay();  // it was up: start again at the minimum
    }

    std::string address() const { return config_.host + ":" + config_.port; }

    GazepointConfig config_;
    std::optional<tcp::resolver> resolver_;
    std::optional<tcp::socket> socket_;
    std::optional<boost::asio::steady_timer> connect_timer_;
    std::array<char, 8192> buffer_{};
    ElementStream stream_;
    uint64_t generation_ = 0;
    bool have_cnt_ = false;
    uint64_t last_cnt_ = 0;
    LogLimiter connect_failures_{logger()}, bad_{logger()};

    // Guarded by mutex_ with the stats (any-thread readers):
    ServerClock clock_;
    RateMeter rate_;
};

}  // namespace

Result<GazepointConfig> parse_config(const toml::table& t) {
    GazepointConfig c;
    std::string address = c.host + ":" + c.port, gaze = "eyes";
    int64_t rmin = c.reconnect_min_ms, rmax = c.reconnect_max_ms;
    ConfigKeys keys("gazepoint", t);
    keys.read("address", address);
    keys.read("gaze", gaze);
    keys.read("rate_hz", c.rate_hz);
    keys.read("reconnect_min_ms", rmin);
    keys.read("reconnect_max_ms", rmax);
    keys.read("tick_hz", c.tick_hz);
    if (!keys.result().ok()) return keys.result().error();
    if (!(c.tick_hz >= 1 && c.tick_hz <= 1e10))
        return make_error("gazepoint: tick_hz must be 1..1e10");
    // host:port, [v6]:port, or a bare host (default port).
    std::string host = address, port = std::to_string(kDefaultPort);
    if (!address.empty() && address.front() == '[') {
        const auto close = address.find(']');
        if (close == std::string::npos)
            return make_error("gazepoint: bad address '" + address + "'");
        host = address.substr(1, close - 1);
        if (close + 1 < address.size()) {
            if (address[close + 1] != ':')
                return make_error("gazepoint: bad address '" + address + "'");
            port = address.substr(close + 2);
        }
    } else if (const auto colon = address.rfind(':'); colon != std::string::npos) {
        host = address.substr(0, colon);
        port = address.substr(colon + 1);
    }
    const long p = std::strtol(port.c_str(), nullptr, 10);
    if (host.empty() || p <= 0 || p > 65535 ||
        port.find_first_not_of("0123456789") != std::string::npos)
        return make_error("gazepoint: address must be host:port (e.g. \"127.0.0.1:4242\"), got '" +
                          address + "'");
    if (gaze != "eyes" && gaze != "best")
        return make_error("gazepoint: gaze must be \"eyes\" or \"best\", got '" + gaze + "'");
    if (c.rate_hz < 0 || c.rate_hz > 10000)
        return make_error("gazepoint: rate_hz must be 0..10000");
    if (auto v = check_reconnect_range("gazepoint", rmin, rmax); !v.ok()) return v.error();
    c.host = host;
    c.port = port;
    c.gaze = gaze == "best" ? GazeSource::kBest : GazeSource::kEyes;
    c.reconnect_min_ms = static_cast<int>(rmin);
    c.reconnect_max_ms = static_cast<int>(rmax);
    return c;
}

std::unique_ptr<Driver> make_gazepoint_driver(const GazepointConfig& config, uint32_t device_id) {
    return std::make_unique<GazepointDriver>(config, device_id);
}

Result<std::unique_ptr<Driver>> make_driver(const toml::table& config, uint32_t device_id) {
    auto c = parse_config(config);
    if (!c.ok()) return c.error();
    return make_gazepoint_driver(*c, device_id);
}

}  // namespace fovea::drivers::gazepoint
