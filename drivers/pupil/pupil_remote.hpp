// Pupil Remote, the REQ/REP command socket of Pupil Capture / Service (default port 50020):
// "SUB_PORT" (the bus to subscribe to), "v" (version), "t" (current Pupil time, seconds),
// "T <s>" (set Pupil time: moves the clock under every other client, so only on request).
// One thread per RemoteClient; the time-sync arithmetic is a pure function.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fovea/result.hpp"

namespace fovea::drivers::pupil {

// One "t" round trip: host CLOCK_MONOTONIC seconds around the request, Pupil's answer.
struct RoundTrip {
    double host_sent_s = 0.0;
    double pupil_s = 0.0;
    double host_received_s = 0.0;
    double rtt_s() const { return host_received_s - host_sent_s; }
};

// offset = Pupil time - host time. Pupil's own time sync: the slowest 30 % of the round trips
// are dropped, the offset is the mean of (Pupil time - round-trip midpoint) over the rest.
struct ClockOffset {
    double offset_s = 0.0;
    double uncertainty_s = 0.0;  // half the slowest kept round trip: the midpoint's worst error
    double sd_s = 0.0;           // spread of the kept offsets
    double median_rtt_s = 0.0;
    std::size_t kept = 0, total = 0;
};
std::optional<ClockOffset> estimate_offset(std::vector<RoundTrip> trips);

// The largest Pupil or host time in seconds a sample can carry: samples hold 64-bit ns ticks.
constexpr double kMaxTimeSeconds = 9.2e9;

// Pupil Remote's answers, as bytes from the network. "t": Pupil time in seconds, |t| <=
// kMaxTimeSeconds (text after the number is ignored).
Result<double> parse_time_reply(std::string_view reply);
// "SUB_PORT": the bus port; the bus is at the Remote's host on that port
// ("tcp://host:50020" + "50021" -> "tcp://host:50021").
Result<std::string> bus_address(const std::string& remote, std::string_view sub_port_reply);

double host_seconds();  // CLOCK_MONOTONIC

// A REQ socket to Pupil Remote. Every request times out (then the socket is unusable: a
// REQ socket that missed its reply must be recreated, so the client is dropped).
class RemoteClient {
public:
    // `context` is a ZeroMQ context owned by the caller.
    static Result<std::unique_ptr<RemoteClient>> connect(void* context, const std::string& address,
                                                         int timeout_ms);
    ~RemoteClient();
    RemoteClient(const RemoteClient&) = delete;
    RemoteClient& operator=(const RemoteClient&) = delete;

    Result<std::string> request(const std::string& command);
    // `rounds` "t" requests; the offset estimate of the fastest 70 %.
    Result<ClockOffset> sync(int rounds);

private:
    RemoteClient() = default;
    void* socket_ = nullptr;
    std::string address_;
};

}  // namespace fovea::drivers::pupil
