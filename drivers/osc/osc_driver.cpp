// The osc driver: a liblo server on a UDP port, its socket watched by the loop (Asio waits for
// readability, liblo parses and dispatches), every message through the FrameAssembler. liblo's
// error handler has no user data: the driver being drained is held in a thread-local.
#include "osc/osc_driver.hpp"

#include <lo/lo.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <mutex>
#include <optional>

#include <boost/asio/posix/stream_descriptor.hpp>

#include "fovea/drivers/rate_meter.hpp"
#include "fovea/drivers/support.hpp"
#include "osc/osc_map.hpp"

namespace fovea::drivers::osc {
namespace {

std::shared_ptr<spdlog::logger> logger() {
    static const auto log = driver_logger("osc");  // FOVEA_LOG_DRV_OSC=debug
    return log;
}

class OscDriver;
thread_local OscDriver* t_draining = nullptr;

class OscDriver final : public Driver {
public:
    OscDriver(AddressMap map, int port, double rate_hz, uint32_t device_id)
        : assembler_(std::move(map)), port_(port), rate_hz_(rate_hz), device_id_(device_id) {}
    ~OscDriver() override { close(); }

    Result<void> open(boost::asio::io_context& io, SampleSink sink) override {
        sink_ = std::move(sink);
        const std::string port = std::to_string(port_);
        server_ = lo_server_new_with_proto(port_ == 0 ? nullptr : port.c_str(), LO_UDP, &on_error);
        if (!server_) return make_error("osc: cannot listen on UDP port " + port + " (in use?)");
        lo_server_add_method(server_, nullptr, nullptr, &on_message, this);
        {
            std::lock_guard lock(mutex_);
            bound_port_ = lo_server_get_port(server_);
            stats_.connected = true;
        }
        socket_.emplace(io, lo_server_get_socket_fd(server_));
        alive_ = std::make_shared<int>(0);
        logger()->info("listening for OSC ({}) on UDP port {}", assembler_.map().preset,
                       bound_port_);
        wait();
        return {};
    }

    void close() override {
        alive_.reset();
        if (socket_) {
            boost::system::error_code ignored;
            socket_->cancel(ignored);
            socket_->release();  // liblo owns the fd
            socket_.reset();
        }
        if (server_) lo_server_free(server_);
        server_ = nullptr;
        std::lock_guard lock(mutex_);
        stats_.connected = false;
    }

    DriverInfo describe() const override {
        std::lock_guard lock(mutex_);
        DriverInfo info;
        info.driver = "osc";
        info.name = "OSC eye tracker (" + assembler_.map().preset +
                    "; no device clock: stamped on receipt)";
        info.address = "udp:" + std::to_string(bound_port_ ? bound_port_ : port_);
        info.nominal_rate_hz = rate_hz_ > 0 ? rate_hz_ : rate_.rate_hz();
        info.clock = {64, 1e9, true, 0.0};  // receipt time is the only clock
        info.binocular = true;
        info.has_pupil = false;
        return info;
    }

    DriverStats stats() const override {
        std::lock_guard lock(mutex_);
        DriverStats s = stats_;
        s.figures["port"] = bound_port_;
        s.figures["unmapped_messages"] = static_cast<double>(unmapped_);
        s.figures["blink_samples"] = static_cast<double>(closed_);
        if (std::isfinite(assembler_.pupil_dilation()))
            s.figures["pupil_dilation"] = assembler_.pupil_dilation();
        s.notes["clock"] = "none in OSC: samples are stamped when they arrive";
        return s;
    }

private:
    void wait() {
        socket_->async_wait(
            boost::asio::posix::stream_descriptor::wait_read,
            [this, token = std::weak_ptr<int>(alive_)](boost::system::error_code ec) {
                if (ec || token.expired()) return;
                drain(token);
                if (!token.expired()) wait();
            });
    }

    void drain(const std::weak_ptr<int>& token) {
        t_draining = this;
        while (!token.expired() && server_ && lo_server_recv_noblock(server_, 0) > 0) {}
        t_draining = nullptr;
    }

    static void on_error(int num, const char* msg, const char* where) {
        if (OscDriver* d = t_draining) {
            std::lock_guard lock(d->mutex_);
            ++d->stats_.frames_dropped;
            d->limiter_.warn(std::string("osc: malformed packet (") + std::to_string(num) + " " +
                             (msg ? msg : "") + (where ? std::string(" at ") + where : "") + ")");
        }
    }

    static int on_message(const char* path, const char* types, lo_arg** argv, int argc, lo_message,
                          void* user) {
        static_cast<OscDriver*>(user)->handle(path, types, argv, argc);
        return 0;
    }

    void handle(const char* path, const char* types, lo_arg** argv, int argc) {
        const int64_t t_receive = monotonic_ns();
        arguments_as_numbers(types, argv, argc, values_);
        std::optional<gaze::RawSample> s;
        const bool mapped = assembler_.message(path, values_, s);
        {
            std::lock_guard lock(mutex_);
            stats_.bytes += std::strlen(path) + 4 * static_cast<uint64_t>(argc);
            if (!mapped) {
                ++unmapped_;
                return;
            }
            if (!s) return;
            ++stats_.samples;
            if (!s->left.valid && !s->right.valid) ++closed_;
            rate_.add(static_cast<double>(t_receive) * 1e-9);
        }
        s->device_ticks = static_cast<uint64_t>(t_receive);
        s->t_receive_ns = t_receive;
        s->device_id = device_id_;
        sink_(*s);
    }

    FrameAssembler assembler_;
    int port_;
    double rate_hz_;
    uint32_t device_id_;
    SampleSink sink_;
    lo_server server_ = nullptr;
    std::optional<boost::asio::posix::stream_descriptor> socket_;
    std::shared_ptr<int> alive_;
    std::vector<double> values_;
    mutable std::mutex mutex_;  // guards what follows
    RateMeter rate_;
    DriverStats stats_;
    int bound_port_ = 0;
    uint64_t unmapped_ = 0, closed_ = 0;
    LogLimiter limiter_{logger()};
};

}  // namespace

Result<std::unique_ptr<Driver>> make_driver(const toml::table& config, uint32_t device_id) {
    auto map = parse_address_map(config);
    if (!map) return map.error();
    int64_t port = 9000;
    double rate = 0.0;  // measured
    if (auto r = read_key("osc", config, "port", port); !r) return r.error();
    if (auto r = read_key("osc", config, "rate_hz", rate); !r) return r.error();
    if (port < 0 || port > 65535) return make_error("osc: port must be 0..65535");
    if (!(rate >= 0 && rate <= 2000))
        return make_error("osc: rate_hz must be 1..2000 (or 0: measured)");
    return std::unique_ptr<Driver>(
        std::make_unique<OscDriver>(std::move(*map), static_cast<int>(port), rate, device_id));
}

}  // namespace fovea::drivers::osc
