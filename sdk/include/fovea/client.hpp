// Header-only RAII C++ over the C client (fovea/client.h): codes become fovea::ClientError
// exceptions, the handle is owned by fovea::Client. Everything stays inline so the C ABI is the
// only binary interface.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "fovea/client.h"

namespace fovea {

class ClientError : public std::runtime_error {
public:
    ClientError(int status, const std::string& what) : std::runtime_error(what), status_(status) {}
    int status() const { return status_; }

private:
    int status_;
};

class Client {
public:
    explicit Client(const std::string& instance = "default",
                    fovea_stream_kind kind = FOVEA_STREAM_GAZE) {
        check(fovea_client_open(instance.c_str(), kind, &c_));
    }
    Client(Client&& o) noexcept : c_(std::exchange(o.c_, nullptr)) {}
    Client& operator=(Client&& o) noexcept {
        if (this != &o) {
            fovea_client_close(&c_);
            c_ = std::exchange(o.c_, nullptr);
        }
        return *this;
    }
    Client(const Client&) = delete;
    Client& operator=(const Client&) = delete;
    ~Client() { fovea_client_close(&c_); }

    fovea_ring_info info() const {
        fovea_ring_info i{};
        check(fovea_client_info(c_, &i));
        return i;
    }
    uint64_t head() const { return fovea_client_head(c_); }
    // The HMD eye geometry the writer maps gaze with; ipd_m == 0 when it has none.
    fovea_eye_geometry eye_geometry() const {
        fovea_eye_geometry g{};
        check(fovea_client_eye_geometry(c_, &g));
        return g;
    }

    // The newest record, or nullopt before the first publish.
    std::optional<fovea_gaze_record> latest() {
        fovea_gaze_record r{};
        const int s = fovea_client_latest(c_, &r);
        if (s == FOVEA_E_NO_DATA || s == FOVEA_E_WRITER_RESTARTED) return std::nullopt;
        check(s);
        return r;
    }

    struct Batch {
        std::vector<fovea_gaze_record> records;
        uint64_t dropped = 0;
        bool writer_restarted = false;  // cursor was reset to the new generation's head
    };

    // Records from *cursor on (at most max), advancing the cursor.
    Batch read(uint64_t& cursor, uint32_t max = 256) {
        Batch b;
        b.records.resize(max);
        uint32_t n = 0;
        const int s = fovea_client_read(c_, &cursor, b.records.data(), max, &n, &b.dropped);
        if (s == FOVEA_E_WRITER_RESTARTED) {
            b.writer_restarted = true;
            cursor = head();
        } else {
            check(s);
        }
        b.records.resize(n);
        return b;
    }

    // True when a record at or after cursor exists, false on timeout. Throws on other errors;
    // a restarted writer resets cursor to the new head and returns false.
    bool wait(uint64_t& cursor, int32_t timeout_ms) {
        const int s = fovea_client_wait(c_, cursor, timeout_ms);
        if (s == FOVEA_OK) return true;
        if (s == FOVEA_E_TIMEOUT) return false;
        if (s == FOVEA_E_WRITER_RESTARTED) {
            cursor = head();
            return false;
        }
        check(s);
        return false;
    }

    // fovea_client_set_wait_spin: 0 sleep only (default), < 0 adaptive, > 0 cap in microseconds.
    void set_wait_spin(int32_t max_spin_us) { fovea_client_set_wait_spin(c_, max_spin_us); }

    fovea_client* handle() const { return c_; }

private:
    static void check(int status) {
        if (status != FOVEA_OK) throw ClientError(status, fovea_last_error());
    }
    fovea_client* c_ = nullptr;
};

// Render-side latency hops (fovea_frame_latency in client.h): the host reports frame events,
// libfovea keeps the per-hop histograms and the stale-gaze counter and reports them to fovead.
// Times are CLOCK_MONOTONIC ns; 0 means now. Event calls from one thread at a time.
class FrameLatency {
public:
    FrameLatency() { check(fovea_frame_latency_create(&f_)); }
    FrameLatency(FrameLatency&& o) noexcept : f_(std::exchange(o.f_, nullptr)) {}
    FrameLatency& operator=(FrameLatency&& o) noexcept {
        if (this != &o) {
            fovea_frame_latency_destroy(&f_);
            f_ = std::exchange(o.f_, nullptr);
        }
        return *this;
    }
    FrameLatency(const FrameLatency&) = delete;
    FrameLatency& operator=(const FrameLatency&) = delete;
    ~FrameLatency() { fovea_frame_latency_destroy(&f_); }

    void set_stale_threshold_ns(int64_t ns) {
        check(fovea_frame_latency_set_stale_threshold(f_, ns));
    }
    void reset() { fovea_frame_latency_reset(f_); }

    void gaze_read(const fovea_gaze_record& r, int64_t t_ns = 0) {
        check(fovea_frame_gaze_read(f_, &r, t_ns));
    }
    // Begins a frame rendered for `r` (nullptr: no gaze yet); returns the gaze's age at begin in
    // ns (capture -> begin; what vk::GazeState::age_s should carry), -1 without a record.
    int64_t frame_begin(const fovea_gaze_record* r, int64_t t_ns = 0) {
        int64_t age = -1;
        check(fovea_frame_begin(f_, r, t_ns, &age));
        return age;
    }
    void submitted(int64_t t_ns = 0) { check(fovea_frame_submitted(f_, t_ns)); }
    void presented(int64_t t_ns = 0) { check(fovea_frame_presented(f_, t_ns)); }

    fovea_hop_stats hop(fovea_render_hop h) const {
        fovea_hop_stats s{};
        check(fovea_frame_latency_hop(f_, h, &s));
        return s;
    }
    fovea_frame_counters counters() const {
        fovea_frame_counters c{};
        check(fovea_frame_latency_counters(f_, &c));
        return c;
    }
    // Sends the histograms to the instance's fovead (`latency.report`); throws ClientError.
    void report(const std::string& instance = "default", int32_t timeout_ms = 1000) const {
        check(fovea_frame_latency_report(f_, instance.c_str(), timeout_ms));
    }

    fovea_frame_latency* handle() const { return f_; }

private:
    static void check(int status) {
        if (status != FOVEA_OK) throw ClientError(status, fovea_last_error());
    }
    fovea_frame_latency* f_ = nullptr;
};

}  // namespace fovea
