// The one runtime-directory rule (sdk/src/paths/fovea/runtime_dir.hpp), which fovead, the CLI and
// the client library's latency report share: its order of precedence and its buffer contract.
#include "fovea/runtime_dir.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "paths.hpp"

namespace {

// Sets variables for one test and puts back what was there before.
class ScopedEnv {
public:
    ~ScopedEnv() {
        for (auto it = saved_.rbegin(); it != saved_.rend(); ++it) {
            if (it->second)
                setenv(it->first.c_str(), it->second->c_str(), 1);
            else
                unsetenv(it->first.c_str());
        }
    }
    void set(const std::string& name, const char* value) {
        const char* old = std::getenv(name.c_str());
        saved_.emplace_back(name, old ? std::optional<std::string>(old) : std::nullopt);
        if (value)
            setenv(name.c_str(), value, 1);
        else
            unsetenv(name.c_str());
    }

private:
    std::vector<std::pair<std::string, std::optional<std::string>>> saved_;
};

TEST(RuntimeDir, FoveaRuntimeDirOverridesEverything) {
    ScopedEnv env;
    env.set("FOVEA_RUNTIME_DIR", "/srv/fovea-test");
    env.set("RUNTIME_DIRECTORY", "/run/other");
    env.set("XDG_RUNTIME_DIR", "/run/user/1");
    EXPECT_EQ(fovea::runtime_dir(), "/srv/fovea-test");
}

TEST(RuntimeDir, SystemdsFirstRuntimeDirectoryIsOurs) {
    ScopedEnv env;
    env.set("FOVEA_RUNTIME_DIR", nullptr);
    env.set("RUNTIME_DIRECTORY", "/run/fovea-a:/run/fovea-b");
    EXPECT_EQ(fovea::runtime_dir(), "/run/fovea-a");
    env.set("RUNTIME_DIRECTORY", "/run/fovea-only");
    EXPECT_EQ(fovea::runtime_dir(), "/run/fovea-only");
}

TEST(RuntimeDir, EmptyVariablesCountAsUnset) {
    ScopedEnv env;
    env.set("FOVEA_RUNTIME_DIR", "");
    env.set("RUNTIME_DIRECTORY", "/run/from-systemd");
    EXPECT_EQ(fovea::runtime_dir(), "/run/from-systemd");
}

TEST(RuntimeDir, WithoutSystemdFallsToRunThenXdgThenTmp) {
    ScopedEnv env;
    env.set("FOVEA_RUNTIME_DIR", nullptr);
    env.set("RUNTIME_DIRECTORY", nullptr);
    env.set("XDG_RUNTIME_DIR", "/run/user/4242");
    const bool run_writable = access("/run/fovea", W_OK) == 0;
    EXPECT_EQ(fovea::runtime_dir(), run_writable ? "/run/fovea" : "/run/user/4242/fovea");
    env.set("XDG_RUNTIME_DIR", nullptr);
    EXPECT_EQ(fovea::runtime_dir(),
              run_writable ? std::string("/run/fovea") : "/tmp/fovea-" + std::to_string(getuid()));
}

TEST(RuntimeDir, ABufferTooSmallIsTruncatedAndReportsTheLengthItNeeded) {
    ScopedEnv env;
    env.set("FOVEA_RUNTIME_DIR", "/a/long/enough/path");
    char small[8];
    EXPECT_EQ(fovea::runtime_dir(small, sizeof small), 19);
    EXPECT_STREQ(small, "/a/long");
}

TEST(RuntimeDir, APathLongerThanTheStringsFirstGuessIsWhole) {
    ScopedEnv env;
    const std::string deep = "/" + std::string(600, 'd');
    env.set("FOVEA_RUNTIME_DIR", deep.c_str());
    EXPECT_EQ(fovea::runtime_dir(), deep);
}

TEST(RuntimeDir, TheStateDirectoryTakesSystemdsFirstEntryToo) {
    ScopedEnv env;
    env.set("FOVEA_STATE_DIR", nullptr);
    env.set("STATE_DIRECTORY", "/var/lib/fovea-a:/var/lib/fovea-b");
    EXPECT_EQ(fovea::daemon::state_dir(), "/var/lib/fovea-a");
    env.set("FOVEA_STATE_DIR", "/srv/state");
    EXPECT_EQ(fovea::daemon::state_dir(), "/srv/state");
}

TEST(RuntimeDir, TheDaemonsSocketAndLockLiveThere) {
    ScopedEnv env;
    env.set("FOVEA_RUNTIME_DIR", "/srv/f");
    EXPECT_EQ(fovea::daemon::control_socket_path("lab"), "/srv/f/lab.sock");
    EXPECT_EQ(fovea::daemon::lock_file_path("lab"), "/srv/f/lab.lock");
}

}  // namespace
