// The client side of fovead's control socket (the CLI, tests): newline-delimited JSON over a Unix
// stream socket, protocol in control.hpp. Plain POSIX sockets, so a client does not compile the
// daemon's Boost.Asio server.
#pragma once

#include <cstddef>
#include <string>

#include <nlohmann/json.hpp>

#include "fovea/result.hpp"

namespace fovea::daemon {

// The longest reply line accepted (status with many clients is tens of KiB).
inline constexpr std::size_t kMaxControlReplyBytes = std::size_t{16} << 20;

// Send one request and wait up to `timeout_ms` in all for its reply line (at most
// kMaxControlReplyBytes). Errors name the socket (and suggest that fovead is not running when
// nothing listens). Thread-safe: each call has its own connection.
Result<nlohmann::json> control_request(const std::string& socket_path,
                                       const nlohmann::json& request, int timeout_ms = 2000);

}  // namespace fovea::daemon
