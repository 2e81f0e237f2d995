// Real child processes for the integration tests (fovead, the fovea CLI): spawned with stdout and
// stderr in files, waited for with a timeout, killed if still running when they go out of scope.
// Header-only; POSIX.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

extern char** environ;

namespace fovea::testing {

// Sanitized builds run several times slower: tests scale their timeouts by this.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
inline constexpr int kSlowdown = 10;
#else
inline constexpr int kSlowdown = 1;
#endif

#ifdef FOVEA_BINARY_DIR  // the build tree, for tests that run the real programs
inline const std::string kFoveadBinary = std::string(FOVEA_BINARY_DIR) + "/daemon/fovead";
inline const std::string kFoveaBinary = std::string(FOVEA_BINARY_DIR) + "/tools/fovea";
#endif

inline std::string slurp_file(const std::string& path) {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

struct ChildProcess {
    pid_t pid = -1;
    std::string out_path, err_path;

    ChildProcess() = default;
    ChildProcess(const ChildProcess&) = delete;
    ChildProcess& operator=(const ChildProcess&) = delete;

    std::string out() const { return slurp_file(out_path); }
    std::string err() const { return slurp_file(err_path); }
    // The first line written to stdout (without its newline), or "" if none came in `timeout`:
    // the protocol simulators print the address they listen on there.
    std::string first_line(std::chrono::milliseconds timeout = std::chrono::seconds(5)) const {
        const auto end = std::chrono::steady_clock::now() + timeout;
        for (;;) {
            const std::string o = out();
            if (const auto nl = o.find('\n'); nl != std::string::npos) return o.substr(0, nl);
            if (std::chrono::steady_clock::now() >= end) return "";
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
    }

    // Exit code, or 128+signal; -1 on timeout (then the process is killed).
    int wait(std::chrono::milliseconds timeout = std::chrono::seconds(20)) {
        if (pid <= 0) return -2;  // never kill(-1, ...): that signals every process we may
        const auto end = std::chrono::steady_clock::now() + timeout;
        int status = 0;
        while (std::chrono::steady_clock::now() < end) {
            if (waitpid(pid, &status, WNOHANG) == pid) {
                pid = -1;
                return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        kill(pid, SIGKILL);
        waitpid(pid, nullptr, 0);
        pid = -1;
        return -1;
    }
    ~ChildProcess() {
        if (pid > 0) {
            kill(pid, SIGKILL);
            waitpid(pid, nullptr, 0);
        }
    }
};

// Starts `exe args...` with the current environment, stdout/stderr truncated into the files.
inline std::unique_ptr<ChildProcess> spawn_logged(const std::string& exe,
                                                  std::vector<std::string> args,
                                                  std::string out_path, std::string err_path) {
    auto p = std::make_unique<ChildProcess>();
    p->out_path = std::move(out_path);
    p->err_path = std::move(err_path);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, p->out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0644);
    posix_spawn_file_actions_addopen(&fa, 2, p->err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0644);
    args.insert(args.begin(), exe);
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    EXPECT_EQ(posix_spawn(&p->pid, exe.c_str(), &fa, nullptr, argv.data(), environ), 0) << exe;
    posix_spawn_file_actions_destroy(&fa);
    return p;
}

}  // namespace fovea::testing
