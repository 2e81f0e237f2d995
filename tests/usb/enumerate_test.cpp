// Live path smoke tests on this machine: libusb_init + the device list, and the "usb" driver's
// lifecycle with no matching device (hotplug registered, clean close).
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include <boost/asio/io_context.hpp>

#include "fovea/drivers/driver.hpp"
#include "usb/usb_driver.hpp"

using namespace fovea::drivers;

TEST(UsbEnumerate, DeviceListWorksOnThisMachine) {
    auto list = usb::list_usb_devices();
    ASSERT_TRUE(list.ok()) << list.error().message;
    std::printf("USB devices visible to libusb: %zu\n", list->size());
}

TEST(UsbDriver, AbsentDeviceKeepsRetryingAndClosesCleanly) {
    auto cfg = toml::parse("driver = \"usb\"\nvid = \"0xf0ea\"\npid = 0x0001\n");
    auto drv = make_driver(cfg, 1);
    ASSERT_TRUE(drv.ok()) << drv.error().message;
    boost::asio::io_context io;
    int samples = 0;
    ASSERT_TRUE((*drv)->open(io, [&](const fovea::gaze::RawSample&) { ++samples; }).ok());
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    io.poll();
    const auto st = (*drv)->stats();
    EXPECT_FALSE(st.connected);
    EXPECT_NE(st.last_error.find("f0ea:0001"), std::string::npos) << st.last_error;
    EXPECT_EQ((*drv)->describe().address, "f0ea:0001");
    const auto t0 = std::chrono::steady_clock::now();
    (*drv)->close();
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::milliseconds(500));
    EXPECT_EQ(samples, 0);
}

TEST(UsbDriver, ConfigurationErrorsAreClear) {
    auto no_ids = make_driver(toml::parse("driver = \"usb\"\n"), 0);
    ASSERT_FALSE(no_ids.ok());
    EXPECT_NE(no_ids.error().message.find("'vid' and 'pid'"), std::string::npos);
    auto bad_ep = make_driver(toml::parse("driver = \"usb\"\nvid = 1\npid = 2\nendpoint = 1\n"), 0);
    ASSERT_FALSE(bad_ep.ok());
    EXPECT_NE(bad_ep.error().message.find("IN endpoint"), std::string::npos);
    auto bad_n = make_driver(toml::parse("driver = \"usb\"\nvid = 1\npid = 2\ntransfers = 0\n"), 0);
    EXPECT_FALSE(bad_n.ok());
}
