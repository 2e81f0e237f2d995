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

namespace runtime_dir_detail {
inline const char* env(const char* name) {
    const char* v = std::getenv(name);
    return v && *v ? v : nullptr;
}
}  // namespace runtime_dir_detail

// FOVEA_RUNTIME_DIR if set; else the first entry of $RUNTIME_DIRECTORY (systemd's
// RuntimeDirectory=, colon-separated when a unit names several); else /run/fovea if writable;
// else $XDG_RUNTIME_DIR/fovea; else /tmp/fovea-<uid>.
// Writes it NUL-terminated into out and returns snprintf's count: >= cap means truncated.
// Allocates nothing (the client library calls it behind a C ABI). Thread-safe as getenv is.
inline int runtime_dir(char* out, std::size_t cap) {
    using runtime_dir_detail::env;
    if (const char* d = env("FOVEA_RUNTIME_DIR")) return std::snprintf(out, cap, "%s", d);
    if (const char* r = env("RUNTIME_DIRECTORY")) {
        const char* colon = std::strchr(r, ':');
        const int n = colon ? int(colon - r) : int(std::strlen(r));
        return std::snprintf(out, cap, "%.*s", n, r);
    }
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
