// The base of a driver whose device comes and goes (a serial port that is unplugged, a TCP
// server that restarts): open() and close() around the Reconnector, the counters behind one lock,
// the connected/reconnects bookkeeping, and the hand-off of a sample to the sink. The derived
// driver says what a connection is (connect()), what to set up and tear down, and what it logs.
// Header-only; used by the serial and Gazepoint drivers.
#pragma once

#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>
#include <utility>

#include <boost/asio/io_context.hpp>

#include "fovea/drivers/driver.hpp"
#include "fovea/drivers/reconnector.hpp"

namespace fovea::drivers {

// Thread rule: open(), close(), connect() and every protected method run on the loop thread
// (the *_locked ones with mutex_ held); stats() and a derived describe() run on any thread and
// take mutex_.
class ReconnectingDriver : public Driver {
public:
    ReconnectingDriver(uint32_t device_id, int reconnect_min_ms, int reconnect_max_ms)
        : reconnect_(std::chrono::milliseconds(reconnect_min_ms),
                     std::chrono::milliseconds(reconnect_max_ms)),
          device_id_(device_id) {}

    // Loop thread. Keeps io and sink, lets the driver make its timers (on_open), then connects
    // now and retries with backoff for as long as the driver is open.
    Result<void> open(boost::asio::io_context& io, SampleSink sink) final {
        io_ = &io;
        sink_ = std::move(sink);
        on_open(io);
        reconnect_.start(io, [this] { connect(); });
        return {};
    }

    // Loop thread; idempotent. The derived destructor calls it (a base destructor cannot reach
    // on_close once the derived part is gone).
    void close() final {
        reconnect_.stop();
        on_close();
    }

    DriverStats stats() const final {
        std::lock_guard lock(mutex_);
        return stats_;
    }

protected:
    // One attempt to bring the link up: on failure the driver calls reconnect_.retry_later().
    virtual void connect() = 0;
    // open(): make what connect() uses (timers, resolvers) on `io`.
    virtual void on_open(boost::asio::io_context& io) = 0;
    // close(): cancel those and drop the link; the sink is not called after it returns.
    virtual void on_close() = 0;

    // mutex_ held. The link is up: the first connection is not a reconnect, every later one is.
    void count_connected_locked() {
        if (ever_connected_) ++stats_.reconnects;
        ever_connected_ = true;
        stats_.connected = true;
    }

    // The link is down. Returns whether it was up (a link that worked may retry at the minimum).
    bool mark_disconnected() {
        std::lock_guard lock(mutex_);
        return std::exchange(stats_.connected, false);
    }

    // The error `fovea status` shows until the driver clears it.
    void set_error(std::string why) {
        std::lock_guard lock(mutex_);
        stats_.last_error = std::move(why);
    }

    // A good sample, stamped with its arrival time and this device's id, to the sink.
    void deliver(gaze::RawSample& sample, int64_t t_receive_ns) {
        sample.t_receive_ns = t_receive_ns;
        sample.device_id = device_id_;
        sink_(sample);
    }

    boost::asio::io_context& io() { return *io_; }

    Reconnector reconnect_;     // retry timer, backoff, the token every handler holds
    mutable std::mutex mutex_;  // guards stats_ and what the derived driver says it guards
    DriverStats stats_;

private:
    uint32_t device_id_;
    boost::asio::io_context* io_ = nullptr;
    SampleSink sink_;
    bool ever_connected_ = false;
};

}  // namespace fovea::drivers
