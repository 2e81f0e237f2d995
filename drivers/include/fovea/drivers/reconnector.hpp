// The reconnect loop of a driver whose device may be absent or go away (a serial port that is
// unplugged, a TCP server that restarts): the retry timer, the exponential backoff between
// reconnect_min_ms and reconnect_max_ms, and the liveness token its async handlers hold. What a
// connection is, when it counts as working and what to log stay with the driver.
// Header-only; used by the serial and Gazepoint drivers.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>

#include "fovea/result.hpp"

namespace fovea::drivers {

// Thread rule: every method runs on the driver's io_context thread (open(), close() and the
// handlers), like the driver itself; nothing here is locked. Not copyable or movable: the retry
// handler points at it.
class Reconnector {
public:
    Reconnector(std::chrono::milliseconds min_delay, std::chrono::milliseconds max_delay)
        : min_(min_delay), max_(max_delay), delay_(min_delay) {}
    ~Reconnector() { stop(); }
    Reconnector(const Reconnector&) = delete;
    Reconnector& operator=(const Reconnector&) = delete;

    // Loop thread (the driver's open(), once what connect uses is set up). Begins a session: a
    // fresh token, the delay back at the minimum, and the first attempt, connect(), right away;
    // each retry_later() calls connect again.
    void start(boost::asio::io_context& io, std::function<void()> connect) {
        stop();
        alive_ = std::make_shared<int>(0);
        timer_.emplace(io);
        connect_ = std::move(connect);
        delay_ = min_;
        const auto first = connect_;  // connect may stop() and start() again
        first();
    }

    // Loop thread. The attempt failed or the link went away: call connect after the current
    // delay, and double the delay (up to the maximum) for the retry after that. A pending retry
    // is replaced, not added to. Does nothing once stopped.
    void retry_later() {
        if (!timer_) return;
        timer_->expires_after(delay_);
        delay_ = std::min(delay_ * 2, max_);
        timer_->async_wait([this, token = token()](boost::system::error_code ec) {
            if (ec || token.expired()) return;  // cancelled, stopped, or this object is gone
            // A copy: connect may stop() and start() again, which replaces connect_.
            const auto connect = connect_;
            connect();
        });
    }

    // Loop thread. The link works: the next retry_later() waits the minimum again.
    void reset_delay() { delay_ = min_; }

    // Loop thread (the driver's close(); may run inside connect). Ends the session: the token
    // expires and a pending retry never calls connect. Idempotent.
    void stop() {
        alive_.reset();
        if (timer_) timer_->cancel();
        timer_.reset();
    }

    // For every async handler of the driver: expired once stop() has run (and before start()),
    // so a late completion returns before it touches the driver.
    std::weak_ptr<void> token() const { return alive_; }

    // What the next retry_later() waits.
    std::chrono::milliseconds next_delay() const { return delay_; }

private:
    std::chrono::milliseconds min_, max_, delay_;
    std::shared_ptr<int> alive_;
    std::optional<boost::asio::steady_timer> timer_;
    std::function<void()> connect_;
};

// The serial and Gazepoint drivers' check of their reconnect_min_ms and reconnect_max_ms keys:
// 1 <= min <= max <= 600000 (ten minutes); the error starts with the driver's name.
inline Result<void> check_reconnect_range(const char* driver, int64_t min_ms, int64_t max_ms) {
    if (min_ms < 1 || max_ms < min_ms || max_ms > 600'000)
        return make_error(std::string(driver) +
                          ": need 1 <= reconnect_min_ms <= reconnect_max_ms <= 600000");
    return {};
}

}  // namespace fovea::drivers
