// The control protocol's dispatcher, without a socket: malformed input, unknown commands,
// permission checks on mutating commands; and, on a real Unix socket, what a burst of
// connections leaves behind.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include <spdlog/sinks/ringbuffer_sink.h>
#include <spdlog/spdlog.h>

#include "control.hpp"

namespace fovea::daemon {
namespace {

using nlohmann::json;

struct ControlFixture : ::testing::Test {
    boost::asio::io_context io;
    ControlServer server{io};
    PeerCredentials root{1, 0, 0};
    PeerCredentials stranger{2, 65534, 65534};

    void SetUp() override {
        server.add_command(
            "echo",
            [](const json& r, const PeerCredentials&) {
                return json{{"echo", r.value("text", "")}};
            },
            false, "echo");
        server.add_command(
            "boom",
            [](const json&, const PeerCredentials&) -> json {
                throw std::runtime_error("it broke");
            },
            false, "throws");
        server.add_command(
            "poke",
            [](const json&, const PeerCredentials&) {
                return json{{"poked", true}};
            },
            true, "mutating");
    }
};

TEST_F(ControlFixture, AnswersAKnownCommand) {
    json r = server.handle_line(R"({"cmd":"echo","text":"hi"})", stranger);
    EXPECT_TRUE(r["ok"]);
    EXPECT_EQ(r["echo"], "hi");
}

TEST_F(ControlFixture, MalformedRequestsGetAnErrorAndAreMarkedForClosing) {
    for (const char* bad : {"", "{", "[1,2]", "{\"cmd\":3}", "\xff\xfe", "{\"nocmd\":1}"}) {
        json r = server.handle_line(bad, root);
        EXPECT_FALSE(r["ok"]) << bad;
        EXPECT_TRUE(r.value("malformed", false)) << bad;
    }
    EXPECT_EQ(server.rejected(), 6u);
}

TEST_F(ControlFixture, UnknownCommandSaysWhatToTry) {
    json r = server.handle_line(R"({"cmd":"frobnicate"})", root);
    EXPECT_FALSE(r["ok"]);
    EXPECT_EQ(r["error"], "unknown command 'frobnicate' (try \"help\")");
}

TEST_F(ControlFixture, HandlerExceptionBecomesAnErrorReply) {
    json r = server.handle_line(R"({"cmd":"boom"})", root);
    EXPECT_FALSE(r["ok"]);
    EXPECT_EQ(r["error"], "it broke");
}

TEST_F(ControlFixture, MutatingCommandsNeedAnAdminPeer) {
    EXPECT_TRUE(server.handle_line(R"({"cmd":"poke"})", root)["ok"]);
    json r = server.handle_line(R"({"cmd":"poke"})", stranger);
    EXPECT_FALSE(r["ok"]);
    EXPECT_NE(r["error"].get<std::string>().find("permission denied"), std::string::npos);
    // Read-only commands stay open to anyone who can reach the socket (group fovea).
    EXPECT_TRUE(server.handle_line(R"({"cmd":"echo"})", stranger)["ok"]);
}

TEST_F(ControlFixture, HelpListsCommands) {
    json r = server.handle_line(R"({"cmd":"help"})", stranger);
    EXPECT_TRUE(r["commands"].contains("poke"));
    EXPECT_EQ(r["commands"]["poke"], "mutating (admin)");
}

// Connects to `path` and sends `bytes` (no newline: a request still being written); -1 on failure.
int connect_and_send(const std::string& path, const std::string& bytes) {
    const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::strncpy(addr.sun_path, path.c_str(), sizeof addr.sun_path - 1);
    if (fd < 0 || ::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
        ::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL) != ssize_t(bytes.size())) {
        if (fd >= 0) ::close(fd);
        return -1;
    }
    return fd;
}

struct ControlSocketFixture : ControlFixture {
    std::string path = "/tmp/fovea-control-test-" + std::to_string(::getpid()) + ".sock";
    void SetUp() override {
        ControlFixture::SetUp();
        ASSERT_TRUE(server.listen(path));
    }
    // Runs the loop until `done` or 5 s.
    template <typename Done>
    bool run_until(Done done) {
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
        while (!done() && std::chrono::steady_clock::now() < deadline)
            io.run_for(std::chrono::milliseconds(10));
        return done();
    }
};

TEST_F(ControlSocketFixture, TheHeapIsTrimmedWhenTheLastConnectionOfABurstCloses) {
    const std::string partial = "{\"cmd\":\"echo\",\"text\":\"" + std::string(8192, 'x');
    // One connection at a time, however many, is no burst.
    for (int i = 0; i < 40; ++i) {
        const int fd = connect_and_send(path, partial);
        ASSERT_GE(fd, 0);
        ASSERT_TRUE(run_until([&] { return server.sessions() == 1; }));
        ::close(fd);
        ASSERT_TRUE(run_until([&] { return server.sessions() == 0; }));
    }
    EXPECT_EQ(server.memory_trims(), 0u);
    // 40 open at once, then all gone: one trim, when the last one closes.
    std::vector<int> fds;
    for (int i = 0; i < 40; ++i) {
        fds.push_back(connect_and_send(path, partial));
        ASSERT_GE(fds.back(), 0);
    }
    ASSERT_TRUE(run_until([&] { return server.sessions() == 40; }));
    for (size_t i = 0; i + 1 < fds.size(); ++i) ::close(fds[i]);
    ASSERT_TRUE(run_until([&] { return server.sessions() == 1; }));
    EXPECT_EQ(server.memory_trims(), 0u);
    ::close(fds.back());
    ASSERT_TRUE(run_until([&] { return server.sessions() == 0; }));
    EXPECT_EQ(server.memory_trims(), 1u);
}

TEST_F(ControlSocketFixture, AFloodOfOversizeRequestsIsLoggedOnceASecondWithACount) {
    auto sink = std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(100);
    auto previous = spdlog::get("daemon");
    spdlog::drop("daemon");
    spdlog::register_logger(std::make_shared<spdlog::logger>("daemon", sink));
    const std::string oversize(ControlServer::kMaxRequestBytes + 1, 'x');
    const auto flood = [&](int n) {
        const uint64_t before = server.rejected();
        for (int i = 0; i < n; ++i) {
            const int fd = connect_and_send(path, oversize);
            ASSERT_GE(fd, 0);
            ASSERT_TRUE(run_until([&] { return server.rejected() == before + i + 1; }));
            ::close(fd);
        }
    };
    flood(30);
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));
    flood(1);
    const std::vector<std::string> lines = sink->last_formatted();
    spdlog::drop("daemon");
    if (previous) spdlog::register_logger(previous);
    EXPECT_EQ(server.rejected(), 31u);
    ASSERT_EQ(lines.size(), 2u) << "a line per refused request, or none";
    EXPECT_NE(lines[0].find("request over 65536 bytes"), std::string::npos) << lines[0];
    EXPECT_NE(lines[1].find("(+29 similar)"), std::string::npos) << lines[1];
}

}  // namespace
}  // namespace fovea::daemon
