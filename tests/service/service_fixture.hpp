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

#include "../support/child_process.hpp"

#include "control_client.hpp"
#include "paths.hpp"

extern char** environ;

namespace fovea::service_test {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace std::chrono_literals;

inline const std::string& kFovead = fovea::testing::kFoveadBinary;
inline const std::string& kFovea = fovea::testing::kFoveaBinary;

inline std::string slurp(const std::string& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

using Proc = fovea::testing::ChildProcess;

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
        static int n = 0;
        ++n;
        return fovea::testing::spawn_logged(exe, std::move(args), dir + "/out" + std::to_string(n),
                                            dir + "/err" + std::to_string(n));
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
