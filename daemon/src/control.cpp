#include "control.hpp"

#include <grp.h>
#include <malloc.h>
#include <pwd.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <boost/asio/read_until.hpp>
#include <boost/asio/streambuf.hpp>
#include <boost/asio/write.hpp>
#include <cerrno>
#include <cstring>
#include <vector>

#include <spdlog/spdlog.h>

#include "fovea/drivers/support.hpp"

namespace fovea::daemon {

namespace asio = boost::asio;
using local = asio::local::stream_protocol;
using nlohmann::json;

bool peer_is_admin(const PeerCredentials& peer, const char* admin_group) {
    if (peer.uid == 0 || peer.uid == getuid()) return true;
    const group* g = getgrnam(admin_group);
    if (!g) return false;
    if (peer.gid == g->gr_gid) return true;
    const passwd* pw = getpwuid(peer.uid);
    if (!pw) return false;
    int n = 64;
    std::vector<gid_t> groups(static_cast<std::size_t>(n));
    if (getgrouplist(pw->pw_name, pw->pw_gid, groups.data(), &n) < 0) {
        groups.resize(static_cast<std::size_t>(n));
        if (getgrouplist(pw->pw_name, pw->pw_gid, groups.data(), &n) < 0) return false;
    }
    for (int i = 0; i < n; ++i)
        if (groups[static_cast<std::size_t>(i)] == g->gr_gid) return true;
    return false;
}

class ControlServer::Session : public std::enable_shared_from_this<Session> {
public:
    Session(ControlServer& server, local::socket socket)
        : server_(server),
          sessions_(server.sessions_),
          socket_(std::move(socket)),
          buffer_(kMaxRequestBytes) {
        sessions_->peak = std::max(sessions_->peak, ++sessions_->live);
        ucred cred{};
        socklen_t len = sizeof cred;
        if (getsockopt(socket_.native_handle(), SOL_SOCKET, SO_PEERCRED, &cred, &len) == 0)
            peer_ = {cred.pid, cred.uid, cred.gid};
    }

    ~Session() {
        if (--sessions_->live > 0 || sessions_->peak < kTrimAfterSessions) return;
        sessions_->peak = 0;
#ifdef __GLIBC__
        malloc_trim(0);
#endif
        ++sessions_->trims;
    }
    Session(const Session&) = delete;
    Session& operator=(const Session&) = delete;

    void read_next() {
        auto self = shared_from_this();
        asio::async_read_until(
            socket_, buffer_, '\n',
            [self](boost::system::error_code ec, std::size_t n) { self->on_line(ec, n); });
    }

private:
    void on_line(boost::system::error_code ec, std::size_t n) {
        if (ec == asio::error::not_found) {  // streambuf full without a newline
            server_.refuse_oversize(peer_.pid);
            reply_and_close({{"ok", false}, {"error", "request too large"}});
            return;
        }
        if (ec) return;  // peer went away
        std::string line(asio::buffers_begin(buffer_.data()),
                         asio::buffers_begin(buffer_.data()) + static_cast<std::ptrdiff_t>(n));
        buffer_.consume(n);
        json reply = server_.handle_line(line, peer_);
        const bool malformed = reply.value("malformed", false);
        reply.erase("malformed");
        auto out = std::make_shared<std::string>(reply.dump() + "\n");
        auto self = shared_from_this();
        asio::async_write(socket_, asio::buffer(*out),
                          [self, out, malformed](boost::system::error_code wec, std::size_t) {
                              if (!wec && !malformed) self->read_next();
                          });
    }

    void reply_and_close(const json& reply) {
        auto out = std::make_shared<std::string>(reply.dump() + "\n");
        auto self = shared_from_this();
        asio::async_write(socket_, asio::buffer(*out),
                          [self, out](boost::system::error_code, std::size_t) {
                              boost::system::error_code ignored;
                              self->socket_.close(ignored);
                          });
    }

    ControlServer& server_;
    std::shared_ptr<Sessions> sessions_;
    local::socket socket_;
    asio::streambuf buffer_;
    PeerCredentials peer_;
};

ControlServer::ControlServer(asio::io_context& io) : io_(io) {
    add_command(
        "help",
        [this](const json&, const PeerCredentials&) {
            json cmds = json::object();
            for (const auto& [name, c] : commands_)
                cmds[name] = c.help + (c.mutating ? " (admin)" : "");
            return json{{"commands", cmds}};
        },
        false, "list the commands");
}

ControlServer::~ControlServer() { close(); }

void ControlServer::refuse_oversize(int pid) {
    ++rejected_;
    if (!oversize_log_) {
        auto log = spdlog::get("daemon");
        oversize_log_ = std::make_unique<drivers::LogLimiter>(log ? log : spdlog::default_logger());
    }
    oversize_log_->warn("control: request over " + std::to_string(kMaxRequestBytes) +
                        " bytes from pid " + std::to_string(pid) + "; closing");
}

Result<void> ControlServer::listen(const std::string& path) {
    if (path.size() >= sizeof(sockaddr_un{}.sun_path))
        return make_error("control socket path too long: " + path);
    // Only replace a socket nobody answers on; a live one means another daemon owns it.
    if (access(path.c_str(), F_OK) == 0) {
        int probe = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
        sockaddr_un addr{};
        addr.sun_family = AF_UNIX;
        std::strncpy(addr.sun_path, path.c_str(), sizeof addr.sun_path - 1);
        const bool live = ::connect(probe, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0;
        ::close(probe);
        if (live) return make_error("control socket " + path + " is in use by another daemon");
        ::unlink(path.c_str());
    }
    boost::system::error_code ec;
    auto acceptor = std::make_unique<local::acceptor>(io_);
    acceptor->open(local(), ec);
    if (!ec) acceptor->bind(local::endpoint(path), ec);
    if (!ec) acceptor->listen(asio::socket_base::max_listen_connections, ec);
    if (ec) return make_error("control socket " + path + ": " + ec.message(), ec.value());
    ::chmod(path.c_str(), 0660);
    acceptor_ = std::move(acceptor);
    path_ = path;
    owns_path_ = true;
    accept_next();
    return {};
}

Result<void> ControlServer::adopt(int listening_fd) {
    boost::system::error_code ec;
    auto acceptor = std::make_unique<local::acceptor>(io_);
    acceptor->assign(local(), listening_fd, ec);
    if (ec) return make_error("adopting control socket fd: " + ec.message(), ec.value());
    acceptor_ = std::move(acceptor);
    owns_path_ = false;  // systemd owns the socket file
    accept_next();
    return {};
}

void ControlServer::close() {
    if (acceptor_) {
        boost::system::error_code ec;
        acceptor_->close(ec);
        acceptor_.reset();
    }
    if (owns_path_) ::unlink(path_.c_str());
    owns_path_ = false;
}

void ControlServer::add_command(const std::string& name, ControlHandler handler, bool mutating,
                                const std::string& help) {
    commands_[name] = Command{std::move(handler), mutating, help};
}

void ControlServer::accept_next() {
    if (!acceptor_) return;
    acceptor_->async_accept([this](boost::system::error_code ec, local::socket socket) {
        if (ec == asio::error::operation_aborted) return;
        if (!ec) std::make_shared<Session>(*this, std::move(socket))->read_next();
        accept_next();
    });
}

json ControlServer::handle_line(const std::string& line, const PeerCredentials& peer) {
    ++requests_;
    json request = json::parse(line, nullptr, /*allow_exceptions=*/false);
    if (request.is_discarded() || !request.is_object() || !request.contains("cmd") ||
        !request["cmd"].is_string()) {
        ++rejected_;
        return {{"ok", false},
                {"error", "malformed request: expected a JSON object with a string \"cmd\""},
                {"malformed", true}};
    }
    const std::string cmd = request["cmd"];
    const auto it = commands_.find(cmd);
    if (it == commands_.end()) {
        ++rejected_;
        return {{"ok", false}, {"error", "unknown command '" + cmd + "' (try \"help\")"}};
    }
    if (it->second.mutating && !peer_is_admin(peer)) {
        ++rejected_;
        return {{"ok", false},
                {"error", "permission denied: '" + cmd +
                              "' needs root, the daemon's user or group fovea-admin"}};
    }
    try {
        json reply = it->second.handler(request, peer);
        if (!reply.is_object()) reply = json{{"result", reply}};
        reply["ok"] = true;
        return reply;
    } catch (const std::exception& e) {
        ++rejected_;
        return {{"ok", false}, {"error", e.what()}};
    }
}

}  // namespace fovea::daemon
