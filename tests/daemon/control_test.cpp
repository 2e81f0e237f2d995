// The control protocol's dispatcher, without a socket: malformed input, unknown commands,
// permission checks on mutating commands.
#include <gtest/gtest.h>

#include <boost/asio/io_context.hpp>

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

}  // namespace
}  // namespace fovea::daemon
