#include <gtest/gtest.h>

#include "config.hpp"

namespace fovea::daemon {
namespace {

TEST(DaemonConfig, EmptyTextGivesDefaults) {
    auto c = parse_config("", "x.toml");
    ASSERT_TRUE(c.ok());
    EXPECT_EQ(c->instance, "default");
    EXPECT_TRUE(c->devices.empty());
    EXPECT_EQ(c->ring_slots, 4096u);
}

TEST(DaemonConfig, ReadsDevicesDisplayAndRing) {
    auto c = parse_config(R"(
instance = "lab"
log_level = "debug"
[ring]
slots = 1024
[display]
width_px = 2560
distance_m = 0.7
[[device]]
driver = "sim"
rate_hz = 500
[[device]]
driver = "serial"
port = "/dev/ttyACM0"
)",
                          "x.toml");
    ASSERT_TRUE(c.ok()) << c.error().message;
    EXPECT_EQ(c->instance, "lab");
    EXPECT_EQ(c->ring_slots, 1024u);
    EXPECT_EQ(c->display.width_px, 2560);
    EXPECT_DOUBLE_EQ(c->display.distance_m, 0.7);
    ASSERT_EQ(c->devices.size(), 2u);
    EXPECT_EQ(c->devices[1]["port"].value_or(std::string()), "/dev/ttyACM0");
}

TEST(DaemonConfig, AnIntegerKeyGivenAFloatBeyondEveryIntegerIsAClearError) {
    // The fuzzer's find: toml++ casts such a float to int64 (undefined behaviour).
    auto c =
        parse_config("[zmq]\npublish = \"tcp://127.0.0.1:50020\"\nsend_hwm = 3.3e53\n", "x.toml");
    ASSERT_FALSE(c.ok());
    EXPECT_NE(c.error().message.find("zmq.send_hwm"), std::string::npos) << c.error().message;
}

TEST(DaemonConfig, SyntaxErrorNamesLineAndColumn) {
    auto c = parse_config("instance = \n", "bad.toml");
    ASSERT_FALSE(c.ok());
    EXPECT_EQ(c.error().message.rfind("bad.toml:1:", 0), 0u) << c.error().message;
    EXPECT_EQ(c.error().message.find('\n'), std::string::npos);
}

// Found by tests/fuzz/fuzz_daemon_config: toml++ quotes the bytes it choked on, newline included,
// so the error was two lines.
TEST(DaemonConfig, SyntaxErrorIsOneLineWhateverBytesItQuotes) {
    auto r = parse_config("#]\nslots =n\n[\x01", "f.toml");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message.find('\n'), std::string::npos) << r.error().message;
    for (char ch : r.error().message) EXPECT_GE(static_cast<unsigned char>(ch), 0x20) << int(ch);
    EXPECT_EQ(r.error().message.rfind("f.toml:2:", 0), 0u) << r.error().message;
}

// Found by tests/fuzz/fuzz_daemon_config: a bad calibration user name was quoted raw, and TOML's
// "\n" escape put a newline into it.
TEST(DaemonConfig, ErrorQuotingAValueIsOneLineWhateverTheValueHolds) {
    for (const char* text : {"[calibration]\nuser = \"a.b\\ncd\"\n", "\"k\\ney\" = 1\n",
                             "[[device]]\ndriver = \"s\\nim\"\n[zmq]\n\"x\\ty\" = 2\n"}) {
        auto r = parse_config(text, "f.toml");
        ASSERT_FALSE(r.ok()) << text;
        EXPECT_EQ(r.error().message.rfind("f.toml", 0), 0u) << r.error().message;
        for (char ch : r.error().message) EXPECT_GE(static_cast<unsigned char>(ch), 0x20) << text;
    }
    auto r = parse_config("[calibration]\nuser = \"a.b\\ncd\"\n", "f.toml");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("'a.b\\x0acd'"), std::string::npos) << r.error().message;
}

TEST(DaemonConfig, UnknownKeyAndBadValuesAreNamed) {
    auto c = parse_config("instanse = \"x\"\n", "a.toml");
    ASSERT_FALSE(c.ok());
    EXPECT_NE(c.error().message.find("instanse: unknown key"), std::string::npos);
    c = parse_config("[display]\nwidth_px = -3\n", "a.toml");
    ASSERT_FALSE(c.ok());
    EXPECT_NE(c.error().message.find("display.width_px"), std::string::npos);
    c = parse_config("[ring]\nslots = \"many\"\n", "a.toml");
    ASSERT_FALSE(c.ok());
    EXPECT_NE(c.error().message.find("ring.slots"), std::string::npos);
    c = parse_config("device = 3\n", "a.toml");
    ASSERT_FALSE(c.ok());
    EXPECT_NE(c.error().message.find("[[device]]"), std::string::npos);
}

TEST(DaemonConfig, HmdDisplayProfileSetsTheDisplayAndTheRingsEyeGeometry) {
    auto c = parse_config("display_profile = \"generic-2x1440x1600\"\n", "x.toml");
    ASSERT_TRUE(c.ok()) << c.error().message;
    EXPECT_EQ(c->display_profile, "generic-2x1440x1600");
    EXPECT_EQ(c->display.width_px, 1440);
    EXPECT_DOUBLE_EQ(c->display.distance_m, 1.0);  // the virtual image plane at 1 m
    EXPECT_FLOAT_EQ(c->eyes.ipd_m, 0.063f);
    // Asymmetric views: 52 deg temporal, 46 deg nasal (left eye: temporal is left).
    EXPECT_FLOAT_EQ(c->eyes.fov_deg[0][0], 52.0f);
    EXPECT_FLOAT_EQ(c->eyes.fov_deg[0][1], 46.0f);
    EXPECT_FLOAT_EQ(c->eyes.fov_deg[1][0], 46.0f);
    EXPECT_FLOAT_EQ(c->eyes.fov_deg[1][1], 52.0f);
    auto monitor = parse_config("display_profile = \"desktop-24in-60cm\"\n", "x.toml");
    ASSERT_TRUE(monitor.ok()) << monitor.error().message;
    EXPECT_EQ(monitor->eyes.ipd_m, 0.0f);  // a monitor has no eye views to publish
    EXPECT_EQ(parse_config("", "x.toml")->eyes.ipd_m, 0.0f);
}

TEST(DaemonConfig, DisplayProfileErrorsAreOneLineNamingTheKey) {
    auto unknown = parse_config("display_profile = \"no-such-hmd\"\n", "x.toml");
    ASSERT_FALSE(unknown);
    EXPECT_EQ(unknown.error().message.rfind("x.toml: display_profile: unknown display profile "
                                            "'no-such-hmd'",
                                            0),
              0u)
        << unknown.error().message;
    auto both = parse_config("display_profile = \"generic-2x1440x1600\"\n[display]\n", "x.toml");
    ASSERT_FALSE(both);
    EXPECT_NE(both.error().message.find("not both"), std::string::npos);
    EXPECT_FALSE(parse_config("display_profile = 3\n", "x.toml"));
}

TEST(DaemonConfig, PublishModeDefaultsToLiveAndIsValidated) {
    EXPECT_EQ(parse_config("", "x.toml")->publish, PublishMode::kLive);
    EXPECT_EQ(parse_config("[processing]\npublish = \"final\"\n", "x.toml")->publish,
              PublishMode::kFinal);
    EXPECT_EQ(parse_config("[processing]\npublish = \"live\"\n", "x.toml")->publish,
              PublishMode::kLive);
    auto bad = parse_config("[processing]\npublish = \"soon\"\n", "x.toml");
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.error().message, "x.toml: processing.publish: must be \"live\" or \"final\"");
    auto unknown = parse_config("[processing]\nlookahead = 3\n", "x.toml");
    ASSERT_FALSE(unknown);
    EXPECT_EQ(unknown.error().message, "x.toml: processing.lookahead: unknown key");
}

TEST(DaemonConfig, LookaheadDefaultsToTheDetectorsAndIsBounded) {
    EXPECT_DOUBLE_EQ(parse_config("", "x.toml")->lookahead_ms, 350.0);
    EXPECT_DOUBLE_EQ(parse_config("[processing]\nlookahead_ms = 100\n", "x.toml")->lookahead_ms,
                     100.0);
    auto bad = parse_config("[processing]\nlookahead_ms = 0\n", "x.toml");
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.error().message.rfind("x.toml: processing.lookahead_ms: must be a number in", 0),
              0u)
        << bad.error().message;
}

TEST(DaemonConfig, MissingFileIsOneClearLine) {
    auto c = load_config("/nonexistent/fovead.toml");
    ASSERT_FALSE(c.ok());
    EXPECT_EQ(c.error().message, "/nonexistent/fovead.toml: cannot open configuration file");
}

}  // namespace
}  // namespace fovea::daemon
