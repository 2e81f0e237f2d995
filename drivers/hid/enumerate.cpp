#include "hid/enumerate.hpp"

#include <fcntl.h>
#include <linux/hidraw.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <cwchar>
#include <fstream>
#include <iterator>
#include <mutex>

#include <hidapi.h>

#include "hid/tracker.hpp"

namespace fovea::drivers::hid {
namespace {

std::string narrow(const wchar_t* w) {
    std::string out;
    if (w == nullptr) return out;
    for (; *w != 0; ++w) out += (*w < 0x80) ? static_cast<char>(*w) : '?';
    return out;
}

}  // namespace

// hid_init is not thread-safe and must run once before any other hidapi call.
Result<void> ensure_hidapi() {
    static std::once_flag once;
    static int rc = 0;
    std::call_once(once, [] { rc = hid_init(); });
    if (rc != 0) return make_error("hid_init failed");
    return {};
}

Result<std::vector<TrackerDevice>> enumerate_trackers() {
    if (auto r = ensure_hidapi(); !r) return r.error();
    std::vector<TrackerDevice> out;
    hid_device_info* list = hid_enumerate(0, 0);
    for (hid_device_info* d = list; d != nullptr; d = d->next) {
        if (d->usage_page != usage::kPage) continue;
        TrackerDevice t;
        t.path = d->path ? d->path : "";
        t.vendor_id = d->vendor_id;
        t.product_id = d->product_id;
        t.usage = d->usage;
        t.serial = narrow(d->serial_number);
        t.manufacturer = narrow(d->manufacturer_string);
        t.product = narrow(d->product_string);
        out.push_back(std::move(t));
    }
    hid_free_enumeration(list);
    return out;
}

Result<std::vector<uint8_t>> read_report_descriptor(const std::string& hidraw_path) {
    const auto slash = hidraw_path.find_last_of('/');
    const std::string node = hidraw_path.substr(slash == std::string::npos ? 0 : slash + 1);
    std::ifstream sys("/sys/class/hidraw/" + node + "/device/report_descriptor", std::ios::binary);
    if (sys) {
        std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(sys)),
                                   std::istreambuf_iterator<char>());
        if (!bytes.empty()) return bytes;
    }
    const int fd = ::open(hidraw_path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return make_error(
            "cannot read the report descriptor of " + hidraw_path + ": " + std::strerror(errno),
            errno);
    int size = 0;
    hidraw_report_descriptor desc{};
    int rc = ::ioctl(fd, HIDIOCGRDESCSIZE, &size);
    if (rc == 0) {
        desc.size = static_cast<uint32_t>(size);
        rc = ::ioctl(fd, HIDIOCGRDESC, &desc);
    }
    const int err = errno;
    ::close(fd);
    if (rc < 0)
        return make_error("HIDIOCGRDESC on " + hidraw_path + ": " + std::strerror(err), err);
    return std::vector<uint8_t>(desc.value, desc.value + desc.size);
}

}  // namespace fovea::drivers::hid
