// Recorder: writes the raw gaze, processed gaze and latency streams of a running daemon to an
// XDF file without ever blocking the caller on disk.
//
// Threading: start(), push_raw(), push_gaze() and stop() are called from ONE thread (the
// daemon's loop thread); push_* only copy the sample into a queue under a short mutex. A writer
// thread owned by the Recorder encodes and write()s the queue at least every flush interval
// (<= 1 s, so a kill -9 loses at most that much), writes a boundary chunk + clock offsets every
// boundary interval and fdatasync()s then. stats() may be called from any thread.
//
// Errors: an unwritable path fails start() with a clear message. A write error later (disk full,
// quota, I/O error) stops the recording: the error is reported once (stats().error and the
// on_error callback, called on the writer thread), later pushes are only counted as dropped, and
// the caller keeps running. What reached the file up to the failure stays readable (`fovea
// repair` closes it).
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "fovea/gaze/sample.hpp"
#include "fovea/record/streams.hpp"
#include "fovea/result.hpp"

namespace fovea::record {

struct RecorderOptions {
    std::string path;
    RecordingInfo info;                       // time_origin_ns 0 = now
    int64_t flush_interval_ns = 250'000'000;  // clamped to <= 1 s
    int64_t boundary_interval_ns = 5'000'000'000;
    std::size_t max_pending_samples = 1 << 20;         // per stream; beyond it samples are dropped
    std::function<void(const std::string&)> on_error;  // once, writer thread
};

struct RecorderStats {
    std::string path;
    bool recording = false;  // started, not stopped, no error
    bool failed = false;
    std::string error;
    uint64_t raw_samples = 0;  // written to the file
    uint64_t gaze_samples = 0;
    uint64_t latency_samples = 0;
    uint64_t dropped_samples = 0;  // queue full or after a write error
    uint64_t bytes_written = 0;
    uint64_t flushes = 0;
    uint64_t buffer_bytes = 0;  // memory the sample queue holds (capacity, both halves)
    int64_t started_ns = 0;
};

class Recorder {
public:
    // Creates (truncates) the file, writes the file and stream headers synchronously and starts
    // the writer thread.
    static Result<std::unique_ptr<Recorder>> start(RecorderOptions options);
    ~Recorder();  // stop()s if still running
    Recorder(const Recorder&) = delete;
    Recorder& operator=(const Recorder&) = delete;

    // Every raw sample from the driver; predict_landing = the pipeline's setting at the time
    // (replay uses it to reproduce the live run).
    // preroll: a sample from before start() (the chain's warm-up history; see RecordingInfo).
    void push_raw(const gaze::RawSample& raw, bool predict_landing, bool preroll = false);
    // Every processed sample, after it was published into the ring at t_publish_ns with index
    // ring_index (records the gaze row and the latency row).
    void push_gaze(const gaze::GazeSample& sample, int64_t t_publish_ns, uint64_t ring_index);

    // Drain the queue, write footers, fsync and close. Idempotent. Returns the first write error.
    Result<RecorderStats> stop();

    RecorderStats stats() const;
    const std::string& path() const { return options_.path; }

private:
    struct Pending {
        std::vector<double> stamps;
        std::vector<double> rows;
    };
    struct StreamState {
        uint32_t id = 0;
        int channels = 0;
        uint64_t written = 0;
        double first_ts = 0.0, last_ts = 0.0;
        std::vector<std::pair<double, double>> offsets;
    };

    Recorder(RecorderOptions options, int fd);
    void writer_main();
    // Encode and write what is pending; true while the file is good.
    bool write_pending(bool final);
    bool write_bytes(const std::vector<uint8_t>& bytes);
    void fail(const std::string& what, int err);
    void push_row(int stream, double stamp, const double* row, int channels);
    void release_spare_capacity();

    RecorderOptions options_;
    int fd_ = -1;

    mutable std::mutex mutex_;
    std::condition_variable wake_;
    Pending pending_[3];
    bool stop_requested_ = false;

    std::atomic<bool> failed_{false};
    std::atomic<uint64_t> dropped_{0};
    std::atomic<uint64_t> bytes_{0};
    std::atomic<uint64_t> flushes_{0};
    std::atomic<uint64_t> written_[3] = {0, 0, 0};
    std::atomic<uint64_t> swap_bytes_{0};  // capacity of swap_, for stats()
    std::string error_;                    // guarded by mutex_

    // writer-thread state
    StreamState streams_[3];
    Pending swap_[3];
    int64_t last_boundary_ns_ = 0;

    std::thread writer_;
    bool stopped_ = false;
    Result<RecorderStats> stop_result_ = make_error("not stopped");
};

int64_t monotonic_ns();

}  // namespace fovea::record
