#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <csignal>
#include <filesystem>
#include <thread>

#include <gtest/gtest.h>

#include "fovea/record/recorder.hpp"
#include "fovea/record/streams.hpp"
#include "fovea/record/xdf.hpp"
#include "libxdf_oracle.hpp"
#include "synthetic.hpp"
#include "test_util.hpp"

using namespace fovea::record;
using fovea::record::test::same_double;
using fovea::record::test::synthetic_gaze;
using fovea::record::test::synthetic_raw;

namespace {

RecorderOptions options(const std::string& path) {
    RecorderOptions o;
    o.path = path;
    o.info.device_name = "synthetic";
    o.info.driver = "test";
    o.info.nominal_rate_hz = 1000;
    o.info.clock.counter_bits = 32;
    o.info.clock.tick_hz = 1e6;
    o.info.display.distance_m = 0.65;
    o.flush_interval_ns = 20'000'000;
    o.boundary_interval_ns = 100'000'000;
    return o;
}

// Receive times near 2^62 ns would lose precision as doubles; relative storage keeps them exact.
constexpr int64_t kT0 = int64_t{4'000'000'000'000'000'000};

void expect_eye(const fovea::gaze::EyeSample& a, const fovea::gaze::EyeSample& b) {
    EXPECT_TRUE(same_double(a.x, b.x));
    EXPECT_TRUE(same_double(a.y, b.y));
    EXPECT_EQ(a.pupil_mm, b.pupil_mm);
    EXPECT_EQ(a.valid, b.valid);
}

}  // namespace

TEST(Recorder, EverySampleRoundTripsBitExactly) {
    const test::ScratchDir dir("roundtrip");
    const std::string path = (dir / "r.xdf").string();
    auto opt = options(path);
    opt.info.time_origin_ns = kT0;
    auto rec = Recorder::start(opt);
    ASSERT_TRUE(rec.ok()) << rec.error().message;
    constexpr int kN = 3000;
    for (int i = 0; i < kN; ++i) {
        (*rec)->push_raw(synthetic_raw(i, kT0), i % 500 < 250);
        const auto g = synthetic_gaze(i, kT0);
        (*rec)->push_gaze(g, g.t_processed_ns + 4000, 77 + static_cast<uint64_t>(i));
        if (i % 1000 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(30));
    }
    auto st = (*rec)->stop();
    ASSERT_TRUE(st.ok()) << st.error().message;
    EXPECT_EQ(st->raw_samples, static_cast<uint64_t>(kN));
    EXPECT_EQ(st->gaze_samples, static_cast<uint64_t>(kN));
    EXPECT_EQ(st->dropped_samples, 0u);
    EXPECT_GT(st->flushes, 1u);

    auto f = xdf::read_file(path);
    ASSERT_TRUE(f.ok()) << f.error().message;
    EXPECT_FALSE(f->truncated);
    const auto* raw = f->find(kRawStreamName);
    const auto* gz = f->find(kGazeStreamName);
    const auto* lat = f->find(kLatencyStreamName);
    ASSERT_TRUE(raw && gz && lat);
    ASSERT_EQ(raw->sample_count(), static_cast<std::size_t>(kN));
    ASSERT_EQ(gz->sample_count(), static_cast<std::size_t>(kN));
    ASSERT_EQ(lat->sample_count(), static_cast<std::size_t>(kN));
    EXPECT_FALSE(raw->footer_xml.empty());
    auto ri = recording_info_from_xml(raw->header_xml);
    ASSERT_TRUE(ri.ok());
    EXPECT_EQ(ri->time_origin_ns, kT0);
    EXPECT_EQ(ri->clock.counter_bits, 32);
    EXPECT_EQ(ri->display.distance_m, 0.65);
    EXPECT_EQ(raw->units[2], "ns");
    for (int i = 0; i < kN; ++i) {
        bool predict = false;
        const auto a = synthetic_raw(i, kT0);
        const auto b = decode_raw(&raw->values[static_cast<std::size_t>(i) * raw_channel_count()],
                                  ri->time_origin_ns, &predict);
        ASSERT_EQ(a.device_ticks, b.device_ticks);
        ASSERT_EQ(a.t_receive_ns, b.t_receive_ns);
        expect_eye(a.left, b.left);
        expect_eye(a.right, b.right);
        ASSERT_EQ(a.device_id, b.device_id);
        ASSERT_EQ(a.truth, b.truth);
        ASSERT_EQ(predict, i % 500 < 250);

        const auto g = synthetic_gaze(i, kT0);
        int64_t pub = 0;
        uint64_t idx = 0;
        const auto h = decode_gaze(&gz->values[static_cast<std::size_t>(i) * gaze_channel_count()],
                                   ri->time_origin_ns, &pub, &idx);
        ASSERT_EQ(g.t_capture_ns, h.t_capture_ns);
        ASSERT_EQ(g.t_processed_ns, h.t_processed_ns);
        ASSERT_EQ(pub, g.t_processed_ns + 4000);
        ASSERT_EQ(idx, 77u + static_cast<uint64_t>(i));
        ASSERT_EQ(g.event, h.event);
        ASSERT_EQ(g.saccade.onset_ns, h.saccade.onset_ns);
        ASSERT_EQ(g.saccade.peak_velocity_dps, h.saccade.peak_velocity_dps);
        ASSERT_EQ(g.combined_deg_x, h.combined_deg_x);
        expect_eye(g.combined, h.combined);
        ASSERT_DOUBLE_EQ(lat->value(i, 3), 4.0);  // processed -> publish, µs
    }
    EXPECT_GE(f->boundaries, 2u);
    test::expect_libxdf_agrees(path);
}

TEST(Recorder, UnwritablePathIsOneClearError) {
    auto r = Recorder::start(options("/nonexistent-dir/x.xdf"));
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("cannot create recording /nonexistent-dir/x.xdf"),
              std::string::npos)
        << r.error().message;
    auto full = Recorder::start(options("/dev/full"));
    ASSERT_FALSE(full.ok());
    EXPECT_NE(full.error().message.find("No space left"), std::string::npos)
        << full.error().message;
}

TEST(Recorder, DiskFullMidRecordingReportsOnceAndTheCallerKeepsGoing) {
    // A real kernel write error: RLIMIT_FSIZE makes write() fail with EFBIG past 64 KiB.
    const test::ScratchDir dir("full");
    const std::string path = (dir / "full.xdf").string();
    std::signal(SIGXFSZ, SIG_IGN);
    rlimit old{};
    getrlimit(RLIMIT_FSIZE, &old);
    rlimit lim = old;
    lim.rlim_cur = 64 * 1024;
    ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &lim), 0);
    std::atomic<int> errors{0};
    std::string first_error;
    auto opt = options(path);
    opt.on_error = [&](const std::string& e) {
        if (errors++ == 0) first_error = e;
    };
    auto rec = Recorder::start(opt);
    ASSERT_TRUE(rec.ok()) << rec.error().message;
    const int64_t t0 = monotonic_ns();
    int pushed = 0;
    for (int i = 0; i < 20000; ++i) {
        (*rec)->push_raw(synthetic_raw(i, t0), true);
        const auto g = synthetic_gaze(i, t0);
        (*rec)->push_gaze(g, g.t_processed_ns, static_cast<uint64_t>(i));
        ++pushed;
        if (i == 0) {
            // the first sample on disk before the burst, however slowly the writer starts (ASan)
            const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
            while ((*rec)->stats().raw_samples == 0 && std::chrono::steady_clock::now() < deadline)
                std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        if (i % 2000 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(25));
    }
    auto st = (*rec)->stop();
    setrlimit(RLIMIT_FSIZE, &old);
    std::signal(SIGXFSZ, SIG_DFL);
    EXPECT_EQ(pushed, 20000);  // pushes never blocked or threw
    ASSERT_FALSE(st.ok());
    EXPECT_EQ(errors.load(), 1);
    EXPECT_NE(first_error.find("File too large"), std::string::npos) << first_error;
    const auto s = (*rec)->stats();
    EXPECT_TRUE(s.failed);
    EXPECT_GT(s.dropped_samples, 0u);
    EXPECT_EQ(s.raw_samples + s.gaze_samples + s.latency_samples + s.dropped_samples, 60000u);
    // what reached the disk is readable, and repair closes it
    auto f = xdf::read_file(path);
    ASSERT_TRUE(f.ok()) << f.error().message;
    EXPECT_GT(f->find(kRawStreamName)->sample_count(), 0u);
    auto rep = xdf::repair(path);
    ASSERT_TRUE(rep.ok()) << rep.error().message;
}

TEST(Recorder, QueueGrownWhileTheDiskStalledIsGivenBackOnceTheWriterCatchesUp) {
    // A real stall: the recording is a FIFO nobody reads, so write() blocks once the pipe is
    // full and the queue grows; then a reader drains it. The queue must shrink back to what the
    // sample rate needs instead of keeping the stall's high-water mark for the whole recording.
    const test::ScratchDir dir("stall");
    const std::string path = (dir / "stall.fifo").string();
    ASSERT_EQ(mkfifo(path.c_str(), 0600), 0);
    const int reader = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    ASSERT_GE(reader, 0);
    auto rec = Recorder::start(options(path));
    ASSERT_TRUE(rec.ok()) << rec.error().message;
    const int64_t t0 = monotonic_ns();
    constexpr int kBurst = 40000;
    for (int i = 0; i < kBurst; ++i) {
        (*rec)->push_raw(synthetic_raw(i, t0), true);
        const auto g = synthetic_gaze(i, t0);
        (*rec)->push_gaze(g, g.t_processed_ns, static_cast<uint64_t>(i));
    }
    // let the writer swap the burst in and block on the full pipe
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    const uint64_t stalled = (*rec)->stats().buffer_bytes;
    EXPECT_GT(stalled, 10u << 20) << "a 40 000-sample burst queued less than 10 MiB?";

    std::atomic<bool> draining{true};
    std::thread drain([&] {
        fcntl(reader, F_SETFL, 0);
        char buf[1 << 16];
        while (::read(reader, buf, sizeof buf) > 0) {}
        draining = false;
    });
    // then 1 kHz for 30 flush intervals: the queue needs ~20 samples per flush
    for (int i = kBurst; i < kBurst + 600; ++i) {
        (*rec)->push_raw(synthetic_raw(i, t0), true);
        const auto g = synthetic_gaze(i, t0);
        (*rec)->push_gaze(g, g.t_processed_ns, static_cast<uint64_t>(i));
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while ((*rec)->stats().raw_samples < kBurst + 600u &&
           std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // a few more flushes
    const auto s = (*rec)->stats();
    EXPECT_EQ(s.raw_samples, kBurst + 600u);
    EXPECT_EQ(s.dropped_samples, 0u);
    EXPECT_LT(s.buffer_bytes, 2u << 20)
        << "kept " << s.buffer_bytes << " bytes after a stall of " << stalled;
    ASSERT_TRUE((*rec)->stop().ok());
    drain.join();
    ::close(reader);
    EXPECT_FALSE(draining.load());
}

TEST(Recorder, KillDashNineLosesAtMostTheLastFlushAndRepairClosesTheFile) {
    const test::ScratchDir dir("kill9");
    const std::string path = (dir / "k.xdf").string();
    const std::string progress = (dir / "progress").string();
    int pipefd[2];
    ASSERT_EQ(pipe(pipefd), 0);
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        // child: record at ~1 kHz forever; report how many samples were pushed >= 1 flush ago
        close(pipefd[0]);
        auto opt = options(path);
        opt.flush_interval_ns = 100'000'000;
        opt.boundary_interval_ns = 300'000'000;
        auto rec = Recorder::start(opt);
        if (!rec.ok()) _exit(3);
        const int64_t t0 = monotonic_ns();
        for (int i = 0;; ++i) {
            (*rec)->push_raw(synthetic_raw(i, t0), true);
            const auto g = synthetic_gaze(i, t0);
            (*rec)->push_gaze(g, g.t_processed_ns, static_cast<uint64_t>(i));
            if (i % 100 == 99) {
                const int n = i + 1;
                if (write(pipefd[1], &n, sizeof n) != sizeof n) _exit(4);
                std::this_thread::sleep_for(std::chrono::milliseconds(100));
            }
        }
    }
    close(pipefd[1]);
    int pushed = 0;
    // let it run ~1.2 s (12 progress reports), then kill -9 without warning
    for (int k = 0; k < 12; ++k) ASSERT_EQ(read(pipefd[0], &pushed, sizeof pushed), 4);
    // samples pushed more than one flush interval (+ slack) before the kill must be on disk
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
    kill(pid, SIGKILL);
    int status = 0;
    waitpid(pid, &status, 0);
    close(pipefd[0]);
    ASSERT_TRUE(WIFSIGNALED(status));

    auto f = xdf::read_file(path);
    ASSERT_TRUE(f.ok()) << f.error().message;
    const auto* raw = f->find(kRawStreamName);
    ASSERT_NE(raw, nullptr);
    EXPECT_GE(raw->sample_count(), static_cast<std::size_t>(pushed));
    EXPECT_GE(f->boundaries, 2u);
    EXPECT_TRUE(raw->footer_xml.empty());  // never closed
    auto rep = xdf::repair(path);
    ASSERT_TRUE(rep.ok()) << rep.error().message;
    EXPECT_EQ(rep->footers_added, 3);
    auto g = xdf::read_file(path);
    ASSERT_TRUE(g.ok());
    EXPECT_FALSE(g->truncated);
    EXPECT_EQ(g->find(kRawStreamName)->sample_count(), raw->sample_count());
    test::expect_libxdf_agrees(path);
}
