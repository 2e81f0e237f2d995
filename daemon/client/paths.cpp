#include "paths.hpp"

#include <unistd.h>

#include <string>

#include "fovea/runtime_dir.hpp"

namespace fovea::daemon {

using fovea::dir_rules::env;

std::string runtime_dir() { return fovea::runtime_dir(); }

std::string control_socket_path(const std::string& instance) {
    return runtime_dir() + "/" + instance + ".sock";
}

std::string lock_file_path(const std::string& instance) {
    return runtime_dir() + "/" + instance + ".lock";
}

std::string state_dir() {
    if (const char* d = env("FOVEA_STATE_DIR")) return d;
    if (const char* d = env("STATE_DIRECTORY")) return {d, dir_rules::first_entry_length(d)};
    if (access("/var/lib/fovea", W_OK) == 0) return "/var/lib/fovea";
    if (const char* d = env("XDG_STATE_HOME")) return std::string(d) + "/fovea";
    if (const char* d = env("HOME")) return std::string(d) + "/.local/state/fovea";
    return "/tmp/fovea-state-" + std::to_string(getuid());
}

}  // namespace fovea::daemon
