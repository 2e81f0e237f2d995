// The control socket: a Unix stream socket speaking newline-delimited JSON.
//   request:  {"cmd": "status", ...arguments}\n
//   reply:    {"ok": true, ...} or {"ok": false, "error": "..."}\n
// Mutating commands check the peer's credentials (SO_PEERCRED): root, the daemon's own user,
// or a member of group `fovea-admin`. Oversized or malformed requests get an error reply and the
// connection is closed; the daemon is unaffected.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include <boost/asio/io_context.hpp>
#include <boost/asio/local/stream_protocol.hpp>
#include <nlohmann/json.hpp>

#include "control_client.hpp"
#include "fovea/result.hpp"

namespace fovea::drivers {
class LogLimiter;
}

namespace fovea::daemon {

struct PeerCredentials {
    pid_t pid = -1;
    uid_t uid = static_cast<uid_t>(-1);
    gid_t gid = static_cast<gid_t>(-1);
};

// May the peer run mutating commands? Root, our own uid, or a member of `admin_group`.
bool peer_is_admin(const PeerCredentials& peer, const char* admin_group = "fovea-admin");

// A handler returns the reply's fields ("ok" is added); throwing std::exception makes an error
// reply with its text. Called on the loop thread.
using ControlHandler =
    std::function<nlohmann::json(const nlohmann::json& request, const PeerCredentials& peer)>;

class ControlServer {
public:
    static constexpr std::size_t kMaxRequestBytes = 64 * 1024;

    explicit ControlServer(boost::asio::io_context& io);
    ~ControlServer();

    // Bind and listen at `path` (mode 0660), replacing a stale socket file.
    Result<void> listen(const std::string& path);
    // Use a socket systemd passed us (sd_listen_fds).
    Result<void> adopt(int listening_fd);
    void close();

    void add_command(const std::string& name, ControlHandler handler, bool mutating,
                     const std::string& help);
    // Dispatch one request line as a connection would (also used by tests and the fuzzer).
    nlohmann::json handle_line(const std::string& line, const PeerCredentials& peer);

    uint64_t requests() const { return requests_; }
    uint64_t rejected() const { return rejected_; }
    // Connections open now, and how often the heap was handed back to the system after a burst
    // of them (see Sessions).
    std::size_t sessions() const { return sessions_->live; }
    uint64_t memory_trims() const { return sessions_->trims; }
    const std::string& path() const { return path_; }

private:
    struct Command {
        ControlHandler handler;
        bool mutating;
        std::string help;
    };
    class Session;
    // Shared with every session, so one that outlives the server (a handler still queued on the
    // io_context) counts down something alive. When the last connection of a burst of at least
    // kTrimAfterSessions closes, malloc_trim returns the heap their request buffers and parsed
    // requests freed: glibc otherwise keeps it, and fovead's RSS would stay at the high-water
    // mark of the largest burst it ever served.
    struct Sessions {
        std::size_t live = 0, peak = 0;
        uint64_t trims = 0;
    };
    static constexpr std::size_t kTrimAfterSessions = 32;
    void accept_next();
    // Counts a refused oversize request and logs it, at most one line a second (a flood would
    // otherwise write a line per connection); the next line says how many went unlogged.
    void refuse_oversize(int pid);

    boost::asio::io_context& io_;
    std::unique_ptr<boost::asio::local::stream_protocol::acceptor> acceptor_;
    std::map<std::string, Command> commands_;
    std::string path_;
    bool owns_path_ = false;
    uint64_t requests_ = 0;
    uint64_t rejected_ = 0;
    std::unique_ptr<drivers::LogLimiter> oversize_log_;  // made at the first refusal
    std::shared_ptr<Sessions> sessions_ = std::make_shared<Sessions>();
};

}  // namespace fovea::daemon
