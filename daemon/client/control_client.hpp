// The client side of fovead's control socket (the CLI, tests): newline-delimited JSON over a Unix
// stream socket, protocol in control.hpp. Plain POSIX sockets, so a client does not compile the
// daemon's Boost.Asio server.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "fovea/result.hpp"

namespace fovea::daemon {

// Send one request and wait up to `timeout_ms` for its reply line. Errors name the socket (and
// suggest that fovead is not running when nothing listens). Thread-safe: each call has its own
// connection.
Result<nlohmann::json> control_request(const std::string& socket_path,
                                       const nlohmann::json& request, int timeout_ms = 2000);

}  // namespace fovea::daemon
