// control_request() against servers that misbehave: a reply that never ends its line, one that
// trickles in, one split over many writes. Each server is a real Unix socket in a thread.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <functional>
#include <string>
#include <thread>

#include "control_client.hpp"

namespace fovea::daemon {
namespace {

// Listens on a fresh path; serve(fd) runs for the one connection it accepts.
class BadServer {
public:
    explicit BadServer(std::function<void(int)> serve)
        : path_("/tmp/fovea-control-client-test-" + std::to_string(::getpid()) + "-" +
                std::to_string(counter_++) + ".sock") {
        listener_ = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
        sockaddr_un addr{};
        addr.sun_family = AF_UNIX;
        std::strncpy(addr.sun_path, path_.c_str(), sizeof addr.sun_path - 1);
        ::unlink(path_.c_str());
        if (::bind(listener_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
            ::listen(listener_, 1) != 0)
            ADD_FAILURE() << "cannot listen on " << path_ << ": " << std::strerror(errno);
        thread_ = std::thread([this, serve] {
            const int fd = ::accept(listener_, nullptr, nullptr);
            if (fd < 0) return;
            char request[256];
            (void)::recv(fd, request, sizeof request, 0);
            serve(fd);
            ::close(fd);
        });
    }
    ~BadServer() {
        ::shutdown(listener_, SHUT_RDWR);
        thread_.join();
        ::close(listener_);
        ::unlink(path_.c_str());
    }
    const std::string& path() const { return path_; }

private:
    static inline int counter_ = 0;
    std::string path_;
    int listener_ = -1;
    std::thread thread_;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

TEST(ControlClient, AReplyThatNeverEndsItsLineIsRefusedAtTheLimit) {
    BadServer server([](int fd) {
        const std::string chunk(1 << 16, 'x');
        while (::send(fd, chunk.data(), chunk.size(), MSG_NOSIGNAL) > 0) {}
    });
    auto r = control_request(server.path(), {{"cmd", "status"}}, 20000);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("without a newline"), std::string::npos) << r.error().message;
}

TEST(ControlClient, ATricklingServerCannotHoldTheCallerPastItsTimeout) {
    BadServer server([](int fd) {
        for (int i = 0; i < 100; ++i) {
            if (::send(fd, "x", 1, MSG_NOSIGNAL) != 1) return;
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
    });
    const auto t0 = std::chrono::steady_clock::now();
    auto r = control_request(server.path(), {{"cmd", "status"}}, 300);
    const double took = seconds_since(t0);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("within 300 ms"), std::string::npos) << r.error().message;
    EXPECT_LT(took, 2.0) << "each byte restarted the timeout";
}

TEST(ControlClient, AReplySplitOverManyWritesIsOneReply) {
    BadServer server([](int fd) {
        const std::string reply = "{\"ok\":true,\"n\":12345}\nignored";
        for (char c : reply) {
            if (::send(fd, &c, 1, MSG_NOSIGNAL) != 1) return;
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
    });
    auto r = control_request(server.path(), {{"cmd", "status"}}, 5000);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->value("n", 0), 12345);
}

}  // namespace
}  // namespace fovea::daemon
