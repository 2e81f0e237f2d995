#include <iterator>
#include <string>

#include "fovea/drivers/driver.hpp"
#include "gazepoint/gazepoint_driver.hpp"
#include "hid/hid_driver.hpp"
#include "osc/osc_driver.hpp"
#include "pupil/pupil_driver.hpp"
#include "replay/replay_driver.hpp"
#include "serial/serial_driver.hpp"
#include "sim/sim_driver.hpp"
#include "usb/usb_driver.hpp"

namespace fovea::drivers {
namespace {

// One line per driver.
constexpr DriverRegistration kDrivers[] = {
    {"sim", &sim::make_driver},
    {"hid", &hid::make_driver},
    {"usb", &usb::make_driver},
    {"serial", &serial::make_driver},
    {"gazepoint", &gazepoint::make_driver},
    {"replay", &replay::make_driver},
    {"pupil", &pupil::make_driver},
    {"osc", &osc::make_driver},
};

}  // namespace

const DriverRegistration* registered_drivers(std::size_t& count) {
    count = std::size(kDrivers);
    return kDrivers;
}

Result<std::unique_ptr<Driver>> make_driver(const toml::table& config, uint32_t device_id) {
    const std::string name = config["driver"].value_or(std::string("sim"));
    for (const auto& d : kDrivers)
        if (name == d.name) return d.factory(config, device_id);
    std::string known;
    for (const auto& d : kDrivers) known += std::string(known.empty() ? "" : ", ") + d.name;
    return make_error("unknown driver '" + name + "' (known: " + known + ")");
}

}  // namespace fovea::drivers
