#include "control_client.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>

namespace fovea::daemon {

using nlohmann::json;

Result<json> control_request(const std::string& socket_path, const json& request, int timeout_ms) {
    int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) return make_error(std::string("socket: ") + std::strerror(errno), errno);
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    if (socket_path.size() >= sizeof addr.sun_path) return make_error("socket path too long");
    std::strncpy(addr.sun_path, socket_path.c_str(), sizeof addr.sun_path - 1);
    if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0)
        return make_error("cannot connect to " + socket_path + ": " + std::strerror(errno) +
                              " (is fovead running for this instance?)",
                          errno);
    const std::string out = request.dump() + "\n";
    if (::send(fd, out.data(), out.size(), MSG_NOSIGNAL) != static_cast<ssize_t>(out.size()))
        return make_error(std::string("send: ") + std::strerror(errno), errno);
    // One deadline for the whole reply (a server trickling bytes cannot hold the caller), and a
    // bounded reply (one that never ends its line cannot exhaust the caller's memory).
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    std::string in;
    char buf[4096];
    std::size_t scanned = 0;
    while (in.find('\n', scanned) == std::string::npos) {
        scanned = in.size();
        if (in.size() > kMaxControlReplyBytes)
            return make_error("reply from " + socket_path + " over " +
                              std::to_string(kMaxControlReplyBytes) + " bytes without a newline");
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
            deadline - std::chrono::steady_clock::now());
        pollfd p{fd, POLLIN, 0};
        const int r = left.count() > 0 ? ::poll(&p, 1, static_cast<int>(left.count())) : 0;
        if (r == 0)
            return make_error("no reply from " + socket_path + " within " +
                              std::to_string(timeout_ms) + " ms");
        if (r < 0) {
            if (errno == EINTR) continue;
            return make_error(std::string("poll: ") + std::strerror(errno), errno);
        }
        const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
        if (n <= 0) return make_error("connection closed by " + socket_path);
        in.append(buf, static_cast<std::size_t>(n));
    }
    json reply = json::parse(in.substr(0, in.find('\n')), nullptr, false);
    if (reply.is_discarded()) return make_error("malformed reply from " + socket_path);
    return reply;
}

}  // namespace fovea::daemon
