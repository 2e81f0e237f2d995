#include "paths.hpp"

#include <unistd.h>

#include <cstdlib>
#include <string>

#include "fovea/runtime_dir.hpp"

namespace fovea::daemon {
namespace {

const char* env(const char* name) {
    const char* v = std::getenv(name);
    return v && *v ? v : nullptr;
}

}  // namespace

std::string runtime_dir() { return fovea::runtime_dir(); }

std::string control_socket_path(const std::string& instance) {
    return runtime_dir() + "/" + instance + ".sock";
}

std::string lock_file_path(const std::string& instance) {
    return runtime_dir() + "/" + instance + ".lock";
}

std::string state_dir() {
    if (const char* d = env("FOVEA_STATE_DIR")) return d;
    if (const char* d = env("STATE_DIRECTORY")) {
        std::string s = d;
        return s.substr(0, s.find(':'));
    }
    if (access("/var/lib/fovea", W_OK) == 0) return "/var/lib/fovea";
    if (const char* d = env("XDG_STATE_HOME")) return std::string(d) + "/fovea";
    if (const char* d = env("HOME")) return std::string(d) + "/.local/state/fovea";
    return "/tmp/fovea-state-" + std::to_string(getuid());
}

}  // namespace fovea::daemon
