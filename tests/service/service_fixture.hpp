// Real fovead / fovea processes for the service tests: each test gets its own instance name and
// runtime directory (FOVEA_RUNTIME_DIR), so tests never touch a system daemon.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "control.hpp"
#include "paths.hpp"

extern char** environ;

namespace fovea::service_test {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace std::chrono_literals;

inline const std::string kFovead = std::string(FOVEA_BINARY_DIR) + "/daemon/fovead";
inline const std::string kFovea = std::string(FOVEA_BINARY_DIR) + "/tools/fovea";

inline std::string slurp(const std::string& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

struct Proc {
    pid_t pid = -1;
    std::string out_path, err_path;

    std::string out() const { return slurp(out_path); }
    std::string err() const { return slurp(err_path); }
    // Exit code, or 128+signal; -1 on timeout (then the process is killed).
    int wait(std::chrono::milliseconds timeout = 10s) {
        if (pid <= 0) return -2;  // never kill(-1, ...)
        const auto end = std::chrono::steady_clock::now() + timeout;
        int status = 0;
        while (std::chrono::steady_clock::now() < end) {
            if (waitpid(pid, &status, WNOHANG) == pid) {
                pid = -1;
                return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
            }
            std::this_thread::sleep_for(5ms);
        }
        kill(pid, SIGKILL);
        waitpid(pid, nullptr, 0);
        pid = -1;
        return -1;
    }
    ~Proc() {
        if (pid > 0) {
            kill(pid, SIGKILL);
            waitpid(pid, nullptr, 0);
        }
    }
};

struct ServiceTest : ::testing::Test {
    std::string dir;
    std::string instance;

    void SetUp() override {
        static int serial = 0;  // short names: a Unix socket path must fit in 108 bytes
        instance = "sv" + std::to_string(getpid()) + "-" + std::to_string(++serial);
        dir = fs::temp_directory_path() / ("fv-" + instance);
        fs::create_directories(dir);
        fs::permissions(dir, fs::perms(0755));
        setenv("FOVEA_RUNTIME_DIR", dir.c_str(), 1);
    }
    void TearDown() override { fs::remove_all(dir); }

    std::unique_ptr<Proc> spawn(const std::string& exe, std::vector<std::string> args) {
        auto p = std::make_unique<Proc>();
        static int n = 0;
        p->out_path = dir + "/out" + std::to_string(++n);
        p->err_path = dir + "/err" + std::to_string(n);
        posix_spawn_file_actions_t fa;
        posix_spawn_file_actions_init(&fa);
        posix_spawn_file_actions_addopen(&fa, 1, p->out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        posix_spawn_file_actions_addopen(&fa, 2, p->err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        args.insert(args.begin(), exe);
        std::vector<char*> argv;
        for (auto& a : args) argv.push_back(a.data());
        argv.push_back(nullptr);
        EXPECT_EQ(posix_spawn(&p->pid, exe.c_str(), &fa, nullptr, argv.data(), environ), 0);
        posix_spawn_file_actions_destroy(&fa);
        return p;
    }

    // fovead --instance <ours> [extra]; returns once the control socket answers.
    std::unique_ptr<Proc> start_daemon(std::vector<std::string> extra = {}) {
        extra.insert(extra.begin(), {"--instance", instance});
        auto d = spawn(kFovead, extra);
        const auto end = std::chrono::steady_clock::now() + 5s;
        while (std::chrono::steady_clock::now() < end) {
            if (query("status").ok()) return d;
            if (waitpid(d->pid, nullptr, WNOHANG) == d->pid) {
                d->pid = -1;
                break;
            }
            std::this_thread::sleep_for(10ms);
        }
        ADD_FAILURE() << "fovead did not come up: " << d->err();
        return d;
    }

    Result<json> query(const std::string& cmd) {
        return daemon::control_request(socket_path(), {{"cmd", cmd}}, 2000);
    }
    std::string socket_path() const { return daemon::control_socket_path(instance); }

    std::string write_file(const std::string& name, const std::string& text) {
        const std::string p = dir + "/" + name;
        std::ofstream(p) << text;
        return p;
    }
};

}  // namespace fovea::service_test
