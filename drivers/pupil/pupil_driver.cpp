// The pupil driver. ZeroMQ sockets are not Asio objects, so one worker thread owns them (as
// DESIGN.md §4 does for hidapi and libusb) and posts samples into the loop: it asks Pupil
// Remote for the bus port and version, syncs the clock by "t" round trips (again every
// sync_interval_s), subscribes to the topics, decodes each message (pupil_bus.hpp: fovea::import's
// Pupil decoder, msgpack-cxx) and maps Pupil time to host time with the measured offset. Capture
// closing or restarting shows as a silent bus and an unanswered Remote: the worker drops both
// sockets and reconnects with backoff, counting it.
#include "pupil/pupil_driver.hpp"

#include <zmq.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <thread>

#include <boost/asio/post.hpp>

#include "fovea/drivers/rate_meter.hpp"
#include "fovea/drivers/support.hpp"
#include "pupil/pupil_bus.hpp"
#include "pupil/pupil_remote.hpp"

namespace fovea::drivers::pupil {
namespace {

constexpr int kPollMs = 50;

std::shared_ptr<spdlog::logger> logger() {
    static const auto log = driver_logger("pupil");  // FOVEA_LOG_DRV_PUPIL=debug
    return log;
}

class PupilDriver final : public Driver {
public:
    PupilDriver(const PupilConfig& config, uint32_t device_id)
        : config_(config), device_id_(device_id) {}
    ~PupilDriver() override { close(); }

    Result<void> open(boost::asio::io_context& io, SampleSink sink) override {
        io_ = &io;
        sink_ = std::move(sink);
        alive_ = std::make_shared<int>(0);
        context_ = zmq_ctx_new();
        if (!context_) return make_error(std::string("pupil: zmq context: ") + zmq_strerror(errno));
        stop_ = false;
        worker_ = std::thread([this, token = std::weak_ptr<int>(alive_)] { run(token); });
        return {};
    }

    void close() override {
        alive_.reset();
        if (!worker_.joinable()) return;
        stop_ = true;
        zmq_ctx_shutdown(context_);  // wakes every blocking call of the worker with ETERM
        wake_.notify_all();
        worker_.join();
        zmq_ctx_term(context_);
        context_ = nullptr;
        std::lock_guard lock(mutex_);
        stats_.connected = false;
    }

    DriverInfo describe() const override {
        std::lock_guard lock(mutex_);
        DriverInfo info;
        info.driver = "pupil";
        info.name = "Pupil Capture" + (version_.empty() ? std::string() : " " + version_);
        info.address = config_.address;
        info.nominal_rate_hz = config_.rate_hz > 0 ? config_.rate_hz : rate_.rate_hz();
        info.clock = {64, 1e9, true, offset_ ? offset_->uncertainty_s * 1e6 : 0.0};
        info.binocular = true;
        info.has_pupil = true;
        return info;
    }

    DriverStats stats() const override {
        std::lock_guard lock(mutex_);
        DriverStats s = stats_;
        if (offset_) {
            s.figures["clock_offset_s"] = offset_->offset_s;
            s.figures["clock_uncertainty_us"] = offset_->uncertainty_s * 1e6;
            s.figures["clock_offset_sd_us"] = offset_->sd_s * 1e6;
            s.figures["sync_rtt_us"] = offset_->median_rtt_s * 1e6;
        }
        s.figures["clock_syncs"] = static_cast<double>(syncs_);
        s.figures["low_confidence"] = static_cast<double>(low_confidence_);
        if (!version_.empty()) s.notes["version"] = version_;
        if (!bus_.empty()) s.notes["bus"] = bus_;
        s.notes["clock"] = config_.set_pupil_clock ? "Pupil time set to host time (T)"
                                                   : "Pupil time mapped by t round trips";
        return s;
    }

private:
    struct Sockets {
        std::unique_ptr<RemoteClient> remote;
        void* sub = nullptr;
        ~Sockets() {
            if (sub) zmq_close(sub);
        }
    };

    void run(std::weak_ptr<int> token) {
        auto backoff = std::chrono::milliseconds(config_.reconnect_min_ms);
        bool ever = false;
        while (!stop_) {
            Sockets s;
            if (auto ok = connect(s); !ok) {
                fail(ok.error().message);
                std::unique_lock lock(wait_mutex_);
                wake_.wait_for(lock, backoff, [this] { return stop_.load(); });
                backoff =
                    std::min(backoff * 2, std::chrono::milliseconds(config_.reconnect_max_ms));
                continue;
            }
            backoff = std::chrono::milliseconds(config_.reconnect_min_ms);
            {
                std::lock_guard lock(mutex_);
                if (ever) ++stats_.reconnects;
                stats_.connected = true;
                stats_.last_error.clear();
            }
            ever = true;
            logger()->info(
                "connected to Pupil {} at {} (bus {}), clock offset {:.6f} s +- {:.0f} us",
                version_, config_.address, bus_, offset_->offset_s, offset_->uncertainty_s * 1e6);
            const std::string why = stream(s, token);
            if (stop_) break;
            fail(why);
        }
    }

    void fail(const std::string& why) {
        std::lock_guard lock(mutex_);
        if (why != stats_.last_error) logger()->warn("{}", why);
        stats_.connected = false;
        stats_.last_error = why;
    }

    Result<void> connect(Sockets& s) {
        auto remote = RemoteClient::connect(context_, config_.address, config_.request_timeout_ms);
        if (!remote) return remote.error();
        s.remote = std::move(*remote);
        auto port = s.remote->request("SUB_PORT");
        if (!port) return port.error();
        auto bus = bus_address(config_.address, *port);
        if (!bus) return make_error("Pupil Remote " + config_.address + ": " + bus.error().message);
        auto version = s.remote->request("v");
        if (!version) return version.error();
        if (config_.set_pupil_clock) {
            auto t = s.remote->request("T " + std::to_string(host_seconds()));
            if (!t) return t.error();
        }
        if (auto c = sync(s); !c) return c;
        s.sub = zmq_socket(context_, ZMQ_SUB);
        if (!s.sub) return make_error(std::string("zmq SUB socket: ") + zmq_strerror(zmq_errno()));
        const int zero = 0, hwm = 100'000;
        zmq_setsockopt(s.sub, ZMQ_LINGER, &zero, sizeof zero);
        zmq_setsockopt(s.sub, ZMQ_RCVHWM, &hwm, sizeof hwm);
        for (const auto& t : config_.topics)
            zmq_setsockopt(s.sub, ZMQ_SUBSCRIBE, t.data(), t.size());
        if (zmq_connect(s.sub, bus->c_str()) != 0)
            return make_error("Pupil bus " + *bus + ": " + zmq_strerror(zmq_errno()));
        std::lock_guard lock(mutex_);
        version_ = *version;
        bus_ = *bus;
        return {};
    }

    Result<void> sync(Sockets& s) {
        auto c = s.remote->sync(config_.sync_rounds);
        if (!c) return c.error();
        std::lock_guard lock(mutex_);
        offset_ = *c;
        ++syncs_;
        next_sync_ = std::chrono::steady_clock::now() +
                     std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                         std::chrono::duration<double>(config_.sync_interval_s));
        return {};
    }

    // Receives until the connection is lost; returns why.
    std::string stream(Sockets& s, const std::weak_ptr<int>& token) {
        auto last_datum = std::chrono::steady_clock::now();
        std::vector<std::string> frames;
        while (!stop_) {
            zmq_pollitem_t item{s.sub, 0, ZMQ_POLLIN, 0};
            const int n = zmq_poll(&item, 1, kPollMs);
            if (n < 0) return std::string("Pupil bus: ") + zmq_strerror(zmq_errno());
            const auto now = std::chrono::steady_clock::now();
            if (n > 0) {
                if (!receive(s.sub, frames))
                    return std::string("Pupil bus: ") + zmq_strerror(zmq_errno());
                last_datum = now;
                handle(frames, token);
            }
            if (now >= next_sync_) {
                if (auto r = sync(s); !r) return r.error().message;
            }
            if (now - last_datum > std::chrono::duration<double>(config_.silence_s)) {
                // A quiet bus is fine while Pupil Remote still answers with the same bus port
                // (nobody wearing it); a new port means Capture restarted.
                auto port = s.remote->request("SUB_PORT");
                if (!port) return "Pupil Capture gone: " + port.error().message;
                auto bus = bus_address(config_.address, *port);
                if (!bus) return "Pupil Remote " + config_.address + ": " + bus.error().message;
                if (*bus != bus_) return "Pupil Capture restarted (bus now on port " + *port + ")";
                last_datum = now;
            }
        }
        return "stopped";
    }

    static bool receive(void* sub, std::vector<std::string>& frames) {
        frames.clear();
        for (int more = 1; more;) {
            zmq_msg_t msg;
            zmq_msg_init(&msg);
            if (zmq_msg_recv(&msg, sub, 0) < 0) {
                zmq_msg_close(&msg);
                return false;
            }
            if (frames.size() < 2)  // [topic, datum, raw frames...]: raw frames are not used
                frames.emplace_back(static_cast<const char*>(zmq_msg_data(&msg)),
                                    zmq_msg_size(&msg));
            more = zmq_msg_more(&msg);
            zmq_msg_close(&msg);
        }
        return true;
    }

    void handle(const std::vector<std::string>& frames, const std::weak_ptr<int>& token) {
        const int64_t t_receive = monotonic_ns();
        {
            std::lock_guard lock(mutex_);
            for (const auto& f : frames) stats_.bytes += f.size();
        }
        const BusMessage m = decode_bus_message(frames, config_.min_confidence);
        if (m.kind == BusMessage::Kind::kOther) return;  // blinks, notifications: not samples
        if (m.kind == BusMessage::Kind::kMalformed) return drop(m.why);
        gaze::RawSample s = m.sample;
        double offset_s = 0;
        {
            std::lock_guard lock(mutex_);
            offset_s = offset_ ? offset_->offset_s : 0.0;
            if (!s.left.valid && !s.right.valid) ++low_confidence_;
            ++stats_.samples;
            rate_.add(m.pupil_time_s);  // Pupil time: capture times, free of network jitter
        }
        s.device_ticks = host_ticks(m.pupil_time_s, offset_s);
        s.t_receive_ns = t_receive;
        s.device_id = device_id_;
        boost::asio::post(*io_, [this, token, s] {
            if (!token.expired()) sink_(s);
        });
    }

    void drop(const std::string& why) {
        std::lock_guard lock(mutex_);
        ++stats_.frames_dropped;
        limiter_.warn(why);
    }

    PupilConfig config_;
    uint32_t device_id_;
    boost::asio::io_context* io_ = nullptr;
    SampleSink sink_;
    std::shared_ptr<int> alive_;
    void* context_ = nullptr;
    std::thread worker_;
    std::atomic<bool> stop_{false};
    std::mutex wait_mutex_;
    std::condition_variable wake_;
    std::chrono::steady_clock::time_point next_sync_{};  // worker thread only
    mutable std::mutex mutex_;                           // guards what follows
    RateMeter rate_;
    DriverStats stats_;
    std::optional<ClockOffset> offset_;
    std::string version_, bus_;
    uint64_t syncs_ = 0, low_confidence_ = 0;
    LogLimiter limiter_{logger()};
};

}  // namespace

Result<PupilConfig> parse_config(const toml::table& t) {
    PupilConfig c;
    ConfigKeys keys("pupil", t);
    int64_t rounds = c.sync_rounds, timeout = c.request_timeout_ms, rmin = c.reconnect_min_ms,
            rmax = c.reconnect_max_ms;
    keys.read("address", c.address);
    keys.read("min_confidence", c.min_confidence);
    keys.read("rate_hz", c.rate_hz);
    keys.read("sync_interval_s", c.sync_interval_s);
    keys.read("sync_rounds", rounds);
    keys.read("set_pupil_clock", c.set_pupil_clock);
    keys.read("request_timeout_ms", timeout);
    keys.read("silence_s", c.silence_s);
    keys.read("reconnect_min_ms", rmin);
    keys.read("reconnect_max_ms", rmax);
    if (!keys.result().ok()) return keys.result().error();
    if (const toml::node* n = t.get("topics")) {
        const toml::array* a = n->as_array();
        if (!a || a->empty())
            return make_error("pupil: topics must be a non-empty array of strings");
        c.topics.clear();
        for (const auto& e : *a) {
            const auto s = e.value<std::string>();
            if (!s || s->empty())
                return make_error("pupil: topics must be a non-empty array of strings");
            c.topics.push_back(*s);
        }
    }
    if (c.address.rfind("tcp://", 0) != 0 || c.address.rfind(':') <= 6)
        return make_error("pupil: address must be \"tcp://HOST:PORT\", got '" + c.address + "'");
    if (!(c.min_confidence >= 0 && c.min_confidence <= 1))
        return make_error("pupil: min_confidence must be 0..1");
    if (!(c.rate_hz >= 0 && c.rate_hz <= 2000))
        return make_error("pupil: rate_hz must be 1..2000 (or 0: measured)");
    if (!(c.sync_interval_s >= 0.1 && c.sync_interval_s <= 3600))
        return make_error("pupil: sync_interval_s must be 0.1..3600");
    if (rounds < 3 || rounds > 1000) return make_error("pupil: sync_rounds must be 3..1000");
    if (timeout < 10 || timeout > 60'000)
        return make_error("pupil: request_timeout_ms must be 10..60000");
    if (!(c.silence_s >= 0.1)) return make_error("pupil: silence_s must be >= 0.1");
    if (rmin < 1 || rmax < rmin)
        return make_error("pupil: need 1 <= reconnect_min_ms <= reconnect_max_ms");
    c.sync_rounds = static_cast<int>(rounds);
    c.request_timeout_ms = static_cast<int>(timeout);
    c.reconnect_min_ms = static_cast<int>(rmin);
    c.reconnect_max_ms = static_cast<int>(rmax);
    return c;
}

Result<std::unique_ptr<Driver>> make_driver(const toml::table& config, uint32_t device_id) {
    auto c = parse_config(config);
    if (!c) return c.error();
    return std::unique_ptr<Driver>(std::make_unique<PupilDriver>(*c, device_id));
}

}  // namespace fovea::drivers::pupil
