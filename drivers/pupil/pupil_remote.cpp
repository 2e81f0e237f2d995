#include "pupil/pupil_remote.hpp"

#include <zmq.h>

#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <string_view>

namespace fovea::drivers::pupil {

double host_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

std::optional<ClockOffset> estimate_offset(std::vector<RoundTrip> trips) {
    trips.erase(std::remove_if(trips.begin(), trips.end(),
                               [](const RoundTrip& t) {
                                   return !(t.rtt_s() >= 0) || !std::isfinite(t.pupil_s);
                               }),
                trips.end());
    if (trips.empty()) return std::nullopt;
    std::sort(trips.begin(), trips.end(),
              [](const RoundTrip& a, const RoundTrip& b) { return a.rtt_s() < b.rtt_s(); });
    ClockOffset c;
    c.total = trips.size();
    c.kept = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(trips.size() * 0.7)));
    auto offset = [](const RoundTrip& t) {
        return t.pupil_s - 0.5 * (t.host_sent_s + t.host_received_s);
    };
    // Two passes: offsets are ~1e5 s apart from zero, so sum-of-squares would cancel to ms.
    double sum = 0, sum2 = 0;
    for (std::size_t i = 0; i < c.kept; ++i) sum += offset(trips[i]);
    const double n = static_cast<double>(c.kept);
    c.offset_s = sum / n;
    for (std::size_t i = 0; i < c.kept; ++i) {
        const double d = offset(trips[i]) - c.offset_s;
        sum2 += d * d;
    }
    c.sd_s = std::sqrt(sum2 / n);
    c.uncertainty_s = 0.5 * trips[c.kept - 1].rtt_s();
    c.median_rtt_s = trips[c.kept / 2].rtt_s();
    return c;
}

namespace {

// A reply quoted in an error: bytes from the network, so bounded.
std::string quoted(std::string_view reply) {
    constexpr std::size_t kMax = 64;
    return "'" + std::string(reply.substr(0, kMax)) + (reply.size() > kMax ? "...'" : "'");
}

}  // namespace

Result<double> parse_time_reply(std::string_view reply) {
    // A time beyond kMaxTimeSeconds (or an offset summed from such times) would map every sample
    // to 0.
    const std::string text(reply);  // strtod needs the terminator
    char* end = nullptr;
    const double t = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || !(std::fabs(t) <= kMaxTimeSeconds))
        return make_error("'t' answered " + quoted(reply) + ", not a time");
    return t;
}

Result<std::string> bus_address(const std::string& remote, std::string_view sub_port_reply) {
    const std::string_view p = sub_port_reply;
    const auto digit = [](char c) { return c >= '0' && c <= '9'; };
    int port = 0;
    if (!p.empty() && p.size() <= 5 && std::all_of(p.begin(), p.end(), digit))
        for (const char c : p) port = port * 10 + (c - '0');
    if (port < 1 || port > 65535)
        return make_error("'SUB_PORT' answered " + quoted(p) + ", not a port");
    return remote.substr(0, remote.rfind(':') + 1) + std::string(p);
}

Result<std::unique_ptr<RemoteClient>> RemoteClient::connect(void* context,
                                                            const std::string& address,
                                                            int timeout_ms) {
    std::unique_ptr<RemoteClient> c(new RemoteClient());
    c->address_ = address;
    c->socket_ = zmq_socket(context, ZMQ_REQ);
    if (!c->socket_) return make_error(std::string("zmq REQ socket: ") + zmq_strerror(zmq_errno()));
    const int zero = 0;
    zmq_setsockopt(c->socket_, ZMQ_LINGER, &zero, sizeof zero);
    zmq_setsockopt(c->socket_, ZMQ_RCVTIMEO, &timeout_ms, sizeof timeout_ms);
    zmq_setsockopt(c->socket_, ZMQ_SNDTIMEO, &timeout_ms, sizeof timeout_ms);
    if (zmq_connect(c->socket_, address.c_str()) != 0)
        return make_error("Pupil Remote " + address + ": " + zmq_strerror(zmq_errno()));
    return c;
}

RemoteClient::~RemoteClient() {
    if (socket_) zmq_close(socket_);
}

Result<std::string> RemoteClient::request(const std::string& command) {
    if (zmq_send(socket_, command.data(), command.size(), 0) < 0)
        return make_error("Pupil Remote " + address_ + ": sending '" + command +
                          "': " + zmq_strerror(zmq_errno()));
    zmq_msg_t msg;
    zmq_msg_init(&msg);
    if (zmq_msg_recv(&msg, socket_, 0) < 0) {
        zmq_msg_close(&msg);
        return make_error("Pupil Remote " + address_ + ": no answer to '" + command + "' (" +
                          zmq_strerror(zmq_errno()) + ")");
    }
    std::string reply(static_cast<const char*>(zmq_msg_data(&msg)), zmq_msg_size(&msg));
    zmq_msg_close(&msg);
    return reply;
}

Result<ClockOffset> RemoteClient::sync(int rounds) {
    std::vector<RoundTrip> trips;
    for (int i = 0; i < rounds; ++i) {
        RoundTrip t;
        t.host_sent_s = host_seconds();
        auto r = request("t");
        t.host_received_s = host_seconds();
        if (!r) return r.error();
        auto pupil_s = parse_time_reply(*r);
        if (!pupil_s)
            return make_error("Pupil Remote " + address_ + ": " + pupil_s.error().message);
        t.pupil_s = *pupil_s;
        trips.push_back(t);
    }
    auto c = estimate_offset(std::move(trips));
    if (!c) return make_error("Pupil Remote " + address_ + ": no usable 't' round trip");
    return *c;
}

}  // namespace fovea::drivers::pupil
