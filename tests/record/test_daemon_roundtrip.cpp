// The "done when" with the real binaries: fovead (simulated tracker) records XDF on
// `fovea record --out X.xdf`; export, replay and report work on it; kill -9 of the daemon while
// recording leaves a file that `fovea repair` closes.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "fovea/record/offline.hpp"
#include "fovea/record/xdf.hpp"
#include "libxdf_oracle.hpp"
#include "test_util.hpp"

extern char** environ;

using namespace fovea::record;

namespace {

const std::string kFovead = std::string(FOVEA_BINARY_DIR) + "/daemon/fovead";
const std::string kFovea = std::string(FOVEA_BINARY_DIR) + "/tools/fovea";

pid_t spawn(const std::vector<std::string>& args, const std::string& log) {
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&fa, 1, 2);
    pid_t pid = -1;
    const int rc = posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&fa);
    return rc == 0 ? pid : -1;
}

int run(const std::string& cmd) {
    const int rc = std::system(cmd.c_str());
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

class DaemonRoundTrip : public ::testing::Test {
protected:
    void SetUp() override {
        if (!std::filesystem::exists(kFovead) || !std::filesystem::exists(kFovea))
            GTEST_SKIP() << "fovead/fovea not built";
        std::filesystem::create_directories(dir_ / "run");
        setenv("FOVEA_RUNTIME_DIR", (dir_ / "run").c_str(), 1);
        instance_ = "rec" + std::to_string(getpid());
        daemon_ = spawn({kFovead, "--instance", instance_, "--log-level", "warn"},
                        (dir_ / "fovead.log").string());
        ASSERT_GT(daemon_, 0);
        // wait for the control socket
        for (int i = 0; i < 100 && !std::filesystem::exists(dir_ / "run" / (instance_ + ".sock"));
             ++i)
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    void TearDown() override {
        if (daemon_ > 0) {
            kill(daemon_, SIGTERM);
            int st = 0;
            waitpid(daemon_, &st, 0);
        }
    }
    std::string cli(const std::string& args) const {
        return kFovea + " --instance " + instance_ + " " + args + " >> '" +
               (dir_ / "cli.log").string() + "' 2>&1";
    }
    test::ScratchDir dir_{"daemon"};
    std::string instance_;
    pid_t daemon_ = -1;
};

}  // namespace

TEST_F(DaemonRoundTrip, RecordExportReplayReportFromTheRunningDaemon) {
    const std::string xdf = (dir_ / "sim.xdf").string();
    ASSERT_EQ(run(cli("record --out " + xdf + " --duration 2")), 0);
    auto f = xdf::read_file(xdf);
    ASSERT_TRUE(f.ok()) << f.error().message;
    EXPECT_FALSE(f->truncated);
    test::expect_libxdf_agrees(xdf);
    auto rec = decode_recording(*f);
    ASSERT_TRUE(rec.ok()) << rec.error().message;
    EXPECT_TRUE(rec->info.preroll_from_start);
    EXPECT_GT(rec->gaze.size(), 1500u);  // 2 s at 1 kHz
    EXPECT_EQ(run(cli("export " + xdf + " --csv " + (dir_ / "csv").string())), 0);
    EXPECT_TRUE(std::filesystem::exists(dir_ / "csv" / "FoveaLatency.csv"));
    EXPECT_EQ(run(cli("replay " + xdf)), 0) << "replay differs from the live run";
    EXPECT_EQ(run(cli("report " + xdf + " --out " + (dir_ / "report").string())), 0);
    EXPECT_TRUE(std::filesystem::exists(dir_ / "report" / "report.html"));
    EXPECT_EQ(run(cli("latency --once --interval 0.5")), 0);
    EXPECT_EQ(run(cli("record --out relative-is-resolved.xdf --duration 0.2")), 0);
    std::filesystem::remove("relative-is-resolved.xdf");
}

TEST_F(DaemonRoundTrip, KillDashNineWhileRecordingThenRepair) {
    const std::string xdf = (dir_ / "killed.xdf").string();
    const pid_t rec =
        spawn({kFovea, "--instance", instance_, "record", "--out", xdf, "--duration", "30"},
              (dir_ / "rec.log").string());
    ASSERT_GT(rec, 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(2500));
    kill(daemon_, SIGKILL);
    int st = 0;
    waitpid(daemon_, &st, 0);
    daemon_ = -1;
    kill(rec, SIGTERM);  // the CLI would otherwise sleep out its 30 s
    waitpid(rec, &st, 0);
    auto before = xdf::read_file(xdf);
    ASSERT_TRUE(before.ok()) << before.error().message;
    const auto* raw = before->find(kRawStreamName);
    ASSERT_NE(raw, nullptr);
    // at most one flush interval (250 ms) of the ~2.5 s is lost
    EXPECT_GT(before->find(kGazeStreamName)->sample_count(), 1800u);
    EXPECT_EQ(run(cli("repair " + xdf)), 0);
    auto after = xdf::read_file(xdf);
    ASSERT_TRUE(after.ok());
    EXPECT_FALSE(after->truncated);
    for (const auto& s : after->streams) EXPECT_FALSE(s.footer_xml.empty()) << s.name;
    EXPECT_EQ(after->find(kGazeStreamName)->sample_count(),
              before->find(kGazeStreamName)->sample_count());
    test::expect_libxdf_agrees(xdf);
    EXPECT_EQ(run(cli("replay " + xdf)), 0);
}
