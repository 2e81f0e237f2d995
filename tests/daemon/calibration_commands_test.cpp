// calibrate.* inside a started Daemon (no socket round trips, no child processes): garbage
// requests, permissions, samples sent with the request, live collection from the simulated
// tracker, storage per user, apply/clear/list and loading the configured user at start.
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "daemon.hpp"
#include "sim/sim_tracker.hpp"

namespace fovea::daemon {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace std::chrono_literals;

const PeerCredentials kAdmin{1, 0, 0};
const PeerCredentials kStranger{2, 65534, 65534};

struct CalibrationCommands : ::testing::Test {
    std::string dir;
    std::unique_ptr<Daemon> daemon;
    std::vector<fovea_gaze_record> published;

    void SetUp() override {
        static int serial = 0;
        const std::string instance =
            "cc" + std::to_string(getpid()) + "-" + std::to_string(++serial);
        dir = fs::temp_directory_path() / ("fv-" + instance);
        fs::create_directories(dir);
        setenv("FOVEA_RUNTIME_DIR", dir.c_str(), 1);
        setenv("FOVEA_STATE_DIR", (dir + "/state").c_str(), 1);
        start(instance, "");
    }
    void TearDown() override {
        daemon.reset();
        fs::remove_all(dir);
    }

    void start(const std::string& instance, const std::string& user) {
        daemon.reset();
        auto cfg = parse_config(
            "[[device]]\ndriver = \"sim\"\ndistortion = 1.0\nseed = 7\n"
            "[calibration]\nsettle_ms = 100\ncollect_ms = 400\n" +
                (user.empty() ? "" : "user = \"" + user + "\"\n"),
            "test");
        ASSERT_TRUE(cfg.ok()) << cfg.error().message;
        cfg->instance = instance;
        // Observers see final samples after the detector's look-ahead; keep it short so the
        // 150 ms runs below publish samples processed after the calibration changed.
        cfg->lookahead_ms = 50;
        daemon = std::make_unique<Daemon>(std::move(cfg).value(), "");
        auto r = daemon->start();
        ASSERT_TRUE(r.ok()) << r.error().message;
        daemon->add_published_observer(
            [this](const gaze::GazeSample&, const fovea_gaze_record& rec) {
                published.push_back(rec);
            });
    }

    json call(const json& req, const PeerCredentials& peer = kAdmin) {
        return daemon->control().handle_line(req.dump(), peer);
    }
    void run_for(std::chrono::milliseconds d) {
        daemon->io().restart();
        daemon->io().run_for(d);
    }

    // Raw samples of the simulated tracker (same distortion) while it looks at (x, y), after
    // its saccadic latency: what a client would send along with calibrate.point.
    static json simulated_samples(drivers::sim::SimTracker& sim, double x, double y) {
        double dx = 0, dy = 0;
        sim.config().display.to_degrees(x, y, dx, dy);
        sim.look_at(dx, dy);
        json samples = json::array();
        for (int i = 0; i < 700; ++i) {
            const auto f = sim.next();
            if (i < 400) continue;  // latency, saccade and settling
            auto eye = [](const gaze::EyeSample& e) {
                return e.valid ? json::array({e.x, e.y}) : json(nullptr);
            };
            samples.push_back({{"left", eye(f.raw.left)}, {"right", eye(f.raw.right)}});
        }
        return samples;
    }
};

TEST_F(CalibrationCommands, GarbageGetsOneClearErrorAndChangesNothing) {
    const std::vector<std::pair<json, std::string>> bad = {
        {{{"cmd", "calibrate.point"}, {"x", 0.5}, {"y", 0.5}}, "no calibration session"},
        {{{"cmd", "calibrate.finish"}}, "no calibration session"},
        {{{"cmd", "calibrate.start"}}, "needs \"user\""},
        {{{"cmd", "calibrate.start"}, {"user", 3}}, "needs \"user\""},
        {{{"cmd", "calibrate.start"}, {"user", "../../etc/passwd"}}, "bad user name"},
        {{{"cmd", "calibrate.start"}, {"user", "ana"}, {"eyes", "three"}}, "\"eyes\" must be"},
        {{{"cmd", "calibrate.start"}, {"user", "ana"}, {"device", 7}}, "device index below 1"},
        {{{"cmd", "calibrate.apply"}, {"user", "nobody"}}, "no stored calibration for 'nobody'"},
        {{{"cmd", "calibrate.target"}, {"x", 2.0}, {"y", 0.5}}, "must be on the display"},
        {{{"cmd", "calibrate.cancel"}}, "no calibration session"},
    };
    for (const auto& [req, why] : bad) {
        const json r = call(req);
        EXPECT_FALSE(r["ok"]) << req;
        const std::string e = r.value("error", "");
        EXPECT_NE(e.find(why), std::string::npos) << req << " -> " << e;
        EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    }
    ASSERT_TRUE(call({{"cmd", "calibrate.start"}, {"user", "ana"}})["ok"]);
    const std::vector<std::pair<json, std::string>> in_session = {
        {{{"cmd", "calibrate.point"}}, "needs a target"},
        {{{"cmd", "calibrate.point"}, {"x", "left"}, {"y", 0.5}}, "\"x\" must be a finite number"},
        {{{"cmd", "calibrate.point"}, {"x", 0.5}, {"y", -0.5}}, "must be on the display"},
        {{{"cmd", "calibrate.point"}, {"x", 0.5}, {"y", 0.5}, {"samples", "many"}},
         "must be an array"},
        {{{"cmd", "calibrate.point"}, {"x", 0.5}, {"y", 0.5}, {"samples", {{{"left", {1}}}}}},
         "samples[0].left must be [x, y]"},
        {{{"cmd", "calibrate.point"}, {"x", 0.5}, {"y", 0.5}, {"samples", {1, 2}}},
         "must be an object"},
        {{{"cmd", "calibrate.finish"}, {"store", "yes"}}, "\"store\" must be true or false"},
        {{{"cmd", "calibrate.finish"}}, "at least 6 distinct targets, got 0"},
    };
    for (const auto& [req, why] : in_session) {
        const json r = call(req);
        EXPECT_FALSE(r["ok"]) << req;
        EXPECT_NE(r.value("error", "").find(why), std::string::npos) << req << " -> " << r;
    }
    // None of them added a point or ended the session.
    const json s = call({{"cmd", "calibrate.status"}});
    EXPECT_EQ(s["session"]["points"].size(), 0u);
    EXPECT_TRUE(s["active"].is_null());
}

TEST_F(CalibrationCommands, MutatingCommandsNeedAnAdmin) {
    for (const char* cmd :
         {"calibrate.start", "calibrate.point", "calibrate.finish", "calibrate.apply",
          "calibrate.clear", "calibrate.cancel", "calibrate.target"}) {
        const json r = call({{"cmd", cmd}, {"user", "ana"}}, kStranger);
        EXPECT_NE(r.value("error", "").find("permission denied"), std::string::npos) << cmd;
    }
    EXPECT_TRUE(call({{"cmd", "calibrate.list"}}, kStranger)["ok"]);
    EXPECT_TRUE(call({{"cmd", "calibrate.status"}}, kStranger)["ok"]);
}

TEST_F(CalibrationCommands, SamplesInTheRequestFitStoreApplyAndReload) {
    drivers::sim::SimConfig sc;
    sc.distortion = 1.0;
    sc.seed = 11;
    sc.blink_rate_hz = 0;
    drivers::sim::SimTracker sim(sc);
    ASSERT_TRUE(call({{"cmd", "calibrate.start"}, {"user", "ana"}})["ok"]);
    for (double y : {0.1, 0.5, 0.9}) {
        for (double x : {0.1, 0.5, 0.9}) {
            const json r = call({{"cmd", "calibrate.point"},
                                 {"x", x},
                                 {"y", y},
                                 {"samples", simulated_samples(sim, x, y)}});
            ASSERT_TRUE(r["ok"]) << r;
            EXPECT_EQ(r["samples"], 300);
        }
    }
    const json f = call({{"cmd", "calibrate.finish"}});
    ASSERT_TRUE(f["ok"]) << f;
    for (const char* eye : {"left", "right"}) {
        EXPECT_GT(f["before"][eye]["accuracy_deg"].get<double>(), 1.0) << eye;
        EXPECT_LT(f["after"][eye]["accuracy_deg"].get<double>(), 0.4) << eye;
        EXPECT_GT(f["after"][eye]["precision_rms_deg"].get<double>(), 0.0) << eye;
        EXPECT_LT(f["after"][eye]["precision_sd_deg"].get<double>(), 0.5) << eye;
    }
    EXPECT_EQ(f["after"]["targets"], 9);
    const std::string stored = f["stored"];
    EXPECT_EQ(stored, dir + "/state/calibrations/ana.json");
    EXPECT_TRUE(fs::exists(stored));
    EXPECT_EQ(call({{"cmd", "calibrate.status"}})["active"]["user"], "ana");

    // The chain flags what it publishes from now on.
    published.clear();
    run_for(150ms);
    ASSERT_FALSE(published.empty());
    EXPECT_TRUE(published.back().flags & FOVEA_FLAG_CALIBRATED);

    const json list = call({{"cmd", "calibrate.list"}});
    ASSERT_EQ(list["calibrations"].size(), 1u) << list;
    EXPECT_EQ(list["calibrations"][0]["user"], "ana");
    EXPECT_EQ(list["active"], "ana");

    EXPECT_EQ(call({{"cmd", "calibrate.clear"}})["cleared"], true);
    published.clear();
    run_for(150ms);
    ASSERT_FALSE(published.empty());
    EXPECT_FALSE(published.back().flags & FOVEA_FLAG_CALIBRATED);
    EXPECT_TRUE(call({{"cmd", "calibrate.status"}})["active"].is_null());

    const json a = call({{"cmd", "calibrate.apply"}, {"user", "ana"}});
    ASSERT_TRUE(a["ok"]) << a;
    EXPECT_NEAR(a["left"]["accuracy_deg"].get<double>(),
                f["after"]["left"]["accuracy_deg"].get<double>(), 1e-9);

    // A daemon configured for ana applies her calibration at start.
    start("cc-reload-" + std::to_string(getpid()), "ana");
    EXPECT_EQ(daemon->status()["calibration"]["active"]["user"], "ana");
    published.clear();
    run_for(150ms);
    ASSERT_FALSE(published.empty());
    EXPECT_TRUE(published.back().flags & FOVEA_FLAG_CALIBRATED);
}

TEST_F(CalibrationCommands, ConfiguredUserWithoutACalibrationRunsUncalibrated) {
    start("cc-missing-" + std::to_string(getpid()), "zoe");
    const json s = daemon->status()["calibration"];
    EXPECT_TRUE(s["active"].is_null());
    EXPECT_NE(s.value("error", "").find("no stored calibration for 'zoe'"), std::string::npos) << s;
}

TEST_F(CalibrationCommands, LivePointsCollectFromTheDeviceAfterTheSettleTime) {
    ASSERT_TRUE(call({{"cmd", "calibrate.start"}, {"user", "bo"}, {"eyes", "left"}})["ok"]);
    const json p = call({{"cmd", "calibrate.point"}, {"deg_x", 0.0}, {"deg_y", 0.0}});
    ASSERT_TRUE(p["ok"]) << p;
    EXPECT_TRUE(p["collecting"]);
    EXPECT_EQ(p["devices_following"], 1);
    EXPECT_NEAR(p["x"].get<double>(), 0.5, 1e-12);
    // A second point while the first collects is refused.
    EXPECT_NE(call({{"cmd", "calibrate.point"}, {"x", 0.1}, {"y", 0.1}})
                  .value("error", "")
                  .find("still collecting"),
              std::string::npos);
    json point;
    for (int i = 0; i < 40; ++i) {
        run_for(50ms);
        point = call({{"cmd", "calibrate.status"}})["session"]["points"][0];
        if (point["done"].get<bool>()) break;
    }
    ASSERT_TRUE(point["done"].get<bool>()) << point;
    // ~100 ms of 1 kHz samples discarded, ~400 collected. The simulated eyes leave 150-250 ms
    // after the target appears and land ~50 ms later, so the window starts with them on their
    // way: only the dwell after the landing (and 40 ms of settling) is fitted, 110-260 samples.
    EXPECT_GT(point["settle_discarded"].get<int>(), 50) << point;
    EXPECT_GT(point["not_settled"].get<int>(), 140) << point;
    EXPECT_GT(point["samples"].get<int>(), 100) << point;
    EXPECT_LT(point["samples"].get<int>(), 270) << point;
    EXPECT_NEAR(point["samples"].get<int>() + point["not_settled"].get<int>(), 400, 2)
        << "1 kHz, no blinks: every other sample is in the dwell " << point;
    EXPECT_TRUE(call({{"cmd", "calibrate.cancel"}})["ok"]);
}

}  // namespace
}  // namespace fovea::daemon
