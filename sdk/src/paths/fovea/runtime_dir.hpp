// The one rule for where fovead keeps its control socket and lock. fovead, the CLI and the
// client library's latency report (which must find the daemon's socket) all use it.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace fovea {

// The pieces of the rule that fovead's state directory follows too (daemon/client/paths.cpp).
namespace dir_rules {
// The variable's value, or nullptr when it is unset or empty.
inline const char* env(const char* name) {
    const char* v = std::getenv(name);
    return v && *v ? v : nullptr;
}
// Length of the first entry of a colon-separated systemd list ($RUNTIME_DIRECTORY,
// $STATE_DIRECTORY: a unit naming several directories gets them all; the first is ours).
inline std::size_t first_entry_length(const char* list) {
    const char* colon = std::strchr(list, ':');
    return colon ? std::size_t(colon - list) : std::strlen(list);
}
}  // namespace dir_rules

// FOVEA_RUNTIME_DIR if set; else the first entry of $RUNTIME_DIRECTORY (systemd's
// RuntimeDirectory=, colon-separated when a unit names several); else /run/fovea if writable;
// else $XDG_RUNTIME_DIR/fovea; else /tmp/fovea-<uid>.
// Writes it NUL-terminated into out and returns snprintf's count: >= cap means truncated.
// Allocates nothing (the client library calls it behind a C ABI). Thread-safe as getenv is.
inline int runtime_dir(char* out, std::size_t cap) {
    using dir_rules::env;
    if (const char* d = env("FOVEA_RUNTIME_DIR")) return std::snprintf(out, cap, "%s", d);
    if (const char* r = env("RUNTIME_DIRECTORY"))
        return std::snprintf(out, cap, "%.*s", int(dir_rules::first_entry_length(r)), r);
    if (access("/run/fovea", W_OK) == 0) return std::snprintf(out, cap, "/run/fovea");
    if (const char* x = env("XDG_RUNTIME_DIR")) return std::snprintf(out, cap, "%s/fovea", x);
    return std::snprintf(out, cap, "/tmp/fovea-%u", unsigned(getuid()));
}

inline std::string runtime_dir() {
    std::string dir(256, '\0');
    int n = runtime_dir(dir.data(), dir.size() + 1);
    if (n > int(dir.size())) {
        dir.resize(std::size_t(n));
        n = runtime_dir(dir.data(), dir.size() + 1);
    }
    dir.resize(n > 0 ? std::size_t(n) : 0);
    return dir;
}

}  // namespace fovea
