// The replay driver: timing (original, scaled, full speed), loop, formats through
// fovea::import (tested on their own in tests/import), a real EyeLink file end to end.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

#include <boost/asio/io_context.hpp>

#include "replay/replay_driver.hpp"

namespace fovea::drivers::replay {
namespace {

using namespace std::chrono_literals;

const char* kLund =
    "# sampFreq=500 viewDist_m=0.67 screenDim_m=0.38,0.3 screenRes_px=1024,768 source=x\n"
    "t_us,pupil_h,pupil_v,x_px,y_px,label\n"
    "1000,24,21,512,384,1\n"
    "3000,24,21,0,0,5\n"
    "5000,24,21,256,192,2\n"
    "garbage,row\n"
    "4000,24,21,256,192,2\n"  // time going backwards
    "7000,24,21,1024,768,3\n";

std::string fovea_csv(int n, double rate) {
    std::string s =
        "# fovea gaze recording v1 instance=t\n"
        "index,t_capture_ns,left_x,left_y,left_pupil_mm,left_valid,right_x,right_y,"
        "right_pupil_mm,right_valid,event\n";
    for (int i = 0; i < n; ++i) {
        const auto t = static_cast<int64_t>(5'000'000'000 + i * 1e9 / rate);
        s += std::to_string(i) + "," + std::to_string(t) + ",0.5,0.25,3.5,1,0.51,0.26,3.6," +
             (i % 10 == 0 ? "0" : "1") + "," + (i % 2 ? "saccade" : "fixation") + "\n";
    }
    return s;
}

std::string write_temp(const std::string& name, const std::string& text) {
    const auto path =
        std::filesystem::temp_directory_path() / (name + "-" + std::to_string(::getpid()) + ".csv");
    std::ofstream(path) << text;
    return path.string();
}

double replay_seconds(const std::string& path, double speed, std::size_t& count, bool loop = false,
                      std::chrono::milliseconds limit = 3000ms) {
    boost::asio::io_context io;
    auto t = toml::table{{"driver", "replay"}, {"path", path}, {"speed", speed}, {"loop", loop}};
    auto d = make_driver(t, 1);
    EXPECT_TRUE(d.ok());
    count = 0;
    std::vector<uint64_t> ticks;
    const auto t0 = std::chrono::steady_clock::now();
    auto last = t0;
    EXPECT_TRUE((*d)->open(io,
                           [&](const gaze::RawSample& s) {
                               ticks.push_back(s.device_ticks);
                               last = std::chrono::steady_clock::now();
                               ++count;
                           })
                    .ok());
    io.run_for(limit);
    for (size_t i = 1; i < ticks.size(); ++i) EXPECT_GT(ticks[i], ticks[i - 1]);
    (*d)->close();
    return std::chrono::duration<double>(last - t0).count();
}

TEST(ReplayDriver, OriginalScaledAndFullSpeedTiming) {
    const auto path = write_temp("replay-timing", fovea_csv(250, 500));  // 0.498 s
    std::size_t n = 0;
    const double original = replay_seconds(path, 1.0, n);
    EXPECT_EQ(n, 250u);
    EXPECT_NEAR(original, 0.498, 0.03);
    const double scaled = replay_seconds(path, 4.0, n);
    EXPECT_EQ(n, 250u);
    EXPECT_NEAR(scaled, 0.498 / 4, 0.02);
    const double fast = replay_seconds(path, 0.0, n);
    EXPECT_EQ(n, 250u);
    EXPECT_LT(fast, 0.02);
    std::filesystem::remove(path);
}

TEST(ReplayDriver, LoopKeepsTheDeviceCounterIncreasing) {
    const auto path = write_temp("replay-loop", fovea_csv(50, 1000));
    std::size_t n = 0;
    replay_seconds(path, 0.0, n, true, 50ms);  // checks ticks strictly increase
    EXPECT_GT(n, 500u);
    std::filesystem::remove(path);
}

TEST(ReplayDriver, BadConfigAndMissingFileAreClearErrors) {
    auto r = make_driver(toml::table{{"driver", "replay"}}, 0);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("path"), std::string::npos);
    r = make_driver(toml::table{{"path", "/nonexistent.csv"}}, 0);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("/nonexistent.csv"), std::string::npos);
    r = make_driver(toml::table{{"path", "x"}, {"speed", -1}}, 0);
    ASSERT_FALSE(r.ok());
}

TEST(ReplayDriver, ReplaysTheLund2013HeaderAndLabels) {
    const auto path = write_temp("replay-lund", kLund);
    boost::asio::io_context io;
    auto d = make_driver(toml::table{{"path", path}, {"speed", 0.0}}, 7);
    ASSERT_TRUE(d.ok()) << d.error().message;
    EXPECT_DOUBLE_EQ((*d)->describe().nominal_rate_hz, 500.0);
    EXPECT_EQ((*d)->describe().clock.tick_hz, 1e6);
    EXPECT_FALSE((*d)->describe().binocular);
    std::vector<gaze::RawSample> got;
    ASSERT_TRUE((*d)->open(io, [&](const gaze::RawSample& s) { got.push_back(s); }).ok());
    io.run_for(200ms);
    ASSERT_EQ(got.size(), 5u);  // the garbage row is dropped, the backwards one repaired
    EXPECT_EQ((*d)->stats().frames_dropped, 1u);
    EXPECT_EQ(got[0].device_id, 7u);
    EXPECT_DOUBLE_EQ(got[0].left.x, 0.5);
    EXPECT_FALSE(got[1].left.valid);
    EXPECT_EQ(got[1].truth, gaze::Event::kBlink);
    EXPECT_EQ(got[4].truth, gaze::Event::kPso);
    EXPECT_EQ(got[3].device_ticks, 7000u);
    std::filesystem::remove(path);
}

TEST(ReplayDriver, ForcedFormatAndUnknownFormatName) {
    const auto path = write_temp("replay-force", kLund);
    auto d = make_driver(toml::table{{"path", path}, {"format", "eyelink-asc"}}, 0);
    ASSERT_FALSE(d.ok());
    EXPECT_NE(d.error().message.find("not an EyeLink ASC file"), std::string::npos);
    d = make_driver(toml::table{{"path", path}, {"format", "edf"}}, 0);
    ASSERT_FALSE(d.ok());
    EXPECT_NE(d.error().message.find("unknown format 'edf' (known: lund2013"), std::string::npos);
    d = make_driver(toml::table{{"path", path}, {"format", "lund2013"}}, 0);
    EXPECT_TRUE(d.ok());
    std::filesystem::remove(path);
}

TEST(ReplayDriver, EveryEyelinkSampleOfARealFileInOrder) {
    const std::filesystem::path path = std::filesystem::path(FOVEA_SHARED_DATA_DIR) /
                                       "recordings/eyelink/mne-testing-data/test_eyelink.asc";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "no " << path;
    uint64_t lines = 0;  // sample lines: a digit first, inside START..END
    {
        std::ifstream in(path);
        std::string line;
        bool block = false;
        while (std::getline(in, line)) {
            block = line.rfind("START", 0) == 0 ? true : line.rfind("END", 0) == 0 ? false : block;
            lines += block && !line.empty() && std::isdigit(static_cast<unsigned char>(line[0]));
        }
    }
    std::size_t n = 0;
    replay_seconds(path.string(), 0.0, n, false, 10000ms);  // checks ticks strictly increase
    EXPECT_EQ(n, lines);
}

}  // namespace
}  // namespace fovea::drivers::replay
