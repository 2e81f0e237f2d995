// Replay: both recording formats, timing (original, scaled, full speed), loop, real lund2013 data.
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

#include <boost/asio/io_context.hpp>

#include "replay/recording.hpp"
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
    std::string s = "# fovea gaze recording v1 instance=t\n"
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
    const auto path = std::filesystem::temp_directory_path() /
                      (name + "-" + std::to_string(::getpid()) + ".csv");
    std::ofstream(path) << text;
    return path.string();
}

TEST(Recording, ReadsLund2013WithLostSamplesLabelsAndBadRows) {
    auto r = parse_recording(kLund);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->format, "lund2013");
    ASSERT_EQ(r->samples.size(), 4u);
    EXPECT_EQ(r->skipped_rows, 2u);
    EXPECT_EQ(r->display.width_px, 1024);
    EXPECT_DOUBLE_EQ(r->display.distance_m, 0.67);
    EXPECT_DOUBLE_EQ(r->samples[0].left.x, 0.5);
    EXPECT_DOUBLE_EQ(r->samples[0].left.y, 0.5);
    EXPECT_FALSE(r->samples[1].left.valid);  // 0,0 is lost tracking
    EXPECT_FALSE(r->samples[0].right.valid);  // monocular
    EXPECT_EQ(r->samples[1].truth, gaze::Event::kBlink);
    EXPECT_EQ(r->samples[3].truth, gaze::Event::kPso);
    EXPECT_EQ(r->t_ns[3], 6'000'000);
    EXPECT_EQ(r->samples[2].device_ticks, 5000u);
    EXPECT_EQ(r->clock.tick_hz, 1e6);
}

TEST(Recording, Lund2013NanTimestampsUseTheNominalRate) {
    auto r = parse_recording(
        "# sampFreq=500 screenRes_px=1024,768\nt_us,pupil_h,pupil_v,x_px,y_px,label\n"
        "nan,1,1,10,10,1\nnan,1,1,11,10,1\nnan,1,1,12,10,1\n");
    ASSERT_TRUE(r.ok());
    ASSERT_EQ(r->t_ns.size(), 3u);
    EXPECT_EQ(r->t_ns[2], 4'000'000);
    EXPECT_DOUBLE_EQ(r->nominal_rate_hz, 500.0);
}

TEST(Recording, ReadsFoveaCsvByColumnName) {
    auto r = parse_recording(fovea_csv(100, 250));
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->format, "fovea-csv");
    ASSERT_EQ(r->samples.size(), 100u);
    EXPECT_TRUE(r->binocular);
    EXPECT_DOUBLE_EQ(r->nominal_rate_hz, 250.0);
    EXPECT_EQ(r->samples[1].device_ticks, 5'004'000'000u);
    EXPECT_FALSE(r->samples[0].right.valid);
    EXPECT_TRUE(r->samples[1].right.valid);
    EXPECT_DOUBLE_EQ(r->samples[1].right.pupil_mm, 3.6);
    EXPECT_EQ(r->samples[1].truth, gaze::Event::kSaccade);
    // Columns in another order still read by name.
    auto r2 = parse_recording("# fovea x\nleft_valid,left_y,left_x,t_capture_ns\n1,0.2,0.1,100\n");
    ASSERT_TRUE(r2.ok());
    EXPECT_DOUBLE_EQ(r2->samples[0].left.x, 0.1);
}

TEST(Recording, ClearErrorsForUnknownOrBrokenFiles) {
    EXPECT_FALSE(parse_recording("").ok());
    auto r = parse_recording("hello\n");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("unknown format"), std::string::npos);
    r = parse_recording("# fovea x\nindex,left_x\n");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("t_capture_ns"), std::string::npos);
    EXPECT_FALSE(load_recording("/nonexistent/file.csv").ok());
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
    EXPECT_TRUE((*d)->open(io, [&](const gaze::RawSample& s) {
                       ticks.push_back(s.device_ticks);
                       last = std::chrono::steady_clock::now();
                       ++count;
                   }).ok());
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

TEST(Recording, ReadsEveryLund2013FileOfTheSharedData) {
    const std::filesystem::path dir = std::filesystem::path(FOVEA_SHARED_DATA_DIR) / "lund2013";
    if (!std::filesystem::exists(dir)) GTEST_SKIP() << "no " << dir << " (../shared/data absent)";
    int files = 0;
    uint64_t samples = 0, lost = 0, skipped = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
        if (e.path().extension() != ".csv" || e.path().filename().string().starts_with("fix_"))
            continue;
        auto r = load_recording(e.path().string());
        ASSERT_TRUE(r.ok()) << r.error().message;
        ++files;
        samples += r->samples.size();
        skipped += r->skipped_rows;
        for (const auto& s : r->samples) lost += !s.left.valid;
        // 500 Hz, or 200 Hz for the files whose timestamps say so.
        EXPECT_TRUE(std::fabs(r->nominal_rate_hz - 500) < 1 || std::fabs(r->nominal_rate_hz - 200) < 1)
            << e.path() << " " << r->nominal_rate_hz;
    }
    EXPECT_EQ(files, 68);  // 34 recordings x 2 coders
    EXPECT_GT(samples, 200'000u);
    EXPECT_EQ(skipped, 0u);
    EXPECT_LT(static_cast<double>(lost) / samples, 0.2);
    std::printf("lund2013: %d files, %llu samples, %.2f %% lost\n", files,
                static_cast<unsigned long long>(samples), 100.0 * lost / samples);
}

}  // namespace
}  // namespace fovea::drivers::replay
