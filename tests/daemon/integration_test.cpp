// fovead and the fovea CLI as a user runs them: real processes, real shm, real Unix sockets.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "../support/child_process.hpp"

#include "control_client.hpp"
#include "fovea/client.hpp"
#include "paths.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace std::chrono_literals;

using fovea::testing::kSlowdown;
const std::string& kFovead = fovea::testing::kFoveadBinary;
const std::string& kFovea = fovea::testing::kFoveaBinary;

using Proc = fovea::testing::ChildProcess;

struct DaemonTest : ::testing::Test {
    std::string dir;
    std::string instance;

    void SetUp() override {
        // Short names: a Unix socket path must fit in 108 bytes.
        static int serial = 0;
        instance = "it" + std::to_string(getpid()) + "-" + std::to_string(++serial);
        dir = fs::temp_directory_path() / ("fv-" + instance);
        fs::create_directories(dir);
        setenv("FOVEA_RUNTIME_DIR", dir.c_str(), 1);
    }
    void TearDown() override { fs::remove_all(dir); }

    std::unique_ptr<Proc> spawn(const std::string& exe, std::vector<std::string> args) {
        static int n = 0;
        ++n;
        return fovea::testing::spawn_logged(exe, std::move(args), dir + "/out" + std::to_string(n),
                                            dir + "/err" + std::to_string(n));
    }

    std::unique_ptr<Proc> start_daemon(std::vector<std::string> extra = {}) {
        extra.insert(extra.begin(), {"--instance", instance});
        auto d = spawn(kFovead, extra);
        // Ready when the control socket answers.
        const auto end = std::chrono::steady_clock::now() + 5s * kSlowdown;
        while (std::chrono::steady_clock::now() < end) {
            if (query("status").ok()) return d;
            std::this_thread::sleep_for(10ms);
        }
        ADD_FAILURE() << "fovead did not come up: " << d->err();
        return d;
    }

    fovea::Result<json> query(const std::string& cmd) {
        return fovea::daemon::control_request(fovea::daemon::control_socket_path(instance),
                                              {{"cmd", cmd}}, 2000 * kSlowdown);
    }

    std::unique_ptr<Proc> cli(std::vector<std::string> args) {
        args.insert(args.begin(), {"--instance", instance});
        return spawn(kFovea, args);
    }
};

int count_lines(const std::string& s) {
    int n = 0;
    for (char c : s) n += c == '\n';
    return n;
}

TEST_F(DaemonTest, WatchPrintsHundredSamplesWithinTwoSeconds) {
    const auto t0 = std::chrono::steady_clock::now();
    auto d = spawn(kFovead, {"--instance", instance});
    auto w = cli({"watch", "--count", "100"});
    ASSERT_EQ(w->wait(10s * kSlowdown), 0) << w->err() << d->err();
    const auto elapsed = std::chrono::steady_clock::now() - t0;
    EXPECT_EQ(count_lines(w->out()), 100);
    EXPECT_NE(w->out().find("gaze=("), std::string::npos);
    EXPECT_LT(elapsed, 2s * kSlowdown) << "daemon start to 100 printed samples";
    std::printf("daemon start -> 100 samples printed: %.0f ms\n",
                std::chrono::duration<double, std::milli>(elapsed).count());
}

// A reader outlives a fovead killed with -9: `fovea watch` follows the restarted daemon's new
// ring (its indices start again near 0) instead of exiting as if the tracker had stopped.
TEST_F(DaemonTest, WatchFollowsAFoveadRestartedAfterKillDashNine) {
    const auto lines_within = [](Proc& p, std::size_t from, int n, std::chrono::milliseconds t) {
        const auto end = std::chrono::steady_clock::now() + t;
        while (count_lines(p.out().substr(std::min(from, p.out().size()))) < n &&
               std::chrono::steady_clock::now() < end)
            std::this_thread::sleep_for(10ms);
        return count_lines(p.out().substr(std::min(from, p.out().size()))) >= n;
    };
    auto d = start_daemon();
    auto w = cli({"watch", "--wait", "10"});
    ASSERT_TRUE(lines_within(*w, 0, 200, 5s * kSlowdown)) << w->err();
    kill(d->pid, SIGKILL);
    d->wait();
    std::this_thread::sleep_for(300ms);  // the reader notices the dead writer's silence
    const std::size_t before = w->out().rfind('\n') + 1;
    auto again = start_daemon();
    ASSERT_TRUE(lines_within(*w, before, 50, 5s * kSlowdown))
        << "fovea watch printed nothing from the restarted fovead: " << w->err();
    const std::string after = w->out().substr(before);
    const uint64_t index = std::stoull(after.substr(after.find('#') + 1));
    EXPECT_LT(index, 5000u) << "not the new ring's numbering: " << after.substr(0, 200);
    EXPECT_EQ(waitpid(w->pid, nullptr, WNOHANG), 0) << "fovea watch exited: " << w->err();
}

TEST_F(DaemonTest, StatusReportsDevicesRingAndRates) {
    auto d = start_daemon();
    std::this_thread::sleep_for(600ms);
    auto s = query("status");
    ASSERT_TRUE(s.ok()) << s.error().message;
    EXPECT_TRUE((*s)["ok"]);
    EXPECT_EQ((*s)["instance"], instance);
    ASSERT_EQ((*s)["devices"].size(), 1u);
    const json& dev = (*s)["devices"][0];
    EXPECT_EQ(dev["driver"], "sim");
    EXPECT_GT(dev["samples"].get<uint64_t>(), 100u);
    EXPECT_GT(dev["measured_rate_hz"].get<double>(), 100.0);
    EXPECT_GT((*s)["ring"]["head"].get<uint64_t>(), 100u);
    EXPECT_GT((*s)["uptime_s"].get<double>(), 0.5);
    EXPECT_EQ((*s)["processing"]["landing_prediction"], "skipped: no reader attached");
    {
        fovea::Client c(instance);
        std::this_thread::sleep_for(600ms);
        EXPECT_EQ(query("status").value()["processing"]["landing_prediction"], "on");
    }
    auto status_cli = cli({"status"});
    ASSERT_EQ(status_cli->wait(), 0) << status_cli->err();
    EXPECT_TRUE(json::parse(status_cli->out())["devices"].is_array());
}

// publish = "live" puts every sample in the ring as soon as the chain filtered it; "final"
// holds it for the event detector's look-ahead. The device-side hops describe the ring.
struct PublishModeLatency {
    double receive_to_processed_p50_us = -1;
    double lookahead_ms = -1;
    std::string mode;
    uint32_t ring_flags = 0;
};

PublishModeLatency measure_publish_mode(DaemonTest& t, const std::string& mode,
                                        const std::string& extra_processing = "") {
    PublishModeLatency m;
    const std::string cfg = t.dir + "/publish-" + mode + ".toml";
    std::ofstream(cfg) << "[processing]\npublish = \"" << mode << "\"\n" << extra_processing;
    auto d = t.start_daemon({"--config", cfg});
    std::this_thread::sleep_for(800ms);
    {
        fovea::Client c(t.instance);
        const auto r = c.latest();
        EXPECT_TRUE(r.has_value());
        if (r) m.ring_flags = r->flags;
    }
    auto s = t.query("status");
    EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
    if (!s.ok()) return m;
    const json& lat = (*s)["latency"];
    EXPECT_TRUE(lat.contains("receive_to_processed")) << s->dump();
    if (lat.contains("receive_to_processed"))
        m.receive_to_processed_p50_us = lat["receive_to_processed"]["p50_us"].get<double>();
    m.mode = (*s)["processing"]["publish"].get<std::string>();
    m.lookahead_ms = (*s)["processing"]["lookahead_ms"].get<double>();
    EXPECT_TRUE(t.query("shutdown").ok());
    EXPECT_EQ(d->wait(), 0) << d->err();
    return m;
}

TEST_F(DaemonTest, LivePublicationSkipsTheLookaheadFinalWaitsForIt) {
    const PublishModeLatency live = measure_publish_mode(*this, "live");
    EXPECT_EQ(live.mode, "live");
    EXPECT_GE(live.receive_to_processed_p50_us, 0.0);
    EXPECT_LT(live.receive_to_processed_p50_us, 5000.0 * kSlowdown);
    EXPECT_TRUE(live.ring_flags & FOVEA_FLAG_PROVISIONAL);

    // The detector's default bound, plus the online microsaccade stage's lag (2 x its 20 ms
    // interval + 1 sample at 1 kHz), which status reports with it.
    EXPECT_NEAR(live.lookahead_ms, 391.0, 2.0);

    // A shorter bound from the configuration keeps the final wait measurable in this test.
    const PublishModeLatency final_ = measure_publish_mode(*this, "final", "lookahead_ms = 120\n");
    EXPECT_EQ(final_.mode, "final");
    EXPECT_NEAR(final_.lookahead_ms, 161.0, 2.0);  // 120 + the microsaccade stage's 41
    EXPECT_FALSE(final_.ring_flags & FOVEA_FLAG_PROVISIONAL);
    // Held for the look-ahead: within 20% of it (plus scheduling slack on a loaded machine).
    EXPECT_GT(final_.receive_to_processed_p50_us, 800.0 * final_.lookahead_ms);
    EXPECT_LT(final_.receive_to_processed_p50_us,
              1200.0 * final_.lookahead_ms + 20000.0 * kSlowdown);
    std::printf("receive_to_processed p50: live %.1f us, final %.1f us (look-ahead %.1f ms)\n",
                live.receive_to_processed_p50_us, final_.receive_to_processed_p50_us,
                final_.lookahead_ms);
}

TEST_F(DaemonTest, BadConfigIsOneClearLineAndNonZero) {
    const std::string cfg = dir + "/bad.toml";
    std::ofstream(cfg) << "[display]\nwidth_px = \"wide\"\n";
    auto d = spawn(kFovead, {"--instance", instance, "--config", cfg});
    EXPECT_EQ(d->wait(), 2);
    EXPECT_EQ(count_lines(d->err()), 1) << d->err();
    EXPECT_NE(d->err().find("display.width_px"), std::string::npos) << d->err();

    auto u = spawn(kFovead, {"--instance", instance, "--frobnicate"});
    EXPECT_EQ(u->wait(), 2);
    EXPECT_EQ(count_lines(u->err()), 1) << u->err();
    EXPECT_NE(u->err().find("--frobnicate"), std::string::npos) << u->err();

    std::ofstream(cfg) << "[[device]]\ndriver = \"warp-drive\"\n";
    auto w = spawn(kFovead, {"--instance", instance, "--config", cfg});
    EXPECT_EQ(w->wait(), 2);
    EXPECT_NE(w->err().find("unknown driver 'warp-drive'"), std::string::npos) << w->err();
}

TEST_F(DaemonTest, SecondDaemonOnSameInstanceRefusesToStart) {
    auto d = start_daemon();
    auto second = spawn(kFovead, {"--instance", instance});
    EXPECT_EQ(second->wait(), 2);
    EXPECT_NE(second->err().find("already running"), std::string::npos) << second->err();
    EXPECT_TRUE(query("status").ok());  // the first is unaffected
}

TEST_F(DaemonTest, SigtermShutsDownCleanly) {
    auto d = start_daemon();
    ASSERT_GT(d->pid, 0);
    kill(d->pid, SIGTERM);
    EXPECT_EQ(d->wait(), 0) << d->err();
    EXPECT_FALSE(fs::exists(fovea::daemon::control_socket_path(instance)));
    fovea_client* c = nullptr;
    EXPECT_EQ(fovea_client_open(instance.c_str(), FOVEA_STREAM_GAZE, &c), FOVEA_E_NOT_FOUND);
}

TEST_F(DaemonTest, ShutdownCommandStopsTheDaemon) {
    auto d = start_daemon();
    auto r = query("shutdown");
    ASSERT_TRUE(r.ok());
    EXPECT_TRUE((*r)["ok"]);
    EXPECT_EQ(d->wait(), 0);
}

TEST_F(DaemonTest, OversizedAndMalformedRequestsLeaveTheDaemonUnaffected) {
    auto d = start_daemon();
    const std::string path = fovea::daemon::control_socket_path(instance);
    auto send_raw = [&](const std::string& bytes) {
        int fd = socket(AF_UNIX, SOCK_STREAM, 0);
        sockaddr_un a{};
        a.sun_family = AF_UNIX;
        std::strncpy(a.sun_path, path.c_str(), sizeof a.sun_path - 1);
        EXPECT_EQ(connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
        [[maybe_unused]] auto n = send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL);
        std::string reply;
        char buf[512];
        ssize_t k;
        while ((k = recv(fd, buf, sizeof buf, 0)) > 0) reply.append(buf, static_cast<size_t>(k));
        close(fd);  // recv returned 0: the daemon closed the connection
        return reply;
    };
    EXPECT_NE(send_raw(std::string(100'000, 'x')).find("request too large"), std::string::npos);
    EXPECT_NE(send_raw("{not json\n").find("malformed request"), std::string::npos);
    auto s = query("status");
    ASSERT_TRUE(s.ok());
    EXPECT_EQ((*s)["control"]["rejected"].get<int>(), 2);
}

TEST_F(DaemonTest, RecordWritesEverySampleAsCsv) {
    auto d = start_daemon();
    const std::string out = dir + "/rec.csv";
    auto r = cli({"record", "--out", out, "--duration", "1"});
    ASSERT_EQ(r->wait(10s * kSlowdown), 0) << r->err();
    std::ifstream in(out);
    std::string first, header, line;
    std::getline(in, first);
    std::getline(in, header);
    EXPECT_EQ(first.rfind("# fovea gaze recording v1", 0), 0u);
    EXPECT_EQ(header.rfind("index,t_capture_ns,", 0), 0u);
    uint64_t prev = 0, rows = 0;
    while (std::getline(in, line)) {
        const uint64_t idx = std::stoull(line.substr(0, line.find(',')));
        if (rows++) { EXPECT_EQ(idx, prev + 1) << "a sample is missing"; }
        prev = idx;
    }
    EXPECT_GT(rows, 500u);  // the simulated tracker runs at 1 kHz by default
}

// fovead configured for a serial tracker, fed by `fovea simulate serial` through a real pty with
// garbage and dropped frames, and reopening the port: gaze flows, drops are counted.
TEST_F(DaemonTest, SerialTrackerThroughAPtyPublishesGazeAndCountsDrops) {
    const std::string link = dir + "/tty";
    auto sim = cli({"simulate", "serial", "--link", link, "--rate", "500", "--garbage", "0.05",
                    "--drop", "0.02", "--reopen-every", "1.5", "--unplugged-ms", "100"});
    for (int i = 0; i < 500 && !fs::exists(link); ++i) std::this_thread::sleep_for(10ms);
    ASSERT_TRUE(fs::exists(link)) << sim->err();
    const std::string cfg = dir + "/serial.toml";
    std::ofstream(cfg) << "[[device]]\ndriver = \"serial\"\nport = \"" << link << "\"\n";
    auto d = start_daemon({"--config", cfg});
    auto w = cli({"watch", "--count", "200"});
    ASSERT_EQ(w->wait(20s * kSlowdown), 0) << w->err() << d->err();
    std::this_thread::sleep_for(2500ms);  // across at least one unplug/replug
    auto s = query("status");
    ASSERT_TRUE(s.ok()) << s.error().message;
    const json& dev = (*s)["devices"][0];
    EXPECT_EQ(dev["driver"], "serial");
    EXPECT_GT(dev["samples"].get<uint64_t>(), 500u);
    EXPECT_GT(dev["frames_dropped"].get<uint64_t>() + dev["frames_lost"].get<uint64_t>(), 0u);
    EXPECT_GE(dev["reconnects"].get<uint64_t>(), 1u);
    EXPECT_TRUE(query("status").ok());  // still up
}

// The same through the Gazepoint Open Gaze API on loopback TCP.
TEST_F(DaemonTest, GazepointTrackerOverTcpPublishesGaze) {
    auto sim = cli({"simulate", "gazepoint", "--port", "0", "--rate", "150"});
    const std::string address = sim->first_line();
    ASSERT_FALSE(address.empty()) << sim->err();
    const std::string cfg = dir + "/gp.toml";
    std::ofstream(cfg) << "[[device]]\ndriver = \"gazepoint\"\naddress = \"" << address << "\"\n";
    auto d = start_daemon({"--config", cfg});
    auto w = cli({"watch", "--count", "100"});
    ASSERT_EQ(w->wait(20s * kSlowdown), 0) << w->err() << d->err();
    EXPECT_EQ(count_lines(w->out()), 100);
    auto s = query("status");
    ASSERT_TRUE(s.ok());
    EXPECT_EQ((*s)["devices"][0]["driver"], "gazepoint");
    EXPECT_TRUE((*s)["devices"][0]["connected"].get<bool>());

    // The Open Gaze API never states the rate; the driver measures it from the first 257
    // samples. The gaze chain must then run at 150 Hz, not at the 1 kHz it started from: its
    // windows and its look-ahead are counted in samples.
    for (int i = 0; i < 100; ++i) {
        s = query("status");
        ASSERT_TRUE(s.ok());
        if ((*s)["devices"][0]["nominal_rate_hz"].get<double>() > 0 &&
            (*s)["devices"][0]["samples"].get<uint64_t>() > 400)
            break;
        std::this_thread::sleep_for(100ms);
    }
    const json& dev = (*s)["devices"][0];
    EXPECT_NEAR(dev["nominal_rate_hz"].get<double>(), 150.0, 1.0);
    // 350 ms of look-ahead plus the online microsaccade stage's lag (2 x 20 ms + 1 sample:
    // 2 x 3 + 1 samples at 150 Hz).
    EXPECT_NEAR(dev["lookahead_ms"].get<double>(), 397.0, 15.0);
    EXPECT_NEAR(dev["lookahead_samples"].get<double>(), 59.0, 2.0);
    // ...and the ring's readers are told the measured rate (the header said 0 at creation).
    EXPECT_NEAR(fovea::Client(instance).info().nominal_rate_hz, 150.0, 1.0);
}

}  // namespace
