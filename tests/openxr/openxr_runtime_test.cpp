// XR_APILAYER_FOVEA_eye_gaze through a real OpenXR runtime: the vendored Monado (in-process,
// null compositor, simulated HMD), with Debian's core validation layer enabled, a real fovead on
// its simulated tracker (HMD profile generic-2x1440x1600), and `fovea openxr-check` as the app.
// The loader finds the layer through XDG_DATA_HOME (the build tree's manifest, or an install
// prefix's); nothing is installed into system directories. FOVEA_MONADO_RUNTIME_JSON names the
// runtime manifest tests/openxr/build_monado.sh printed; without it every test skips.
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "../support/child_process.hpp"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace std::chrono_literals;
using Proc = fovea::testing::ChildProcess;

const std::string kLayerXdgDataHome = FOVEA_OPENXR_LAYER_XDG_DATA_HOME;

int count_lines_with(const std::string& text, const std::string& needle) {
    int n = 0;
    for (std::size_t p = text.find(needle); p != std::string::npos; p = text.find(needle, p + 1))
        ++n;
    return n;
}

class OpenXrRuntime : public ::testing::Test {
protected:
    void SetUp() override {
        const char* rt = std::getenv("FOVEA_MONADO_RUNTIME_JSON");
        if (!rt || !*rt)
            GTEST_SKIP() << "FOVEA_MONADO_RUNTIME_JSON is not set: build the vendored Monado with "
                            "tests/openxr/build_monado.sh (tools/dev.sh test does) and point it "
                            "at the manifest it prints";
        ASSERT_TRUE(fs::exists(rt)) << "no runtime manifest at " << rt;
        static int serial = 0;
        instance_ = "xr" + std::to_string(getpid()) + "-" + std::to_string(++serial);
        dir_ = fs::temp_directory_path() / ("fv-" + instance_);
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        // Blinks every second or so, so a short run is sure to see several.
        std::ofstream(dir_ / "fovead.toml") << "display_profile = \"generic-2x1440x1600\"\n"
                                               "[[device]]\ndriver = \"sim\"\nseed = 7\n"
                                               "blink_rate_hz = 1.0\n";
        setenv("FOVEA_RUNTIME_DIR", dir_.c_str(), 1);
        setenv("XR_RUNTIME_JSON", rt, 1);
        setenv("XRT_COMPOSITOR_NULL", "1", 1);
        setenv("XR_ENABLE_API_LAYERS", "XR_APILAYER_LUNARG_core_validation", 1);
        setenv("XDG_DATA_HOME", kLayerXdgDataHome.c_str(), 1);
        setenv("FOVEA_INSTANCE", instance_.c_str(), 1);  // which fovead the layer reads
        unsetenv("DISABLE_XR_APILAYER_FOVEA_eye_gaze");
        start_daemon();
    }
    void TearDown() override {
        daemon_.reset();
        for (const char* v :
             {"FOVEA_RUNTIME_DIR", "XR_RUNTIME_JSON", "XRT_COMPOSITOR_NULL", "XR_ENABLE_API_LAYERS",
              "XDG_DATA_HOME", "FOVEA_INSTANCE", "DISABLE_XR_APILAYER_FOVEA_eye_gaze"})
            unsetenv(v);
        if (!HasFailure()) fs::remove_all(dir_);
    }

    void start_daemon() {
        daemon_ = spawn(fovea::testing::kFoveadBinary,
                        {"--instance", instance_, "--config", (dir_ / "fovead.toml").string(),
                         "--log-level", "warn"});
        const std::string ring = "/dev/shm/fovea." + instance_ + ".gaze";
        for (int i = 0; i < 400 && !fs::exists(ring); ++i) std::this_thread::sleep_for(25ms);
        ASSERT_TRUE(fs::exists(ring)) << "fovead did not start: " << daemon_->err();
    }

    std::unique_ptr<Proc> spawn(const std::string& exe, std::vector<std::string> args) {
        ++spawned_;
        return fovea::testing::spawn_logged(exe, std::move(args),
                                            (dir_ / ("out" + std::to_string(spawned_))).string(),
                                            (dir_ / ("err" + std::to_string(spawned_))).string());
    }

    // `fovea openxr-check` with `args`; its JSON report (null when it printed none).
    json check(std::vector<std::string> args, int expect_rc, std::string* err = nullptr,
               std::chrono::seconds timeout = 120s) {
        std::vector<std::string> all = {"--instance", instance_, "openxr-check", "--json"};
        all.insert(all.end(), args.begin(), args.end());
        auto p = spawn(fovea::testing::kFoveaBinary, all);
        const int rc = p->wait(timeout);
        if (err) *err = p->err();
        EXPECT_EQ(rc, expect_rc) << p->out() << p->err();
        return json::parse(p->out(), nullptr, false);
    }

    std::string instance_;
    fs::path dir_;
    std::unique_ptr<Proc> daemon_;
    int spawned_ = 0;
};

TEST_F(OpenXrRuntime, PoseEqualsTheRingsGazeAtMatchingTimesThroughMonado) {
    std::string err;
    const json r = check({"--frames", "300", "--csv", (dir_ / "frames.csv").string()}, 0, &err);
    ASSERT_TRUE(r.is_object()) << err;
    EXPECT_TRUE(r["eye_gaze_extension"].get<bool>());
    EXPECT_TRUE(r["supports_eye_gaze_interaction"].get<bool>());
    EXPECT_NE(r["runtime"].get<std::string>().find("Monado"), std::string::npos);
    const auto layers = r["api_layers"].get<std::vector<std::string>>();
    EXPECT_NE(std::find(layers.begin(), layers.end(), "XR_APILAYER_LUNARG_core_validation"),
              layers.end());
    EXPECT_NE(std::find(layers.begin(), layers.end(), "XR_APILAYER_FOVEA_eye_gaze"), layers.end());
    EXPECT_EQ(r["frames"], 300);
    EXPECT_GT(r["probes_compared"].get<int>(), 150);
    EXPECT_LE(r["max_angle_error_deg"].get<double>(), 0.1);
    EXPECT_EQ(r["validity_mismatches"], 0);
    EXPECT_GT(r["untracked_probes"].get<int>(), 0) << "no blink fell on a probe";
    EXPECT_GT(r["saccades"].get<int>(), 3);
    EXPECT_LE(r["saccade_lag_frames_max"].get<int>(), 1);
    EXPECT_EQ(r["saccade_layer_lag_frames_max"], 0);
    // Landing prediction: in saccades the pose at display time beats holding the newest sample.
    if (r["saccade_frames"].get<int>() >= 5) {
        EXPECT_LT(r["saccade_display_error_p50_deg"].get<double>(),
                  r["saccade_hold_error_p50_deg"].get<double>());
    }
    EXPECT_GT(r["valid_frames"].get<int>(), 150);
    EXPECT_GT(r["invalid_frames"].get<int>(), 0) << "blinks must make the pose invalid";
    EXPECT_LE(r["max_local_error_deg"].get<double>(), 0.01);
    EXPECT_GT(r["median_gaze_age_ms"].get<double>(), 0.0);
    // The layer says what it does, once; the validation layer below it finds nothing to report.
    EXPECT_EQ(count_lines_with(err, "XR_APILAYER_FOVEA_eye_gaze: providing"), 1) << err;
    EXPECT_EQ(count_lines_with(err, "VUID-"), 0) << err;
}

TEST_F(OpenXrRuntime, RestartedDaemonMakesPosesInvalidThenValidWhileTheAppRuns) {
    std::vector<std::string> args = {"--instance", instance_,  "openxr-check",
                                     "--json",     "--frames", "260"};
    auto app = spawn(fovea::testing::kFoveaBinary, args);
    std::this_thread::sleep_for(5s);  // session up, frames running on gaze
    kill(daemon_->pid, SIGKILL);      // a crash: the ring is left behind, never closed
    daemon_->wait(5s);
    std::this_thread::sleep_for(2s);
    start_daemon();
    ASSERT_EQ(app->wait(120s), 0) << app->out() << app->err();
    const json r = json::parse(app->out(), nullptr, false);
    ASSERT_TRUE(r.is_object()) << app->out();
    EXPECT_EQ(r["frames"], 260);
    EXPECT_GE(r["longest_invalid_run_frames"].get<int>(), 20);  // 2 s down at 20 frames/s
    EXPECT_GE(r["valid_frames_after_longest_invalid_run"].get<int>(), 20);
    EXPECT_GE(r["ring_restarts"].get<int>(), 1);
    EXPECT_EQ(r["validity_mismatches"], 0);
    EXPECT_LT(r["frame_interval_max_ms"].get<double>(), 500.0) << "the frame loop was blocked";
    const std::string err = app->err();
    EXPECT_EQ(count_lines_with(err, "no new gaze from fovead"), 1) << err;
    EXPECT_EQ(count_lines_with(err, "restarted"), 1) << err;
}

TEST_F(OpenXrRuntime, DisabledLayerIsAsIfItWereAbsent) {
    setenv("DISABLE_XR_APILAYER_FOVEA_eye_gaze", "1", 1);
    std::string err_disabled;
    const json disabled = check({"--frames", "40", "--allow-no-gaze"}, 0, &err_disabled);
    unsetenv("DISABLE_XR_APILAYER_FOVEA_eye_gaze");
    fs::create_directories(dir_ / "empty");
    setenv("XDG_DATA_HOME", (dir_ / "empty").c_str(), 1);
    const json absent = check({"--frames", "40", "--allow-no-gaze"}, 0);
    ASSERT_TRUE(disabled.is_object() && absent.is_object());
    for (const json* r : {&disabled, &absent}) {
        EXPECT_FALSE((*r)["eye_gaze_extension"].get<bool>());
        EXPECT_EQ((*r)["frames"], 40);
    }
    EXPECT_EQ(disabled["api_layers"], absent["api_layers"]);
    EXPECT_EQ(count_lines_with(err_disabled, "XR_APILAYER_FOVEA_eye_gaze"), 0) << err_disabled;
    // Without --allow-no-gaze the check says why there is nothing to check.
    std::string err;
    check({"--frames", "5"}, 2, &err);
    EXPECT_NE(err.find("XR_EXT_eye_gaze_interaction is not offered"), std::string::npos) << err;
}

TEST_F(OpenXrRuntime, CmakeInstalledLayerIsFoundByTheLoader) {
    const fs::path prefix = dir_ / "prefix";
    auto install = spawn("/usr/bin/env",
                         {"cmake", "--install", FOVEA_BINARY_DIR, "--prefix", prefix.string()});
    ASSERT_EQ(install->wait(120s), 0) << install->out() << install->err();
    const fs::path manifest =
        prefix / "share/openxr/1/api_layers/implicit.d/XrApiLayer_fovea_eye_gaze.json";
    ASSERT_TRUE(fs::exists(manifest));
    const json m = json::parse(std::ifstream(manifest), nullptr, false);
    const std::string lib = m["api_layer"]["library_path"].get<std::string>();
    EXPECT_NE(lib.front(), '/') << "an install prefix moves as a whole: the path is relative";
    EXPECT_TRUE(fs::exists(manifest.parent_path() / lib)) << lib;
    setenv("XDG_DATA_HOME", (prefix / "share").c_str(), 1);
    const json r = check({"--frames", "60"}, 0);
    ASSERT_TRUE(r.is_object());
    EXPECT_TRUE(r["eye_gaze_extension"].get<bool>());
    EXPECT_GT(r["valid_frames"].get<int>(), 0);
}

}  // namespace
