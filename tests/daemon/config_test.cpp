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
)", "x.toml");
    ASSERT_TRUE(c.ok()) << c.error().message;
    EXPECT_EQ(c->instance, "lab");
    EXPECT_EQ(c->ring_slots, 1024u);
    EXPECT_EQ(c->display.width_px, 2560);
    EXPECT_DOUBLE_EQ(c->display.distance_m, 0.7);
    ASSERT_EQ(c->devices.size(), 2u);
    EXPECT_EQ(c->devices[1]["port"].value_or(std::string()), "/dev/ttyACM0");
}

TEST(DaemonConfig, SyntaxErrorNamesLineAndColumn) {
    auto c = parse_config("instance = \n", "bad.toml");
    ASSERT_FALSE(c.ok());
    EXPECT_EQ(c.error().message.rfind("bad.toml:1:", 0), 0u) << c.error().message;
    EXPECT_EQ(c.error().message.find('\n'), std::string::npos);
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
