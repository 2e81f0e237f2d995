// Live path smoke tests on this machine: hidapi enumeration and the "hid" driver's lifecycle.
// Machines without trackers (CI) must report zero devices cleanly.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include <boost/asio/io_context.hpp>

#include "fovea/drivers/driver.hpp"
#include "hid/enumerate.hpp"

using namespace fovea::drivers;

TEST(HidEnumerate, ListsOnlyUsagePage0x12TrackersAndSucceedsWithNone) {
    auto list = hid::enumerate_trackers();
    ASSERT_TRUE(list.ok()) << list.error().message;
    for (const auto& d : *list) {
        EXPECT_TRUE(d.usage == 0x01 || d.usage == 0x02) << d.path;
        EXPECT_FALSE(d.path.empty());
    }
    std::printf("usage page 0x12 devices on this machine: %zu\n", list->size());
}

TEST(HidEnumerate, MissingHidrawNodeIsAClearError) {
    auto r = hid::read_report_descriptor("/dev/hidraw-does-not-exist");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("/dev/hidraw-does-not-exist"), std::string::npos);
}

TEST(HidDriver, AbsentDeviceIsNotAnErrorAndCloseIsPrompt) {
    auto cfg = toml::parse(R"(driver = "hid"
vid = "0x1234"
pid = 0x5678
screen_width_mm = 531.0
screen_height_mm = 299.0)");
    auto drv = make_driver(cfg, 3);
    ASSERT_TRUE(drv.ok()) << drv.error().message;
    boost::asio::io_context io;
    int samples = 0;
    ASSERT_TRUE((*drv)->open(io, [&](const fovea::gaze::RawSample&) { ++samples; }).ok());
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // reader thread tries once
    io.poll();
    const auto st = (*drv)->stats();
    EXPECT_FALSE(st.connected);
    EXPECT_FALSE(st.last_error.empty());
    EXPECT_EQ((*drv)->describe().driver, "hid");
    (*drv)->close();
    EXPECT_EQ(samples, 0);
}

TEST(HidDriver, BadVidIsAConfigurationError) {
    auto cfg = toml::parse(R"(driver = "hid"
vid = "zz")");
    auto drv = make_driver(cfg, 0);
    ASSERT_FALSE(drv.ok());
    EXPECT_NE(drv.error().message.find("vid"), std::string::npos);
}
