// `fovea calibrate` end to end: a real fovead on a private instance runs the simulated tracker
// with its known distortion; the CLI calibrates over the control socket; the ring then carries
// calibrated, accurate gaze; garbage requests get one clear error and the daemon keeps running;
// a restarted daemon configured for the user applies the stored calibration.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
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

std::string slurp(const std::string& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

int64_t now_ns() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

using Proc = fovea::testing::ChildProcess;

struct CalibrateEndToEnd : ::testing::Test {
    std::string dir, instance, config;

    void SetUp() override {
        instance = "ci" + std::to_string(getpid());
        dir = fs::temp_directory_path() / ("fv-" + instance);
        fs::create_directories(dir);
        setenv("FOVEA_RUNTIME_DIR", dir.c_str(), 1);
        setenv("FOVEA_STATE_DIR", (dir + "/state").c_str(), 1);
        config = dir + "/fovead.toml";
    }
    void TearDown() override { fs::remove_all(dir); }

    void write_config(const std::string& user) {
        std::ofstream(config) << "[[device]]\ndriver = \"sim\"\ndistortion = 1.0\nseed = 3\n"
                                 "[calibration]\nsettle_ms = 300\ncollect_ms = 300\n"
                              << (user.empty() ? "" : "user = \"" + user + "\"\n");
    }

    std::unique_ptr<Proc> spawn(const std::string& exe, std::vector<std::string> args) {
        static int n = 0;
        ++n;
        return fovea::testing::spawn_logged(exe, std::move(args), dir + "/out" + std::to_string(n),
                                            dir + "/err" + std::to_string(n));
    }

    fovea::Result<json> query(const json& req) {
        return fovea::daemon::control_request(fovea::daemon::control_socket_path(instance), req,
                                              2000 * kSlowdown);
    }

    std::unique_ptr<Proc> start_daemon() {
        auto d = spawn(kFovead, {"--instance", instance, "--config", config});
        const auto end = std::chrono::steady_clock::now() + 5s * kSlowdown;
        while (std::chrono::steady_clock::now() < end) {
            if (query({{"cmd", "status"}}).ok()) return d;
            std::this_thread::sleep_for(10ms);
        }
        ADD_FAILURE() << "fovead did not come up: " << slurp(d->err_path);
        return d;
    }

    // Show a target and measure the published left/right gaze against it: median offset in
    // degrees per eye and the share of records flagged calibrated. Samples more than 5 deg off
    // are excluded (the convention of fovea calibrate's validation): the eye may still be on
    // its way. So are samples within kLidMarginNs of a lost one, as pupillometry and
    // accuracy studies drop blink flanks: the simulated eyes blink now and then while they
    // hold a target, and the lid edges drag the gaze up by a few degrees. A blink may last the
    // whole 400 ms window, so the window stretches until each eye has kMinKept samples.
    struct Measured {
        double left_deg = NAN, right_deg = NAN, calibrated_share = 0;
        int records = 0, kept = 0, excluded = 0;
    };
    static constexpr int64_t kLidMarginNs = 100'000'000;
    static constexpr size_t kMinKept = 150;

    static Measured score(const std::vector<fovea_gaze_record>& window, double tx, double ty) {
        std::vector<int64_t> lost;
        for (const auto& r : window) {
            if (!(r.left.valid & FOVEA_VALID) || !(r.right.valid & FOVEA_VALID)) {
                lost.push_back(r.t_capture_ns);
            }
        }
        const auto near_lost = [&](int64_t t) {
            const auto it = std::lower_bound(lost.begin(), lost.end(), t - kLidMarginNs);
            return it != lost.end() && *it <= t + kLidMarginNs;
        };
        Measured m;
        std::vector<double> offsets[2];
        double flagged = 0;
        for (const auto& r : window) {
            ++m.records;
            flagged += (r.flags & FOVEA_FLAG_CALIBRATED) ? 1 : 0;
            if (near_lost(r.t_capture_ns)) continue;
            const fovea_eye* eyes[2] = {&r.left, &r.right};
            for (int e = 0; e < 2; ++e) {
                const double offset = std::hypot(eyes[e]->deg_x - tx, eyes[e]->deg_y - ty);
                if (!(offset <= 5.0)) {
                    ++m.excluded;
                    continue;
                }
                offsets[e].push_back(offset);
                ++m.kept;
            }
        }
        const auto median = [](std::vector<double>& v) {
            if (v.size() < kMinKept) return double(NAN);
            std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
            return v[v.size() / 2];
        };
        m.left_deg = median(offsets[0]);
        m.right_deg = median(offsets[1]);
        m.calibrated_share = m.records ? flagged / m.records : 0;
        return m;
    }

    Measured measure_at(double x, double y) {
        fovea::Client ring(instance);
        uint64_t cursor = ring.head();
        // By capture time: 500 ms for latency, saccade and settling, then 400 ms measured, or
        // up to 3 s more while blinks leave too few samples.
        const int64_t from_ns = now_ns() + 500'000'000, give_up_ns = from_ns + 3'400'000'000LL;
        auto shown = query({{"cmd", "calibrate.target"}, {"x", x}, {"y", y}});
        EXPECT_TRUE(shown.ok() && (*shown)["ok"].get<bool>());
        const double tx = (*shown)["deg_x"], ty = (*shown)["deg_y"];
        std::vector<fovea_gaze_record> window;
        Measured m;
        for (int64_t until_ns = from_ns + 400'000'000; until_ns <= give_up_ns;
             until_ns += 200'000'000) {
            bool past = false;
            while (!past && now_ns() < until_ns + 3'000'000'000LL * kSlowdown) {
                if (!ring.wait(cursor, 100)) continue;
                for (const auto& r : ring.read(cursor, 256).records) {
                    past = past || r.t_capture_ns >= until_ns;
                    if (r.t_capture_ns >= from_ns) window.push_back(r);
                }
            }
            m = score(window, tx, ty);
            if (std::isfinite(m.left_deg) && std::isfinite(m.right_deg)) break;
        }
        return m;
    }
};

TEST_F(CalibrateEndToEnd, CalibratesTheDistortedSimulatorOverTheSocket) {
    write_config("");
    auto d = start_daemon();
    const Measured raw = measure_at(0.35, 0.6);
    EXPECT_GT(raw.records, 100);
    EXPECT_EQ(raw.calibrated_share, 0.0);
    EXPECT_GT(raw.left_deg, 1.0) << "the distortion is on";

    auto cal = spawn(kFovea, {"--instance", instance, "calibrate", "--user", "it", "--json"});
    ASSERT_EQ(cal->wait(60s * kSlowdown), 0) << slurp(cal->err_path) << slurp(cal->out_path);
    const json r = json::parse(slurp(cal->out_path));
    for (const char* eye : {"left", "right"}) {
        EXPECT_GT(r["before"][eye]["accuracy_deg"].get<double>(), 1.0) << eye;
        EXPECT_LT(r["after"][eye]["accuracy_deg"].get<double>(), 0.5) << eye;
        EXPECT_LT(r["validation"][eye]["accuracy_deg"].get<double>(), 0.5) << eye;
        // Measured on the settled dwell, not on the eyes still travelling to the target.
        EXPECT_LT(r["validation"][eye]["precision_sd_deg"].get<double>(), 0.2) << eye;
        std::printf(
            "%s eye: accuracy before %.3f deg, after %.3f deg (fit), %.3f deg (validation); "
            "precision RMS %.3f / SD %.3f deg (fit), SD %.3f deg (validation)\n",
            eye, r["before"][eye]["accuracy_deg"].get<double>(),
            r["after"][eye]["accuracy_deg"].get<double>(),
            r["validation"][eye]["accuracy_deg"].get<double>(),
            r["after"][eye]["precision_rms_deg"].get<double>(),
            r["after"][eye]["precision_sd_deg"].get<double>(),
            r["validation"][eye]["precision_sd_deg"].get<double>());
    }
    EXPECT_EQ(r["validation"]["calibrated_records"], r["validation"]["records"]);
    // Each fresh target on its own: no region of the display is left uncalibrated. A target
    // the eyes never settled on (a blink over its whole window) has no figure.
    ASSERT_EQ(r["validation"]["per_target"].size(), 5u);
    int measured = 0;
    for (const json& t : r["validation"]["per_target"]) {
        for (const char* eye : {"left_deg", "right_deg"}) {
            if (!t[eye].is_number()) continue;
            ++measured;
            EXPECT_LT(t[eye].get<double>(), 0.5) << t;
        }
    }
    EXPECT_GE(measured, 2 * 3) << r["validation"]["per_target"];
    EXPECT_TRUE(fs::exists(dir + "/state/calibrations/it.json"));

    // The ring after calibration: flagged and accurate at a point no target used.
    const Measured after = measure_at(0.35, 0.6);
    EXPECT_EQ(after.calibrated_share, 1.0);
    EXPECT_GT(after.kept, after.excluded) << "the eye was on the target most of the window";
    EXPECT_LT(after.left_deg, 0.6);
    EXPECT_LT(after.right_deg, 0.6);

    // Garbage: one clear error line each, and the daemon keeps publishing.
    for (const json& bad : {json{{"cmd", "calibrate.point"}, {"x", 0.5}, {"y", 0.5}},
                            json{{"cmd", "calibrate.start"}, {"user", "a/b"}},
                            json{{"cmd", "calibrate.apply"}, {"user", 17}},
                            json{{"cmd", "calibrate.target"}, {"x", 0.5}, {"y", "down"}}}) {
        auto e = query(bad);
        ASSERT_TRUE(e.ok()) << e.error().message;
        EXPECT_FALSE((*e)["ok"].get<bool>()) << bad;
        EXPECT_FALSE((*e).value("error", "").empty()) << bad;
    }
    auto s = query({{"cmd", "status"}});
    ASSERT_TRUE(s.ok());
    EXPECT_EQ((*s)["calibration"]["active"]["user"], "it");
    EXPECT_EQ(measure_at(0.6, 0.4).calibrated_share, 1.0);

    // A daemon configured for the user applies the stored calibration at start.
    ASSERT_TRUE(query({{"cmd", "shutdown"}}).ok());
    ASSERT_EQ(d->wait(10s * kSlowdown), 0) << slurp(d->err_path);
    write_config("it");
    d = start_daemon();
    const Measured reloaded = measure_at(0.65, 0.35);
    EXPECT_EQ(reloaded.calibrated_share, 1.0);
    EXPECT_LT(reloaded.left_deg, 0.6);
    EXPECT_LT(reloaded.right_deg, 0.6);
}

}  // namespace
