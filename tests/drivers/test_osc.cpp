// The osc driver: address maps and frame assembly, then live on loopback UDP driven by
// `fovea simulate osc` (a liblo sender, our own: no real EyeTrackVR bytes are in ../shared) in
// both presets — in process, and through a real fovead into its ring — with blinks coming out
// as samples without valid eyes.
#include <gtest/gtest.h>
#include <lo/lo.h>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <nlohmann/json.hpp>

#include "../support/child_process.hpp"
#include "fovea/client.hpp"
#include "osc/osc_driver.hpp"
#include "osc/osc_map.hpp"

namespace fovea::drivers::osc {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using fovea::testing::kSlowdown;

FrameAssembler assembler(const toml::table& t) {
    auto m = parse_address_map(t);
    EXPECT_TRUE(m.ok()) << (m.ok() ? "" : m.error().message);
    return FrameAssembler(m.ok() ? *m : AddressMap{});
}

TEST(OscMap, VrchatVectorsAndTheClosedAmount) {
    auto a = assembler(toml::table{{"preset", "vrchat"}, {"fov_deg", toml::array{90.0, 90.0}}});
    std::optional<gaze::RawSample> s;
    EXPECT_TRUE(a.message("/tracking/eye/EyesClosedAmount", {0.1}, s));
    EXPECT_FALSE(s);
    // Straight ahead, and 45 deg right / up at the edge of a 90 deg field of view.
    ASSERT_TRUE(a.message("/tracking/eye/LeftRightVec", {0, 0, 1, 1, 1, 1}, s));
    ASSERT_TRUE(s);
    EXPECT_NEAR(s->left.x, 0.5, 1e-12);
    EXPECT_NEAR(s->right.x, 1.0, 1e-12);
    EXPECT_NEAR(s->right.y, 0.0, 1e-12);  // up is y = 0
    EXPECT_TRUE(s->left.valid && s->right.valid);
    a.message("/tracking/eye/EyesClosedAmount", {0.9}, s);
    ASSERT_TRUE(a.message("/tracking/eye/LeftRightVec", {0, 0, 1, 0, 0, 1}, s));
    EXPECT_FALSE(s->left.valid || s->right.valid);                        // eyes closed: a blink
    EXPECT_FALSE(a.message("/tracking/eye/LeftRightVec", {0, 0, 1}, s));  // 3 of 6 values
    EXPECT_FALSE(a.message("/avatar/unknown", {1}, s));
}

TEST(OscMap, VrcftScalarsNeedAllFourAndLidsCloseOneEye) {
    auto a = assembler(toml::table{
        {"preset", "vrcft-v2"}, {"angle_deg", 45.0}, {"fov_deg", toml::array{90.0, 90.0}}});
    const std::string p = "/avatar/parameters/v2/";
    std::optional<gaze::RawSample> s;
    a.message(p + "EyeLidLeft", {0.1}, s);
    for (const char* k : {"EyeLeftX", "EyeLeftY", "EyeRightX"}) {
        a.message(p + k, {1.0}, s);
        EXPECT_FALSE(s) << k;
    }
    ASSERT_TRUE(a.message(p + "EyeRightY", {0.0}, s));
    ASSERT_TRUE(s);
    EXPECT_FALSE(s->left.valid);  // lid 0.1 <= 0.2
    EXPECT_NEAR(s->right.x, 1.0, 1e-12);
    EXPECT_NEAR(s->right.y, 0.5, 1e-12);
}

TEST(OscMap, ArgumentsOfEveryNumericTypeFromAPacketAtAnyAlignment) {
    // Found by fuzz_osc: liblo's argv points into the packet, 4-byte aligned; reading a double
    // through lo_arg was a misaligned access.
    lo_message m = lo_message_new();
    lo_message_add_float(m, 0.25f);
    lo_message_add_double(m, -2.5);
    lo_message_add_int32(m, -7);
    lo_message_add_int64(m, int64_t{1} << 40);
    lo_message_add_true(m);
    lo_message_add_false(m);
    lo_message_add_string(m, "x");
    std::size_t size = 0;
    void* packet = lo_message_serialise(m, "/a", nullptr, &size);
    lo_message_free(m);
    ASSERT_NE(packet, nullptr);
    for (std::size_t offset : {0, 4}) {  // 8-byte and 4-byte aligned packets
        std::vector<uint64_t> storage(size / 8 + 2);
        auto* at = reinterpret_cast<char*>(storage.data()) + offset;
        std::memcpy(at, packet, size);
        int err = 0;
        lo_message parsed = lo_message_deserialise(at, size, &err);
        ASSERT_NE(parsed, nullptr) << err;
        std::vector<double> v;
        arguments_as_numbers(lo_message_get_types(parsed), lo_message_get_argv(parsed),
                             lo_message_get_argc(parsed), v);
        lo_message_free(parsed);
        ASSERT_EQ(v.size(), 7u);
        EXPECT_EQ(v[0], 0.25);
        EXPECT_EQ(v[1], -2.5);
        EXPECT_EQ(v[2], -7);
        EXPECT_EQ(v[3], static_cast<double>(int64_t{1} << 40));
        EXPECT_EQ(v[4], 1.0);
        EXPECT_EQ(v[5], 0.0);
        EXPECT_TRUE(std::isnan(v[6]));
    }
    std::free(packet);
}

TEST(OscMap, CustomMapsAndBadConfigs) {
    auto m = parse_address_map(
        toml::table{{"preset", "custom"},
                    {"addresses", toml::table{{"left_x", "/g/x"}, {"left_y", "/g/y"}}},
                    {"range", toml::array{0.0, 1.0}}});
    ASSERT_TRUE(m.ok()) << m.error().message;
    FrameAssembler a(*m);
    std::optional<gaze::RawSample> s;
    a.message("/g/x", {0.5}, s);
    a.message("/g/y", {0.5}, s);
    ASSERT_TRUE(s);
    EXPECT_NEAR(s->left.x, 0.5, 1e-12);
    EXPECT_FALSE(s->right.valid);
    auto bad = parse_address_map(toml::table{{"preset", "steamvr"}});
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("preset"), std::string::npos);
    bad = parse_address_map(
        toml::table{{"preset", "custom"}, {"addresses", toml::table{{"nose", "/n"}}}});
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("addresses.nose"), std::string::npos);
    bad = parse_address_map(toml::table{{"range", toml::array{1.0, 1.0}}});
    ASSERT_FALSE(bad.ok());
}

struct Scratch {
    fs::path dir;
    explicit Scratch(const std::string& name) {
        dir = fs::temp_directory_path() / ("fv-osc-" + name + "-" + std::to_string(getpid()));
        fs::create_directories(dir);
    }
    ~Scratch() { fs::remove_all(dir); }
};

std::unique_ptr<fovea::testing::ChildProcess> send(const Scratch& tmp, int port,
                                                   const std::string& preset) {
    return fovea::testing::spawn_logged(
        fovea::testing::kFoveaBinary,
        {"simulate", "osc", "--port", std::to_string(port), "--preset", preset, "--frames", "300",
         "--rate", "300", "--blink-every", "50", "--blink-frames", "5"},
        (tmp.dir / (preset + ".out")).string(), (tmp.dir / (preset + ".err")).string());
}

TEST(OscDriver, BothPresetsOverLoopbackUdpWithBlinks) {
    if (!fs::exists(fovea::testing::kFoveaBinary)) GTEST_SKIP() << "no fovea binary";
    Scratch tmp("drv");
    for (const std::string preset : {"vrchat", "vrcft-v2"}) {
        auto d = make_driver(toml::table{{"preset", preset}, {"port", 0}}, 1);
        ASSERT_TRUE(d.ok()) << d.error().message;
        boost::asio::io_context io;
        std::vector<gaze::RawSample> got;
        ASSERT_TRUE((*d)->open(io, [&](const gaze::RawSample& s) { got.push_back(s); }).ok());
        const int port = static_cast<int>((*d)->stats().figures.at("port"));
        ASSERT_GT(port, 0);
        EXPECT_NE((*d)->describe().name.find("no device clock"), std::string::npos);
        auto sender = send(tmp, port, preset);
        const auto end = std::chrono::steady_clock::now() + 20s * kSlowdown;
        while (got.size() < 300 && std::chrono::steady_clock::now() < end) io.run_for(20ms);
        EXPECT_EQ(sender->wait(), 0) << sender->err();
        // OSC states no rate; the driver measures the sender's 300 Hz from receipt times.
        EXPECT_NEAR((*d)->describe().nominal_rate_hz, 300.0, 45.0) << preset;
        (*d)->close();
        ASSERT_EQ(got.size(), 300u) << preset;
        int closed = 0;
        for (std::size_t i = 0; i < got.size(); ++i) {
            const bool want_closed = i % 50 < 5;
            closed += !got[i].left.valid && !got[i].right.valid;
            EXPECT_EQ(got[i].left.valid, !want_closed) << preset << " frame " << i;
            if (i) { EXPECT_GE(got[i].device_ticks, got[i - 1].device_ticks); }
        }
        EXPECT_EQ(closed, 30) << preset;
    }
}

TEST(OscDriver, ThroughARealFoveadIntoTheRing) {
    if (!fs::exists(fovea::testing::kFoveadBinary)) GTEST_SKIP() << "no fovead binary";
    Scratch tmp("fovead");
    setenv("FOVEA_RUNTIME_DIR", tmp.dir.c_str(), 1);
    const std::string instance = "osc" + std::to_string(getpid());
    const fs::path cfg = tmp.dir / "osc.toml";
    std::ofstream(cfg) << "[[device]]\ndriver = \"osc\"\npreset = \"vrcft-v2\"\nport = 0\n";
    auto daemon = fovea::testing::spawn_logged(
        fovea::testing::kFoveadBinary, {"--instance", instance, "--config", cfg.string()},
        (tmp.dir / "d.out").string(), (tmp.dir / "d.err").string());
    int port = 0;
    for (int i = 0; i < 200 * kSlowdown && port == 0; ++i) {
        auto st = fovea::testing::spawn_logged(
            fovea::testing::kFoveaBinary, {"--instance", instance, "status"},
            (tmp.dir / "s.out").string(), (tmp.dir / "s.err").string());
        if (st->wait() == 0) {
            const auto j = nlohmann::json::parse(st->out(), nullptr, false);
            if (!j.is_discarded() && j.contains("devices"))
                port = j["devices"][0]["details"].value("port", 0.0);
        }
        if (!port) std::this_thread::sleep_for(20ms);
    }
    ASSERT_GT(port, 0) << daemon->err();
    fovea::Client client(instance);
    uint64_t cursor = client.head(), records = 0, blinks = 0;
    auto sender = send(tmp, port, "vrcft-v2");
    const auto end = std::chrono::steady_clock::now() + 20s * kSlowdown;
    while (records < 300 && std::chrono::steady_clock::now() < end) {
        if (!client.wait(cursor, 100)) continue;
        for (const auto& r : client.read(cursor).records) {
            ++records;
            blinks += !(r.left.valid & FOVEA_VALID) && !(r.right.valid & FOVEA_VALID);
        }
    }
    EXPECT_EQ(sender->wait(), 0) << sender->err();
    EXPECT_EQ(records, 300u) << daemon->err();
    EXPECT_EQ(blinks, 30u);
    kill(daemon->pid, SIGTERM);
    EXPECT_EQ(daemon->wait(10s), 0) << daemon->err();
}

}  // namespace
}  // namespace fovea::drivers::osc
