#include "zmq_publisher.hpp"

#include <zmq.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <string>

#include <boost/asio/steady_timer.hpp>

#include <spdlog/spdlog.h>

#include "daemon.hpp"

namespace fovea::daemon {
namespace {

constexpr int kLingerMs = 200;  // flush queued samples on shutdown, but never hang the stop

std::string last_endpoint(void* socket, const std::string& fallback) {
    char ep[256] = {};
    std::size_t len = sizeof ep;
    return zmq_getsockopt(socket, ZMQ_LAST_ENDPOINT, ep, &len) == 0 ? std::string(ep) : fallback;
}

// Pupil Remote requests are rare (a client asks once for the port); 20 Hz polling is plenty and
// keeps the REP socket out of the loop's readiness machinery.
constexpr auto kRemotePoll = std::chrono::milliseconds(50);

void poll_remote(std::weak_ptr<ZmqPublisher> weak,
                 std::shared_ptr<boost::asio::steady_timer> timer) {
    timer->expires_after(kRemotePoll);
    timer->async_wait([weak, timer](boost::system::error_code ec) {
        auto p = weak.lock();
        if (ec || !p) return;
        p->serve_remote();
        poll_remote(weak, timer);
    });
}

}  // namespace

Result<std::unique_ptr<ZmqPublisher>> ZmqPublisher::bind(const ZmqConfig& config) {
    std::unique_ptr<ZmqPublisher> p(new ZmqPublisher());
    p->context_ = zmq_ctx_new();
    if (!p->context_) return make_error(zmq_error("zmq: cannot create a context"));
    p->socket_ = zmq_socket(p->context_, ZMQ_PUB);
    if (!p->socket_) return make_error(zmq_error("zmq: cannot create a PUB socket"));
    p->send_hwm_ = config.send_hwm;
    const int linger = kLingerMs;
    if (zmq_setsockopt(p->socket_, ZMQ_SNDHWM, &p->send_hwm_, sizeof p->send_hwm_) != 0 ||
        zmq_setsockopt(p->socket_, ZMQ_LINGER, &linger, sizeof linger) != 0)
        return make_error(zmq_error("zmq: setsockopt"));
    if (zmq_bind(p->socket_, config.publish.c_str()) != 0)
        return make_error(zmq_error("zmq.publish: cannot bind " + config.publish));
    p->endpoint_ = last_endpoint(p->socket_, config.publish);
    if (!config.remote.empty()) {
        p->remote_ = zmq_socket(p->context_, ZMQ_REP);
        if (!p->remote_) return make_error(zmq_error("zmq: cannot create a REP socket"));
        const int zero = 0;
        zmq_setsockopt(p->remote_, ZMQ_LINGER, &zero, sizeof zero);
        if (zmq_bind(p->remote_, config.remote.c_str()) != 0)
            return make_error(zmq_error("zmq.remote: cannot bind " + config.remote));
        p->remote_endpoint_ = last_endpoint(p->remote_, config.remote);
    }
    return p;
}

ZmqPublisher::~ZmqPublisher() {
    if (remote_) zmq_close(remote_);
    if (socket_) zmq_close(socket_);
    if (context_) zmq_ctx_term(context_);
}

void ZmqPublisher::publish(const fovea_gaze_record& record) {
    const ZmqMessage m = encode_pupil_gaze(record);
    if (zmq_send(socket_, m.topic.data(), m.topic.size(), ZMQ_SNDMORE | ZMQ_DONTWAIT) < 0 ||
        zmq_send(socket_, m.payload.data(), m.payload.size(), ZMQ_DONTWAIT) < 0) {
        ++failed_;
        return;
    }
    ++sent_;
}

void ZmqPublisher::serve_remote() {
    if (!remote_) return;
    char buf[256];
    for (;;) {
        const int n = zmq_recv(remote_, buf, sizeof buf, ZMQ_DONTWAIT);
        if (n < 0) return;  // EAGAIN: nothing pending
        ++remote_requests_;
        const std::string cmd(buf, static_cast<std::size_t>(std::min<int>(n, sizeof buf)));
        std::string reply = "Unknown command.";
        if (cmd == "SUB_PORT") {
            reply = endpoint_.substr(endpoint_.rfind(':') + 1);
        } else if (cmd == "t") {
            timespec ts{};
            clock_gettime(CLOCK_MONOTONIC, &ts);  // the clock `timestamp` is in
            reply = std::to_string(static_cast<double>(ts.tv_sec) + ts.tv_nsec / 1e9);
        } else if (cmd == "v") {
            reply = "fovea";
        }
        zmq_send(remote_, reply.data(), reply.size(), ZMQ_DONTWAIT);
    }
}

nlohmann::json ZmqPublisher::status() const {
    nlohmann::json s = {
        {"endpoint", endpoint_}, {"send_hwm", send_hwm_}, {"sent", sent_}, {"failed", failed_}};
    if (remote_) {
        s["remote"] = remote_endpoint_;
        s["remote_requests"] = remote_requests_;
    }
    return s;
}

Result<void> attach_zmq_publisher(Daemon& daemon) {
    const ZmqConfig& cfg = daemon.config().zmq;
    if (cfg.publish.empty()) return {};
    auto pub = ZmqPublisher::bind(cfg);
    if (!pub) return pub.error();
    std::shared_ptr<ZmqPublisher> p = std::move(pub).value();
    spdlog::default_logger()->info("zmq: publishing Pupil-style gaze on {}", p->endpoint());
    daemon.add_published_observer(
        [p](const gaze::GazeSample&, const fovea_gaze_record& rec) { p->publish(rec); });
    daemon.add_status_section("zmq", [p] { return p->status(); });
    if (p->has_remote()) {
        spdlog::default_logger()->info("zmq: Pupil Remote on {}", p->remote_endpoint());
        poll_remote(p, std::make_shared<boost::asio::steady_timer>(daemon.io()));
    }
    return {};
}

}  // namespace fovea::daemon
