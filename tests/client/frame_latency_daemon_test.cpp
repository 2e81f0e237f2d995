// The render hops end to end: a real fovead (simulated tracker) on a private instance, a client
// that reads its ring, reports frame events through fovea_frame_latency and sends them with
// fovea_frame_latency_report; `status` over the control socket then carries the render hops next
// to the daemon's device hops.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "control_client.hpp"
#include "fovea/client.hpp"
#include "paths.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace std::chrono_literals;

const std::string kFovead = std::string(FOVEA_BINARY_DIR) + "/daemon/fovead";

class FrameLatencyDaemon : public ::testing::Test {
protected:
    void SetUp() override {
        if (!fs::exists(kFovead)) GTEST_SKIP() << "fovead not built at " << kFovead;
        instance_ = "fl" + std::to_string(getpid());
        dir_ = fs::temp_directory_path() / ("fv-" + instance_);
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        setenv("FOVEA_RUNTIME_DIR", dir_.c_str(), 1);
        const std::string log = (dir_ / "fovead.log").string();
        std::vector<std::string> args = {kFovead, "--instance", instance_, "--log-level", "warn"};
        std::vector<char*> argv;
        for (auto& a : args) argv.push_back(a.data());
        argv.push_back(nullptr);
        posix_spawn_file_actions_t fa;
        posix_spawn_file_actions_init(&fa);
        posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        posix_spawn_file_actions_adddup2(&fa, 1, 2);
        ASSERT_EQ(posix_spawn(&daemon_, argv[0], &fa, nullptr, argv.data(), environ), 0);
        posix_spawn_file_actions_destroy(&fa);
        socket_ = fovea::daemon::control_socket_path(instance_);
        for (int i = 0; i < 400 && !fs::exists(socket_); ++i) std::this_thread::sleep_for(25ms);
        ASSERT_TRUE(fs::exists(socket_)) << "fovead did not start; see " << log;
    }
    void TearDown() override {
        if (daemon_ > 0) {
            kill(daemon_, SIGTERM);
            waitpid(daemon_, nullptr, 0);
        }
        fs::remove_all(dir_);
        unsetenv("FOVEA_RUNTIME_DIR");
    }
    json status() const {
        auto r = fovea::daemon::control_request(socket_, {{"cmd", "status"}}, 5000);
        EXPECT_TRUE(r) << (r ? "" : r.error().message);
        return r ? *r : json();
    }

    std::string instance_, socket_;
    fs::path dir_;
    pid_t daemon_ = -1;
};

TEST_F(FrameLatencyDaemon, StatusCarriesTheReportedRenderHops) {
    std::unique_ptr<fovea::Client> client;
    for (int i = 0; i < 200 && !client; ++i) {
        try {
            client = std::make_unique<fovea::Client>(instance_);
        } catch (const fovea::ClientError&) { std::this_thread::sleep_for(25ms); }
    }
    ASSERT_TRUE(client) << "no gaze ring for instance " << instance_;

    // 30 frames about 5 ms apart from live gaze, every event stamped by the library ("now")
    fovea::FrameLatency fl;
    constexpr int kFrames = 30;
    int with_gaze = 0;
    for (int f = 0; f < kFrames; ++f) {
        uint64_t cursor = client->head();
        client->wait(cursor, 200);
        const auto r = client->latest();
        if (r) fl.gaze_read(*r);
        const int64_t age = fl.frame_begin(r ? &*r : nullptr);
        if (r) {
            EXPECT_GE(age, 0);
            ++with_gaze;
        }
        std::this_thread::sleep_for(2ms);  // "recording" the frame
        fl.submitted();
        std::this_thread::sleep_for(3ms);  // "GPU + present"
        fl.presented();
    }
    ASSERT_GT(with_gaze, 0) << "the simulated tracker published nothing";
    fl.report(instance_, 5000);

    const json s = status();
    ASSERT_TRUE(s.value("ok", false)) << s.dump();
    ASSERT_TRUE(s.contains("latency_clients")) << s.dump();
    const json& c = s["latency_clients"];
    EXPECT_EQ(c.value("clients", 0), 1) << c.dump();
    for (const char* hop : {"publish_to_read", "read_to_frame_begin"}) {
        ASSERT_TRUE(c.contains(hop)) << hop << " missing: " << c.dump();
        EXPECT_EQ(c[hop]["count"], with_gaze) << hop;
    }
    for (const char* hop : {"frame_begin_to_submit", "submit_to_present"}) {
        ASSERT_TRUE(c.contains(hop)) << hop << " missing: " << c.dump();
        EXPECT_EQ(c[hop]["count"], kFrames) << hop;
    }
    // slept >= 2 ms and >= 3 ms between the events
    EXPECT_GE(c["frame_begin_to_submit"]["p50_us"].get<double>(), 1900.0);
    EXPECT_GE(c["submit_to_present"]["p50_us"].get<double>(), 2900.0);
    ASSERT_TRUE(c.contains("gaze_age")) << c.dump();
    EXPECT_EQ(c["gaze_age"]["capture_to_frame_begin"]["count"], with_gaze);
    EXPECT_EQ(c["gaze_age"]["capture_to_present"]["count"], with_gaze);
    EXPECT_EQ(c["frames"]["frames"], kFrames);
    EXPECT_EQ(c["frames"]["without_gaze"], kFrames - with_gaze);
    EXPECT_DOUBLE_EQ(c["frames"]["stale_threshold_ms_min"].get<double>(),
                     FOVEA_STALE_GAZE_DEFAULT_NS / 1e6);
    // the device hops are there too: `fovea latency` shows all of them from this one status.
    // They are counted as samples get their final labels, one detector look-ahead (350 ms)
    // after capture, so a status this early may not carry them yet.
    json device = s;
    for (int i = 0; i < 100 && !device["latency"].contains("capture_to_receive"); ++i) {
        std::this_thread::sleep_for(20ms);
        device = status();
    }
    ASSERT_TRUE(device["latency"].contains("capture_to_receive")) << device.dump();
    EXPECT_GT(device["latency"]["capture_to_receive"].value("count", 0), 0);

    // a later report from the same process replaces the earlier one (cumulative, not added)
    fl.report(instance_, 5000);
    const json again = status();
    EXPECT_EQ(again["latency_clients"]["submit_to_present"]["count"], kFrames);
}

TEST_F(FrameLatencyDaemon, MalformedReportIsRefusedWithTheDaemonsReason) {
    auto r = fovea::daemon::control_request(
        socket_, {{"cmd", "latency.report"}, {"hops", {{"publish_to_read", {{"count", 3}}}}}},
        5000);
    ASSERT_TRUE(r) << r.error().message;
    EXPECT_FALSE(r->value("ok", true)) << r->dump();
    EXPECT_NE(r->value("error", std::string()).find("buckets"), std::string::npos) << r->dump();
}

// Found by tests/fuzz/fuzz_control: a frame counter of 1e300 reached nlohmann's get<uint64_t>(),
// which is undefined behaviour for a float, not an exception.
TEST_F(FrameLatencyDaemon, FrameCountersThatAreNotCountsAreRefusedByName) {
    for (const json& bad : {json(1e300), json(-3), json(2.5), json("7")}) {
        for (const char* key : {"frames", "stale_frames", "stale_threshold_ns"}) {
            auto r = fovea::daemon::control_request(
                socket_, {{"cmd", "latency.report"}, {"hops", json::object()}, {key, bad}}, 5000);
            ASSERT_TRUE(r) << r.error().message;
            EXPECT_FALSE(r->value("ok", true)) << key << " " << bad.dump() << " " << r->dump();
            EXPECT_NE(r->value("error", std::string()).find(key), std::string::npos) << r->dump();
        }
    }
    auto ok = fovea::daemon::control_request(
        socket_, {{"cmd", "latency.report"}, {"hops", json::object()}, {"frames", 12}}, 5000);
    ASSERT_TRUE(ok) << ok.error().message;
    EXPECT_TRUE(ok->value("ok", false)) << ok->dump();
}

}  // namespace
