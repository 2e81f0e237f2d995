// The pupil driver: Pupil's time-sync arithmetic, config errors, and end to end against
// `fovea simulate pupil` serving the real binocular_only_gaze.pldata over loopback ZeroMQ —
// in process through the driver, and through a real fovead into its ring — with garbage,
// truncated datums and restarts of the simulated Pupil Capture. The simulator forwards the
// recorded bytes, so the datums are Pupil Capture's; the network behaviour is ours.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>
#include <vector>

#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <nlohmann/json.hpp>

#include "../support/child_process.hpp"
#include "fovea/client.hpp"
#include "pupil/pupil_driver.hpp"
#include "pupil/pupil_remote.hpp"

namespace fovea::drivers::pupil {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using fovea::testing::kSlowdown;

const fs::path kGaze = fs::path(FOVEA_SHARED_DATA_DIR) /
                       "recordings/pupil/vedb_pupil_recording_interface/tests_test_data/"
                       "binocular_only_gaze.pldata";

// The time stamps in the .npy beside the .pldata: little-endian float64 after the header.
std::vector<double> npy_timestamps(const fs::path& npy) {
    std::ifstream in(npy, std::ios::binary);
    std::string d((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t hl = static_cast<uint8_t>(d[8]) | static_cast<uint8_t>(d[9]) << 8;
    std::vector<double> t((d.size() - 10 - hl) / 8);
    std::memcpy(t.data(), d.data() + 10 + hl, t.size() * 8);
    return t;
}

// The recording's own rate: the median of its time-stamp intervals.
double recorded_rate_hz(const std::vector<double>& t) {
    std::vector<double> dt;
    for (std::size_t i = 1; i < t.size(); ++i) dt.push_back(t[i] - t[i - 1]);
    std::nth_element(dt.begin(), dt.begin() + dt.size() / 2, dt.end());
    return 1.0 / dt[dt.size() / 2];
}

TEST(PupilTimeSync, DropsTheSlowestThirtyPercentAndUsesMidpoints) {
    std::vector<RoundTrip> trips;
    // Pupil clock = host + 100 s; 7 fast symmetric trips, 3 slow ones skewed to mislead.
    for (int i = 0; i < 7; ++i) trips.push_back({10.0 + i, 110.0 + i + 0.0005, 10.001 + i});
    for (int i = 0; i < 3; ++i) trips.push_back({20.0 + i, 120.0 + i + 0.04, 20.05 + i});
    const auto c = estimate_offset(trips);
    ASSERT_TRUE(c);
    EXPECT_EQ(c->kept, 7u);
    EXPECT_EQ(c->total, 10u);
    EXPECT_NEAR(c->offset_s, 100.0, 1e-9);
    EXPECT_NEAR(c->uncertainty_s, 0.0005, 1e-9);
    EXPECT_NEAR(c->sd_s, 0.0, 1e-9);
    // Pupil time far from host time (as after days of uptime): the spread must not cancel.
    std::vector<RoundTrip> far;
    for (int i = 0; i < 10; ++i)
        far.push_back({1.0 + i, 3e5 + 1.0 + i + 0.0001 + (i % 2 ? 1e-5 : -1e-5), 1.0002 + i});
    const auto f = estimate_offset(far);
    ASSERT_TRUE(f);
    EXPECT_NEAR(f->sd_s, 1e-5, 1e-6);  // sum of squares would give milliseconds here
    EXPECT_FALSE(estimate_offset({}));
    EXPECT_FALSE(estimate_offset({{1.0, NAN, 1.1}}));
}

TEST(PupilRemoteReplies, SubPortMustBeAPortOnTheRemotesHost) {
    const std::string remote = "tcp://10.0.0.7:50020";
    EXPECT_EQ(bus_address(remote, "50021").value(), "tcp://10.0.0.7:50021");
    EXPECT_EQ(bus_address(remote, "1").value(), "tcp://10.0.0.7:1");
    for (const char* bad : {"", "0", "65536", "99999999", "5002x", " 50021", "50021\n", "-1"}) {
        auto b = bus_address(remote, bad);
        ASSERT_FALSE(b.ok()) << bad;
        EXPECT_NE(b.error().message.find("'SUB_PORT' answered"), std::string::npos);
    }
    EXPECT_LT(bus_address(remote, std::string(10'000, '7')).error().message.size(), 120u);
}

// Found by fuzz_pupil_remote: "t" answered with a huge finite number ("22e188") made the clock
// offset of the round trips infinite, and every sample's host time 0.
TEST(PupilRemoteReplies, TimeReplyIsAFiniteTimeThatFitsNanosecondTicks) {
    EXPECT_DOUBLE_EQ(parse_time_reply("2294.807856069").value(), 2294.807856069);
    EXPECT_DOUBLE_EQ(parse_time_reply("12.5 trailing").value(), 12.5);  // as strtod reads it
    EXPECT_DOUBLE_EQ(parse_time_reply("1.7e9").value(), 1.7e9);         // Pupil time set to Unix
    for (const char* bad : {"", "Unknown command.", "nan", "inf", "22e188", "-1e10", "1e10"}) {
        auto t = parse_time_reply(bad);
        ASSERT_FALSE(t.ok()) << bad;
        EXPECT_NE(t.error().message.find("'t' answered"), std::string::npos);
    }
    std::vector<RoundTrip> trips;
    for (const char* reply : {"22e188", "22e188", "1e3"})
        if (auto t = parse_time_reply(reply)) trips.push_back({1.0, *t, 1.001});
    const auto c = estimate_offset(trips);
    ASSERT_TRUE(c);
    EXPECT_TRUE(std::isfinite(c->offset_s));
}

TEST(PupilConfig, ClearErrorsNamingTheKey) {
    EXPECT_TRUE(parse_config(toml::table{}).ok());
    auto r = parse_config(toml::table{{"address", "127.0.0.1:50020"}});
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("tcp://HOST:PORT"), std::string::npos);
    r = parse_config(toml::table{{"topics", toml::array{}}});
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("topics"), std::string::npos);
    r = parse_config(toml::table{{"min_confidence", 2.0}});
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("min_confidence"), std::string::npos);
}

struct Sim {
    std::unique_ptr<fovea::testing::ChildProcess> proc;
    std::string address;
};

Sim start_sim(const fs::path& dir, std::vector<std::string> extra) {
    std::vector<std::string> args = {"simulate",     "pupil",     "--recording",
                                     kGaze.string(), "--address", "tcp://127.0.0.1:0"};
    args.insert(args.end(), extra.begin(), extra.end());
    Sim s;
    s.proc = fovea::testing::spawn_logged(fovea::testing::kFoveaBinary, args,
                                          (dir / "sim.out").string(), (dir / "sim.err").string());
    s.address = s.proc->first_line(10s * kSlowdown);
    return s;
}

struct Scratch {
    fs::path dir;
    explicit Scratch(const std::string& name) {
        dir = fs::temp_directory_path() / ("fv-pupil-" + name + "-" + std::to_string(getpid()));
        fs::create_directories(dir);
    }
    ~Scratch() { fs::remove_all(dir); }
};

TEST(PupilDriver, EveryRecordedGazeDatumInOrderThroughFaultsAndRestarts) {
    if (!fs::exists(kGaze)) GTEST_SKIP() << "no " << kGaze;
    if (!fs::exists(fovea::testing::kFoveaBinary)) GTEST_SKIP() << "no fovea binary";
    Scratch tmp("drv");
    const std::vector<double> stamps =
        npy_timestamps(fs::path(kGaze).replace_extension("").string() + "_timestamps.npy");
    const uint64_t want = stamps.size();
    ASSERT_EQ(want, 665u);
    Sim sim = start_sim(tmp.dir, {"--garbage", "0.05", "--truncate", "0.05", "--restart", "0.7"});
    ASSERT_FALSE(sim.address.empty()) << sim.proc->err();
    auto cfg = toml::table{{"address", sim.address},
                           {"reconnect_min_ms", 20},
                           {"sync_interval_s", 0.5},
                           {"silence_s", 0.3}};
    auto d = make_driver(cfg, 3);
    ASSERT_TRUE(d.ok()) << d.error().message;
    boost::asio::io_context io;
    // The driver's worker thread posts samples; without a guard run_for() would stop at once.
    auto work = boost::asio::make_work_guard(io);
    std::vector<gaze::RawSample> got;
    ASSERT_TRUE((*d)->open(io, [&](const gaze::RawSample& s) { got.push_back(s); }).ok());
    const auto end = std::chrono::steady_clock::now() + 30s * kSlowdown;
    while (got.size() < want && std::chrono::steady_clock::now() < end) io.run_for(50ms);
    const DriverStats st = (*d)->stats();
    (*d)->close();
    EXPECT_EQ(sim.proc->wait(10s), 0) << sim.proc->err();
    ASSERT_EQ(got.size(), want) << st.last_error << "\n" << sim.proc->err();
    for (std::size_t i = 0; i < got.size(); ++i) {
        EXPECT_TRUE(got[i].left.valid && got[i].right.valid) << i;  // all have confidence > 0.9
        EXPECT_EQ(got[i].device_id, 3u);
        if (i) { EXPECT_GT(got[i].device_ticks, got[i - 1].device_ticks) << i; }
    }
    EXPECT_GT(st.frames_dropped, 0u);  // garbage and truncated copies, counted
    EXPECT_GE(st.reconnects, 1u);      // the restarts
    EXPECT_GE(st.figures.at("clock_syncs"), 2.0);
    EXPECT_LT(st.figures.at("clock_uncertainty_us"), 50'000.0 * kSlowdown);
    EXPECT_EQ(st.notes.at("version"), "unknown");  // the file has no info.player.json beside it
    // Pupil's API never states its rate; the driver measures it (a 400 Hz recording, where the
    // old fixed default of 200 Hz put every window of the gaze chain off by 2x).
    const double recorded = recorded_rate_hz(stamps);
    EXPECT_NEAR(recorded, 399.4, 0.5);
    EXPECT_NEAR((*d)->describe().nominal_rate_hz, recorded, 1.0);
    std::printf(
        "pupil: %zu samples, %llu dropped, %llu reconnects, clock offset %.6f s +- %.0f us "
        "(sd %.0f us, rtt %.0f us)\n",
        got.size(), static_cast<unsigned long long>(st.frames_dropped),
        static_cast<unsigned long long>(st.reconnects), st.figures.at("clock_offset_s"),
        st.figures.at("clock_uncertainty_us"), st.figures.at("clock_offset_sd_us"),
        st.figures.at("sync_rtt_us"));
}

TEST(PupilDriver, ThroughARealFoveadIntoTheRing) {
    if (!fs::exists(kGaze)) GTEST_SKIP() << "no " << kGaze;
    if (!fs::exists(fovea::testing::kFoveadBinary)) GTEST_SKIP() << "no fovead binary";
    Scratch tmp("fovead");
    setenv("FOVEA_RUNTIME_DIR", tmp.dir.c_str(), 1);
    const std::string instance = "pupil" + std::to_string(getpid());
    Sim sim = start_sim(tmp.dir, {"--garbage", "0.02"});
    ASSERT_FALSE(sim.address.empty()) << sim.proc->err();
    const fs::path cfg = tmp.dir / "pupil.toml";
    std::ofstream(cfg) << "[[device]]\ndriver = \"pupil\"\naddress = \"" << sim.address
                       << "\"\ntopics = [\"gaze.3d.\"]\n";
    auto daemon = fovea::testing::spawn_logged(
        fovea::testing::kFoveadBinary, {"--instance", instance, "--config", cfg.string()},
        (tmp.dir / "d.out").string(), (tmp.dir / "d.err").string());
    std::unique_ptr<fovea::Client> client;
    for (int i = 0; i < 500 * kSlowdown && !client; ++i) {
        try {
            client = std::make_unique<fovea::Client>(instance);
        } catch (const std::exception&) { std::this_thread::sleep_for(10ms); }
    }
    ASSERT_TRUE(client) << daemon->err();
    uint64_t cursor = 0, records = 0;
    int64_t last_t = 0;
    bool ordered = true;
    const auto end = std::chrono::steady_clock::now() + 30s * kSlowdown;
    while (records < 665 && std::chrono::steady_clock::now() < end) {
        if (!client->wait(cursor, 100)) continue;
        for (const auto& r : client->read(cursor).records) {
            ++records;
            ordered &= r.t_capture_ns >= last_t;
            last_t = r.t_capture_ns;
        }
    }
    EXPECT_EQ(records, 665u) << daemon->err() << sim.proc->err();
    EXPECT_TRUE(ordered);
    auto status = fovea::testing::spawn_logged(
        fovea::testing::kFoveaBinary, {"--instance", instance, "status"},
        (tmp.dir / "s.out").string(), (tmp.dir / "s.err").string());
    ASSERT_EQ(status->wait(), 0) << status->err();
    const auto j = nlohmann::json::parse(status->out());
    const auto& dev = j["devices"][0];
    EXPECT_EQ(dev["driver"], "pupil");
    EXPECT_EQ(dev["samples"].get<uint64_t>(), 665u);
    EXPECT_TRUE(dev["details"].contains("clock_uncertainty_us")) << dev.dump();
    std::printf("fovead: %llu ring records; status details %s\n",
                static_cast<unsigned long long>(records), dev["details"].dump().c_str());
    client.reset();
    kill(daemon->pid, SIGTERM);
    EXPECT_EQ(daemon->wait(10s), 0) << daemon->err();
}

}  // namespace
}  // namespace fovea::drivers::pupil
