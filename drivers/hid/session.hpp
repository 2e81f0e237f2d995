// One connected tracker: descriptor, located layout, feature-report state, and the conversion of
// input reports into RawSample / HeadPose. No I/O: the HID driver's reader thread feeds it, and
// tests feed it generated reports. Not thread-safe; owned by one thread.
#pragma once

#include <cstdint>
#include <span>

#include "fovea/drivers/driver.hpp"
#include "hid/descriptor.hpp"
#include "hid/tracker.hpp"

namespace fovea::drivers::hid {

class TrackerSession {
public:
    // `fallback_screen_*_um`: screen size to use when the device reports no calibrated size.
    static Result<TrackerSession> create(std::span<const uint8_t> descriptor,
                                         double fallback_screen_width_um = 0,
                                         double fallback_screen_height_um = 0);

    // A feature report as read (report ID byte first when numbered); updates info().
    int apply_feature(std::span<const uint8_t> report);

    struct Outcome {
        DecodeStatus status = DecodeStatus::kOk;
        bool gaze = false;  // `sample` was filled
        bool head = false;  // `pose` was filled
    };
    Outcome on_report(std::span<const uint8_t> report, int64_t t_receive_ns, uint32_t device_id,
                      gaze::RawSample& sample, HeadPose& pose) const;

    const ReportDescriptor& descriptor() const { return desc_; }
    const TrackerLayout& layout() const { return layout_; }
    const TrackerInfo& info() const { return info_; }
    // Bits of the device timestamp (for ClockSync's unwrapping) and its tick rate.
    gaze::DeviceClock clock() const;
    // Screen size in use: calibrated if the device reported one, else the fallback.
    double screen_width_um() const;
    double screen_height_um() const;

private:
    ReportDescriptor desc_;
    TrackerLayout layout_;
    TrackerInfo info_;
    double fallback_w_um_ = 0, fallback_h_um_ = 0;
};

}  // namespace fovea::drivers::hid
