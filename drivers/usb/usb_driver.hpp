// The "usb" driver: a vendor-class USB interface carrying the serial protocol's frames
// (drivers/serial/PROTOCOL.md) in bulk or interrupt IN transfers. libusb asynchronous transfers
// and hotplug run on the driver's own event thread, which posts samples into the io_context.
//
// [[device]] keys: driver = "usb"; vid, pid (required; integers or hex strings "0x1234");
// optional interface (number; default: the first vendor-class 0xFF interface), endpoint (IN
// endpoint address, e.g. 0x81; default: the interface's first bulk/interrupt IN endpoint),
// transfers (in flight, 1..32, default 4), transfer_size (bytes, 64..65536, default 1024).
// A kernel driver bound to the interface is detached on open and reattached on close.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "fovea/drivers/driver.hpp"

namespace fovea::drivers::usb {

// Factory registered as "usb" in drivers/registry.cpp.
Result<std::unique_ptr<Driver>> make_driver(const toml::table& config, uint32_t device_id);

struct UsbDeviceInfo {
    uint16_t vendor_id = 0, product_id = 0;
    uint8_t bus = 0, address = 0;
    uint8_t device_class = 0;
};

// Every USB device libusb sees (libusb_init + libusb_get_device_list). Blocking; not for the
// loop thread. No devices (or no USB at all in a container) is an empty list, not an error.
Result<std::vector<UsbDeviceInfo>> list_usb_devices();

}  // namespace fovea::drivers::usb
