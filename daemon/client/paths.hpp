// Where an instance's control socket and lock live. Shared by fovead and the CLI.
#pragma once

#include <string>

namespace fovea::daemon {

// fovea::runtime_dir() (sdk/src/paths/fovea/runtime_dir.hpp owns the rule).
std::string runtime_dir();
std::string control_socket_path(const std::string& instance);
std::string lock_file_path(const std::string& instance);
// Persistent state (per-user calibrations): FOVEA_STATE_DIR, else $STATE_DIRECTORY (systemd
// StateDirectory=), else /var/lib/fovea if writable, else $XDG_STATE_HOME/fovea, else
// $HOME/.local/state/fovea, else /tmp/fovea-state-<uid>.
std::string state_dir();

}  // namespace fovea::daemon
