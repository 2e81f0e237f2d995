// fovea_frame_latency: the SDK's render-side hop histograms, the stale-gaze counter and its
// threshold, and the `latency.report` request as fovead's parser reads it (a stand-in socket in a
// private runtime directory captures the request).
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "fovea/client.h"
#include "fovea/client.hpp"
#include "fovea/record/latency_stats.hpp"

namespace {

using fovea::FrameLatency;
using nlohmann::json;

constexpr int64_t kMs = 1'000'000;

fovea_gaze_record gaze(uint64_t index, int64_t capture_ns, int64_t publish_ns) {
    fovea_gaze_record r{};
    r.index = index;
    r.t_capture_ns = capture_ns;
    r.t_receive_ns = capture_ns;
    r.t_processed_ns = publish_ns;
    r.t_publish_ns = publish_ns;
    return r;
}

// One frame with every event at a known time: capture 0, publish +2 ms, read +3 ms, begin
// +5 ms, submit +9 ms, present +25 ms (all relative to `base`).
void full_frame(FrameLatency& fl, uint64_t index, int64_t base) {
    const auto r = gaze(index, base, base + 2 * kMs);
    fl.gaze_read(r, base + 3 * kMs);
    EXPECT_EQ(fl.frame_begin(&r, base + 5 * kMs), 5 * kMs);
    fl.submitted(base + 9 * kMs);
    fl.presented(base + 25 * kMs);
}

void expect_near_ns(int64_t got, int64_t want) {
    EXPECT_NEAR(static_cast<double>(got), static_cast<double>(want),
                0.008 * static_cast<double>(want));
}

TEST(FrameLatency, HopNamesContinueTheDaemonsHops) {
    using fovea::record::Hop;
    EXPECT_EQ(std::string(fovea_render_hop_name(FOVEA_HOP_PUBLISH_TO_READ)),
              fovea::record::hop_name(Hop::kPublishToRead));
    EXPECT_EQ(std::string(fovea_render_hop_name(FOVEA_HOP_READ_TO_FRAME_BEGIN)),
              fovea::record::hop_name(Hop::kReadToFrameBegin));
    EXPECT_EQ(std::string(fovea_render_hop_name(FOVEA_HOP_FRAME_BEGIN_TO_SUBMIT)),
              fovea::record::hop_name(Hop::kFrameBeginToSubmit));
    EXPECT_EQ(std::string(fovea_render_hop_name(FOVEA_HOP_SUBMIT_TO_PRESENT)),
              fovea::record::hop_name(Hop::kSubmitToPresent));
    EXPECT_STREQ(fovea_render_hop_name(FOVEA_HOP_CAPTURE_TO_FRAME_BEGIN), "capture_to_frame_begin");
    EXPECT_EQ(fovea_render_hop_name(FOVEA_RENDER_HOP_COUNT), nullptr);
    EXPECT_EQ(fovea_render_hop_name(-1), nullptr);
}

TEST(FrameLatency, EveryHopGetsItsOwnHistogram) {
    FrameLatency fl;
    for (uint64_t i = 0; i < 100; ++i) full_frame(fl, i, static_cast<int64_t>(i + 1) * 100 * kMs);
    const struct {
        fovea_render_hop hop;
        int64_t ns;
    } want[] = {
        {FOVEA_HOP_PUBLISH_TO_READ, 1 * kMs},        {FOVEA_HOP_READ_TO_FRAME_BEGIN, 2 * kMs},
        {FOVEA_HOP_FRAME_BEGIN_TO_SUBMIT, 4 * kMs},  {FOVEA_HOP_SUBMIT_TO_PRESENT, 16 * kMs},
        {FOVEA_HOP_CAPTURE_TO_FRAME_BEGIN, 5 * kMs}, {FOVEA_HOP_PUBLISH_TO_FRAME_BEGIN, 3 * kMs},
        {FOVEA_HOP_CAPTURE_TO_PRESENT, 25 * kMs}};
    for (const auto& w : want) {
        SCOPED_TRACE(fovea_render_hop_name(w.hop));
        const fovea_hop_stats s = fl.hop(w.hop);
        EXPECT_EQ(s.count, 100u);
        EXPECT_EQ(s.negative, 0u);
        expect_near_ns(s.p50_ns, w.ns);
        expect_near_ns(s.p999_ns, w.ns);
        EXPECT_EQ(s.min_ns, w.ns);
        EXPECT_EQ(s.max_ns, w.ns);
        EXPECT_DOUBLE_EQ(s.mean_ns, static_cast<double>(w.ns));
    }
    const auto c = fl.counters();
    EXPECT_EQ(c.frames, 100u);
    EXPECT_EQ(c.submitted, 100u);
    EXPECT_EQ(c.presented, 100u);
    EXPECT_EQ(c.stale_frames, 0u);
}

TEST(FrameLatency, PercentilesFollowTheDistribution) {
    FrameLatency fl;
    // publish -> read of 1..1000 us: p50 ~500 us, p90 ~900 us, p99 ~990 us, max 1000 us
    for (int64_t i = 1; i <= 1000; ++i) {
        const auto r = gaze(static_cast<uint64_t>(i), 10 * kMs, 20 * kMs);
        fl.gaze_read(r, 20 * kMs + i * 1000);
    }
    const auto s = fl.hop(FOVEA_HOP_PUBLISH_TO_READ);
    EXPECT_EQ(s.count, 1000u);
    expect_near_ns(s.p50_ns, 500'000);
    expect_near_ns(s.p90_ns, 900'000);
    expect_near_ns(s.p99_ns, 990'000);
    EXPECT_EQ(s.max_ns, 1'000'000);
    EXPECT_EQ(s.min_ns, 1'000);
    // no frame used these reads: the frame hops stay empty
    EXPECT_EQ(fl.hop(FOVEA_HOP_READ_TO_FRAME_BEGIN).count, 0u);
    EXPECT_EQ(fl.counters().frames, 0u);
}

TEST(FrameLatency, ReadToFrameBeginOnlyForTheRecordLastRead) {
    FrameLatency fl;
    const auto a = gaze(7, 1 * kMs, 2 * kMs);
    const auto b = gaze(8, 3 * kMs, 4 * kMs);
    fl.gaze_read(a, 5 * kMs);
    fl.frame_begin(&b, 6 * kMs);  // b was never read through the API
    EXPECT_EQ(fl.hop(FOVEA_HOP_READ_TO_FRAME_BEGIN).count, 0u);
    EXPECT_EQ(fl.hop(FOVEA_HOP_CAPTURE_TO_FRAME_BEGIN).count, 1u);
    // same index from a restarted writer (another publish time) is another record
    const auto a2 = gaze(7, 1 * kMs, 2 * kMs + 1);
    fl.frame_begin(&a2, 7 * kMs);
    EXPECT_EQ(fl.hop(FOVEA_HOP_READ_TO_FRAME_BEGIN).count, 0u);
    fl.frame_begin(&a, 8 * kMs);
    const auto s = fl.hop(FOVEA_HOP_READ_TO_FRAME_BEGIN);
    EXPECT_EQ(s.count, 1u);
    EXPECT_EQ(s.max_ns, 3 * kMs);
}

TEST(FrameLatency, StaleFramesAgainstTheThreshold) {
    FrameLatency fl;
    EXPECT_EQ(fl.counters().stale_threshold_ns, FOVEA_STALE_GAZE_DEFAULT_NS);
    const auto r = gaze(1, 100 * kMs, 101 * kMs);
    EXPECT_EQ(fl.frame_begin(&r, 110 * kMs), 10 * kMs);  // 10 ms: fresh
    EXPECT_EQ(fl.frame_begin(&r, 140 * kMs), 40 * kMs);  // exactly the threshold: fresh
    EXPECT_EQ(fl.frame_begin(&r, 141 * kMs), 41 * kMs);  // stale
    EXPECT_EQ(fl.frame_begin(nullptr, 150 * kMs), -1);   // no gaze at all: stale
    auto c = fl.counters();
    EXPECT_EQ(c.frames, 4u);
    EXPECT_EQ(c.stale_frames, 2u);
    EXPECT_EQ(c.frames_without_gaze, 1u);
    EXPECT_EQ(fl.hop(FOVEA_HOP_CAPTURE_TO_FRAME_BEGIN).count, 3u);

    fl.set_stale_threshold_ns(5 * kMs);
    fl.frame_begin(&r, 110 * kMs);
    c = fl.counters();
    EXPECT_EQ(c.stale_threshold_ns, 5 * kMs);
    EXPECT_EQ(c.stale_frames, 3u);

    fl.reset();
    c = fl.counters();
    EXPECT_EQ(c.frames, 0u);
    EXPECT_EQ(c.stale_frames, 0u);
    EXPECT_EQ(c.stale_threshold_ns, 5 * kMs);  // reset keeps the threshold
    EXPECT_EQ(fl.hop(FOVEA_HOP_CAPTURE_TO_FRAME_BEGIN).count, 0u);
}

TEST(FrameLatency, ErrorsAreCodesWithText) {
    fovea_frame_latency* fl = nullptr;
    ASSERT_EQ(fovea_frame_latency_create(&fl), FOVEA_OK);
    EXPECT_EQ(fovea_frame_latency_set_stale_threshold(fl, 0), FOVEA_E_INVALID_ARGUMENT);
    EXPECT_NE(std::strstr(fovea_last_error(), "stale threshold"), nullptr);
    EXPECT_EQ(fovea_frame_submitted(fl, 0), FOVEA_E_NO_DATA);
    EXPECT_EQ(fovea_frame_presented(fl, 0), FOVEA_E_NO_DATA);
    EXPECT_EQ(fovea_frame_begin(fl, nullptr, -5, nullptr), FOVEA_E_INVALID_ARGUMENT);
    EXPECT_EQ(fovea_frame_gaze_read(fl, nullptr, 0), FOVEA_E_INVALID_ARGUMENT);
    fovea_hop_stats s{};
    EXPECT_EQ(fovea_frame_latency_hop(fl, static_cast<fovea_render_hop>(9), &s),
              FOVEA_E_INVALID_ARGUMENT);
    // begin -> present without a submit is refused and leaves the frame open for the submit
    ASSERT_EQ(fovea_frame_begin(fl, nullptr, 0, nullptr), FOVEA_OK);
    EXPECT_EQ(fovea_frame_presented(fl, 0), FOVEA_E_NO_DATA);
    EXPECT_EQ(fovea_frame_submitted(fl, 0), FOVEA_OK);
    EXPECT_EQ(fovea_frame_presented(fl, 0), FOVEA_OK);
    EXPECT_EQ(fovea_frame_presented(fl, 0), FOVEA_E_NO_DATA);  // closed
    EXPECT_STREQ(fovea_status_string(FOVEA_E_REJECTED), "FOVEA_E_REJECTED");
    fovea_frame_latency_destroy(&fl);
    EXPECT_EQ(fl, nullptr);
    fovea_frame_latency_destroy(&fl);  // safe on NULL
}

// A stand-in for fovead's control socket: accepts one connection per serve(), keeps the request
// line and answers with `reply` (or nothing).
class FakeDaemon {
public:
    explicit FakeDaemon(const std::string& instance) {
        dir_ = std::filesystem::temp_directory_path() /
               ("fovea_frame_latency_" + std::to_string(getpid()) + "_" + instance);
        std::filesystem::remove_all(dir_);
        std::filesystem::create_directories(dir_);
        setenv("FOVEA_RUNTIME_DIR", dir_.c_str(), 1);
        fd_ = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
        sockaddr_un addr{};
        addr.sun_family = AF_UNIX;
        const std::string path = (dir_ / (instance + ".sock")).string();
        std::strncpy(addr.sun_path, path.c_str(), sizeof addr.sun_path - 1);
        EXPECT_EQ(bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
        EXPECT_EQ(listen(fd_, 4), 0);
    }
    ~FakeDaemon() {
        if (thread_.joinable()) thread_.join();
        close(fd_);
        std::filesystem::remove_all(dir_);
        unsetenv("FOVEA_RUNTIME_DIR");
    }
    void serve(std::string reply) {
        thread_ = std::thread([this, reply] {
            const int c = accept(fd_, nullptr, nullptr);
            if (c < 0) return;
            std::string in;
            char buf[4096];
            while (in.find('\n') == std::string::npos) {
                const ssize_t n = recv(c, buf, sizeof buf, 0);
                if (n <= 0) break;
                in.append(buf, static_cast<std::size_t>(n));
            }
            request_ = in;
            if (!reply.empty()) {
                send(c, reply.data(), reply.size(), MSG_NOSIGNAL);
            } else {
                char b;  // hold the connection until the client gives up
                while (recv(c, &b, 1, 0) > 0) {}
            }
            close(c);
        });
    }
    std::string request() {
        if (thread_.joinable()) thread_.join();
        return request_;
    }

private:
    std::filesystem::path dir_;
    int fd_ = -1;
    std::thread thread_;
    std::string request_;
};

TEST(FrameLatency, ReportIsTheRequestFoveadParses) {
    FakeDaemon d("fl-report");
    FrameLatency fl;
    for (uint64_t i = 0; i < 50; ++i) full_frame(fl, i, static_cast<int64_t>(i + 1) * 100 * kMs);
    fl.frame_begin(nullptr, 6000 * kMs);  // one frame without gaze
    d.serve("{\"accepted\":true,\"ok\":true}\n");
    fl.report("fl-report", 2000);
    const std::string line = d.request();
    ASSERT_FALSE(line.empty());
    EXPECT_EQ(line.back(), '\n');
    const json j = json::parse(line);
    EXPECT_EQ(j["cmd"], "latency.report");
    // the daemon's own parser: every pipeline hop present and equal to the SDK's numbers
    auto stats = fovea::record::LatencyStats::from_json(j["hops"]);
    ASSERT_TRUE(stats) << stats.error().message;
    using fovea::record::Hop;
    const std::pair<Hop, fovea_render_hop> pairs[] = {
        {Hop::kPublishToRead, FOVEA_HOP_PUBLISH_TO_READ},
        {Hop::kReadToFrameBegin, FOVEA_HOP_READ_TO_FRAME_BEGIN},
        {Hop::kFrameBeginToSubmit, FOVEA_HOP_FRAME_BEGIN_TO_SUBMIT},
        {Hop::kSubmitToPresent, FOVEA_HOP_SUBMIT_TO_PRESENT}};
    for (const auto& [daemon_hop, sdk_hop] : pairs) {
        const auto& h = stats->hop(daemon_hop);
        const auto s = fl.hop(sdk_hop);
        EXPECT_EQ(h.count(), s.count);
        EXPECT_EQ(static_cast<int64_t>(h.percentile(0.99)), s.p99_ns);
        EXPECT_EQ(static_cast<int64_t>(h.max_ns()), s.max_ns);
    }
    // the gaze-age hops travel in "hops" too, in the same histogram form
    for (const char* name :
         {"capture_to_frame_begin", "publish_to_frame_begin", "capture_to_present"}) {
        fovea::LatencyHistogram h;
        ASSERT_TRUE(fovea::record::histogram_from_json(j["hops"][name], h)) << name;
        EXPECT_EQ(h.count(), 50u) << name;
    }
    EXPECT_EQ(j["frames"], 51);
    EXPECT_EQ(j["stale_frames"], 1);
    EXPECT_EQ(j["frames_without_gaze"], 1);
    EXPECT_EQ(j["stale_threshold_ns"], FOVEA_STALE_GAZE_DEFAULT_NS);
}

// Found by tests/fuzz/fuzz_latency_json: a report whose min is above its max was accepted, and
// percentile() then clamped into an empty range (undefined behaviour).
TEST(FrameLatency, HistogramWithMinAboveMaxIsRefused) {
    fovea::LatencyHistogram h;
    const auto j = nlohmann::json::parse(
        R"({"count":1,"negative":0,"sum_ns":123456,"min_ns":246912,"max_ns":123456,)"
        R"("buckets":[[1000,1]]})");
    EXPECT_FALSE(fovea::record::histogram_from_json(j, h));
    EXPECT_EQ(h.count(), 0u);
    auto ok = j;
    ok["min_ns"] = 123456;
    EXPECT_TRUE(fovea::record::histogram_from_json(ok, h));
    EXPECT_EQ(h.percentile(0.5), 123456u);
}

TEST(FrameLatency, WideDistributionsAreCoarsenedToFitTheDaemonsLimit) {
    FakeDaemon d("fl-wide");
    FrameLatency fl;
    // every bucket of every hop non-empty would be ~250 KB of JSON
    int64_t t = 1;
    for (int64_t v = 1; v < (int64_t{1} << 40); v += v / 64 + 1, ++t) {
        const auto r = gaze(static_cast<uint64_t>(t), 0, 0);
        fl.gaze_read(r, v);
        fl.frame_begin(&r, v);
        fl.submitted(2 * v);
        fl.presented(3 * v);
    }
    d.serve("{\"accepted\":true,\"ok\":true}\n");
    fl.report("fl-wide", 2000);
    const std::string line = d.request();
    EXPECT_LT(line.size(), 64u * 1024u);
    const json j = json::parse(line);
    auto stats = fovea::record::LatencyStats::from_json(j["hops"]);
    ASSERT_TRUE(stats) << stats.error().message;
    const auto& h = stats->hop(fovea::record::Hop::kPublishToRead);
    const auto s = fl.hop(FOVEA_HOP_PUBLISH_TO_READ);
    EXPECT_EQ(h.count(), s.count);
    EXPECT_EQ(static_cast<int64_t>(h.max_ns()), s.max_ns);  // exact despite the coarsening
    EXPECT_NEAR(static_cast<double>(h.percentile(0.5)), static_cast<double>(s.p50_ns),
                0.05 * static_cast<double>(s.p50_ns));
}

TEST(FrameLatency, ReportErrors) {
    FrameLatency fl;
    {
        FakeDaemon d("fl-refuse");
        d.serve("{\"error\":\"too many reporting clients\",\"ok\":false}\n");
        try {
            fl.report("fl-refuse", 2000);
            ADD_FAILURE() << "a refused report must throw";
        } catch (const fovea::ClientError& e) {
            EXPECT_EQ(e.status(), FOVEA_E_REJECTED);
            EXPECT_NE(std::string(e.what()).find("too many reporting clients"), std::string::npos)
                << e.what();
        }
    }
    {
        FakeDaemon d("fl-silent");
        d.serve("");  // never answers
        EXPECT_EQ(fovea_frame_latency_report(fl.handle(), "fl-silent", 100), FOVEA_E_TIMEOUT);
        // let the stand-in see the client hang up
    }
    {
        FakeDaemon d("fl-none");  // sets the runtime dir; no socket for another instance
        EXPECT_EQ(fovea_frame_latency_report(fl.handle(), "nobody-here", 100), FOVEA_E_NOT_FOUND);
        EXPECT_NE(std::strstr(fovea_last_error(), "nobody-here"), nullptr);
        d.serve("{\"ok\":true}\n");
        fl.report("fl-none", 1000);  // unblocks the stand-in's accept
    }
    EXPECT_EQ(fovea_frame_latency_report(fl.handle(), "bad/name", 100), FOVEA_E_INVALID_ARGUMENT);
}

// The reply is JSON, read as JSON: spacing is free, escapes are decoded, and a line that is not
// an object is a refusal that quotes it.
TEST(FrameLatency, TheDaemonsReplyIsReadAsJson) {
    FrameLatency fl;
    {
        FakeDaemon d("fl-spaced");
        d.serve("{ \"ok\" : true, \"accepted\": true }\n");
        EXPECT_EQ(fovea_frame_latency_report(fl.handle(), "fl-spaced", 2000), FOVEA_OK)
            << fovea_last_error();
    }
    {
        FakeDaemon d("fl-escaped");
        d.serve("{\"error\":\"hop \\\"x\\\" unknown\",\"ok\":false}\n");
        EXPECT_EQ(fovea_frame_latency_report(fl.handle(), "fl-escaped", 2000), FOVEA_E_REJECTED);
        EXPECT_NE(std::strstr(fovea_last_error(), "hop \"x\" unknown"), nullptr)
            << fovea_last_error();
    }
    {
        FakeDaemon d("fl-garbled");
        d.serve("ok true\n");
        EXPECT_EQ(fovea_frame_latency_report(fl.handle(), "fl-garbled", 2000), FOVEA_E_REJECTED);
        EXPECT_NE(std::strstr(fovea_last_error(), "not a JSON object: ok true"), nullptr)
            << fovea_last_error();
    }
}

// Statistics and reports from another thread while the render thread records (TSan).
TEST(FrameLatency, ReadersRunAlongsideTheRenderThread) {
    FakeDaemon d("fl-threads");
    FrameLatency fl;
    std::atomic<bool> done{false};
    std::thread render([&] {
        for (uint64_t i = 0; i < 20000; ++i)
            full_frame(fl, i, static_cast<int64_t>(i + 1) * 30 * kMs);
        done = true;
    });
    uint64_t last = 0;
    bool reported = false;
    while (!done) {
        const auto s = fl.hop(FOVEA_HOP_CAPTURE_TO_PRESENT);
        EXPECT_GE(s.count, last);
        last = s.count;
        const auto c = fl.counters();
        EXPECT_LE(c.stale_frames, c.frames);
        if (!reported && last > 1000) {
            // a report taken mid-frame must still add up (bucket counts == count)
            d.serve("{\"ok\":true}\n");
            fl.report("fl-threads", 2000);
            auto mid = fovea::record::LatencyStats::from_json(json::parse(d.request())["hops"]);
            EXPECT_TRUE(mid) << mid.error().message;
            reported = true;
        }
    }
    render.join();
    d.serve("{\"ok\":true}\n");
    fl.report("fl-threads", 2000);
    const json j = json::parse(d.request());
    auto stats = fovea::record::LatencyStats::from_json(j["hops"]);
    ASSERT_TRUE(stats) << stats.error().message;
    EXPECT_EQ(stats->hop(fovea::record::Hop::kSubmitToPresent).count(), 20000u);
}

}  // namespace
