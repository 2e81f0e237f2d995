#include "fovea/record/recorder.hpp"

#include <fcntl.h>
#include <malloc.h>
#include <sys/stat.h>
#include <unistd.h>
#include <algorithm>
#include <cerrno>
#include <cstring>
#include <ctime>

namespace fovea::record {

int64_t monotonic_ns() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

namespace {
constexpr int kRaw = 0, kGaze = 1, kLatency = 2;

std::string hostname() {
    char b[256] = {};
    if (gethostname(b, sizeof b - 1) != 0) return {};
    return b;
}

std::size_t capacity_bytes(const std::vector<double>& stamps, const std::vector<double>& rows) {
    return (stamps.capacity() + rows.capacity()) * sizeof(double);
}

// A queue half keeps the capacity of a few flushes at the current rate, and at least this many
// samples (a flush interval at 16 kHz), so that steady recording never reallocates.
constexpr std::size_t kKeepSamples = 4096;
constexpr std::size_t kTrimAfterBytes = std::size_t{1} << 20;

bool write_all(int fd, const uint8_t* p, std::size_t n, int& err) {
    while (n > 0) {
        const ssize_t w = ::write(fd, p, n);
        if (w < 0) {
            if (errno == EINTR) continue;
            err = errno;
            return false;
        }
        p += w;
        n -= static_cast<std::size_t>(w);
    }
    return true;
}
}  // namespace

Result<std::unique_ptr<Recorder>> Recorder::start(RecorderOptions options) {
    if (options.path.empty()) return make_error("recording path is empty");
    if (options.info.time_origin_ns == 0) options.info.time_origin_ns = monotonic_ns();
    if (options.info.hostname.empty()) options.info.hostname = hostname();
    options.flush_interval_ns =
        std::clamp<int64_t>(options.flush_interval_ns, 1'000'000, 1'000'000'000);
    const int fd = ::open(options.path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) {
        const int e = errno;
        return make_error("cannot create recording " + options.path + ": " + std::strerror(e), e);
    }
    xdf::ChunkEncoder enc;
    enc.magic();
    char extra[160];
    std::snprintf(extra, sizeof extra,
                  "  <writer>fovea recorder</writer>\n  <time_origin_ns>%lld</time_origin_ns>\n",
                  static_cast<long long>(options.info.time_origin_ns));
    enc.file_header(extra);
    enc.stream_header(kRawStreamId, raw_stream_info(options.info));
    enc.stream_header(kGazeStreamId, gaze_stream_info(options.info));
    enc.stream_header(kLatencyStreamId, latency_stream_info(options.info));
    const double t0 = static_cast<double>(options.info.time_origin_ns) * 1e-9;
    for (uint32_t id : {kRawStreamId, kGazeStreamId, kLatencyStreamId}) {
        enc.clock_offset(id, t0, 0.0);  // one clock (CLOCK_MONOTONIC) for every stream
    }
    enc.boundary();
    int err = 0;
    if (!write_all(fd, enc.buffer().data(), enc.buffer().size(), err)) {
        // remove the empty file we made, never a device or anything else at that path
        struct stat st {};
        if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode)) ::unlink(options.path.c_str());
        ::close(fd);
        return make_error("cannot write recording " + options.path + ": " + std::strerror(err),
                          err);
    }
    std::unique_ptr<Recorder> r(new Recorder(std::move(options), fd));
    r->bytes_ = enc.buffer().size();
    return r;
}

Recorder::Recorder(RecorderOptions options, int fd) : options_(std::move(options)), fd_(fd) {
    const uint32_t ids[3] = {kRawStreamId, kGazeStreamId, kLatencyStreamId};
    const int chans[3] = {raw_channel_count(), gaze_channel_count(), latency_channel_count()};
    const double t0 = static_cast<double>(options_.info.time_origin_ns) * 1e-9;
    for (int i = 0; i < 3; ++i) {
        streams_[i].id = ids[i];
        streams_[i].channels = chans[i];
        streams_[i].offsets.emplace_back(t0, 0.0);
    }
    last_boundary_ns_ = monotonic_ns();
    writer_ = std::thread([this] { writer_main(); });
}

Recorder::~Recorder() { (void)stop(); }

void Recorder::push_row(int stream, double stamp, const double* row, int channels) {
    std::lock_guard lock(mutex_);
    Pending& p = pending_[stream];
    if (p.stamps.size() >= options_.max_pending_samples) {
        dropped_.fetch_add(1, std::memory_order_relaxed);
        return;
    }
    p.stamps.push_back(stamp);
    p.rows.insert(p.rows.end(), row, row + channels);
}

void Recorder::push_raw(const gaze::RawSample& raw, bool predict_landing, bool preroll) {
    if (stopped_ || failed_.load(std::memory_order_relaxed)) {
        dropped_.fetch_add(1, std::memory_order_relaxed);
        return;
    }
    double row[32];
    encode_raw(raw, predict_landing, options_.info.time_origin_ns, row, preroll);
    push_row(kRaw, static_cast<double>(raw.t_receive_ns) * 1e-9, row, raw_channel_count());
}

void Recorder::push_gaze(const gaze::GazeSample& s, int64_t t_publish_ns, uint64_t ring_index) {
    if (stopped_ || failed_.load(std::memory_order_relaxed)) {
        dropped_.fetch_add(2, std::memory_order_relaxed);
        return;
    }
    double g[64];
    double l[8];
    encode_gaze(s, t_publish_ns, ring_index, options_.info.time_origin_ns, g);
    encode_latency(s, t_publish_ns, ring_index, l);
    std::lock_guard lock(mutex_);
    for (int k : {kGaze, kLatency}) {
        if (pending_[k].stamps.size() >= options_.max_pending_samples) {
            dropped_.fetch_add(1, std::memory_order_relaxed);
            continue;
        }
        const bool gz = k == kGaze;
        pending_[k].stamps.push_back(static_cast<double>(gz ? s.t_capture_ns : t_publish_ns) *
                                     1e-9);
        const double* row = gz ? g : l;
        pending_[k].rows.insert(pending_[k].rows.end(), row,
                                row + (gz ? gaze_channel_count() : latency_channel_count()));
    }
}

void Recorder::fail(const std::string& what, int err) {
    std::string msg = what + " " + options_.path + ": " + std::strerror(err) +
                      "; recording stopped, the daemon keeps running";
    {
        std::lock_guard lock(mutex_);
        if (failed_.load()) return;
        error_ = msg;
        failed_.store(true);
        for (auto& p : pending_) {
            dropped_.fetch_add(p.stamps.size(), std::memory_order_relaxed);
            p.stamps.clear();
            p.rows.clear();
        }
    }
    if (options_.on_error) options_.on_error(msg);
}

bool Recorder::write_bytes(const std::vector<uint8_t>& bytes) {
    int err = 0;
    if (!write_all(fd_, bytes.data(), bytes.size(), err)) {
        fail("cannot write recording", err);
        return false;
    }
    bytes_.fetch_add(bytes.size(), std::memory_order_relaxed);
    return true;
}

bool Recorder::write_pending(bool final) {
    {
        std::lock_guard lock(mutex_);
        for (int i = 0; i < 3; ++i) {
            swap_[i].stamps.clear();
            swap_[i].rows.clear();
            std::swap(swap_[i], pending_[i]);
        }
        std::size_t bytes = 0;
        for (const auto& p : swap_) bytes += capacity_bytes(p.stamps, p.rows);
        swap_bytes_.store(bytes, std::memory_order_relaxed);
    }
    auto drop_swapped = [this] {
        for (const auto& p : swap_) dropped_.fetch_add(p.stamps.size(), std::memory_order_relaxed);
    };
    if (failed_.load()) {
        drop_swapped();
        return false;
    }
    xdf::ChunkEncoder enc;
    // One Samples chunk per stream and flush; chunks are capped so a reader never needs a
    // huge allocation for one chunk.
    constexpr std::size_t kMaxChunkSamples = 4096;
    for (int i = 0; i < 3; ++i) {
        auto& st = streams_[i];
        const auto& p = swap_[i];
        const std::size_t n = p.stamps.size();
        for (std::size_t a = 0; a < n; a += kMaxChunkSamples) {
            const std::size_t m = std::min(kMaxChunkSamples, n - a);
            enc.samples(st.id, xdf::Format::kDouble64, st.channels, p.stamps.data() + a,
                        p.rows.data() + a * static_cast<std::size_t>(st.channels), m);
        }
        if (n > 0) {
            if (st.written == 0) st.first_ts = p.stamps.front();
            st.last_ts = p.stamps.back();
        }
    }
    const int64_t now = monotonic_ns();
    const bool boundary = final || now - last_boundary_ns_ >= options_.boundary_interval_ns;
    if (boundary) {
        last_boundary_ns_ = now;
        for (auto& st : streams_) {
            st.offsets.emplace_back(static_cast<double>(now) * 1e-9, 0.0);
            enc.clock_offset(st.id, static_cast<double>(now) * 1e-9, 0.0);
        }
        enc.boundary();
    }
    if (final) {
        for (const auto& st : streams_) {
            const uint64_t n = st.written + swap_[&st - streams_].stamps.size();
            std::string extra = "  <clock_offsets>";
            for (const auto& [t, o] : st.offsets) {
                char b[96];
                std::snprintf(b, sizeof b,
                              "<offset><time>%.17g</time><value>%.17g</value></offset>", t, o);
                extra += b;
            }
            extra += "</clock_offsets>\n  <dropped_samples>" + std::to_string(dropped_.load()) +
                     "</dropped_samples>\n";
            enc.stream_footer(st.id, st.first_ts, st.last_ts, n, extra);
        }
    }
    if (enc.buffer().empty()) return true;
    if (!write_bytes(enc.buffer())) {
        drop_swapped();
        return false;
    }
    for (int i = 0; i < 3; ++i) {
        streams_[i].written += swap_[i].stamps.size();
        written_[i].store(streams_[i].written, std::memory_order_relaxed);
    }
    flushes_.fetch_add(1, std::memory_order_relaxed);
    release_spare_capacity();
    if (boundary && ::fdatasync(fd_) != 0 && errno != EINVAL) {
        fail("cannot sync recording", errno);
        return false;
    }
    return true;
}

// A disk that stalls for a few seconds lets the queue grow to seconds of samples. Once the
// writer has caught up, a half that holds far more than the rate needs is freed (and the heap
// trimmed), so the stall's high-water mark is not kept for the rest of the recording.
void Recorder::release_spare_capacity() {
    std::size_t released = 0, kept = 0;
    for (auto& p : swap_) {
        const std::size_t keep = std::max(kKeepSamples, 4 * p.stamps.size());
        if (p.stamps.capacity() > keep) {
            released += capacity_bytes(p.stamps, p.rows);
            p = Pending{};
        }
        kept += capacity_bytes(p.stamps, p.rows);
    }
    swap_bytes_.store(kept, std::memory_order_relaxed);
    if (released >= kTrimAfterBytes) malloc_trim(0);
}

void Recorder::writer_main() {
    std::unique_lock lock(mutex_);
    for (;;) {
        wake_.wait_for(lock, std::chrono::nanoseconds(options_.flush_interval_ns),
                       [this] { return stop_requested_; });
        const bool final = stop_requested_;
        lock.unlock();
        write_pending(final);
        lock.lock();
        if (final) return;
    }
}

Result<RecorderStats> Recorder::stop() {
    if (stopped_) return stop_result_;
    {
        std::lock_guard lock(mutex_);
        stop_requested_ = true;
    }
    wake_.notify_all();
    if (writer_.joinable()) writer_.join();
    stopped_ = true;
    if (fd_ >= 0) {
        if (!failed_.load() && ::fsync(fd_) != 0 && errno != EINVAL)
            fail("cannot sync recording", errno);
        ::close(fd_);
        fd_ = -1;
    }
    RecorderStats s = stats();
    if (s.failed) {
        stop_result_ = make_error(s.error);
    } else {
        stop_result_ = s;
    }
    return stop_result_;
}

RecorderStats Recorder::stats() const {
    RecorderStats s;
    s.path = options_.path;
    s.failed = failed_.load();
    {
        std::lock_guard lock(mutex_);
        s.error = error_;
        s.recording = !stop_requested_ && !s.failed;
        for (const auto& p : pending_) s.buffer_bytes += capacity_bytes(p.stamps, p.rows);
    }
    s.buffer_bytes += swap_bytes_.load(std::memory_order_relaxed);
    s.raw_samples = written_[kRaw].load(std::memory_order_relaxed);
    s.gaze_samples = written_[kGaze].load(std::memory_order_relaxed);
    s.latency_samples = written_[kLatency].load(std::memory_order_relaxed);
    s.dropped_samples = dropped_.load(std::memory_order_relaxed);
    s.bytes_written = bytes_.load(std::memory_order_relaxed);
    s.flushes = flushes_.load(std::memory_order_relaxed);
    s.started_ns = options_.info.time_origin_ns;
    return s;
}

}  // namespace fovea::record
