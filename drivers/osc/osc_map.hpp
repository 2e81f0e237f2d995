// What OSC addresses mean: presets for VR eye trackers (EyeTrackVR and others) and custom maps,
// and the assembly of messages into gaze samples. Pure: no sockets; one thread.
//   vrchat:   /tracking/eye/LeftRightVec  6 floats, left then right unit gaze direction
//             (x right, y up, z forward); /tracking/eye/EyesClosedAmount 0 open .. 1 closed.
//   vrcft-v2: /avatar/parameters/v2/EyeLeftX, EyeLeftY, EyeRightX, EyeRightY (each `range`,
//             its ends `angle_deg` either side of straight ahead; y up), EyeLidLeft,
//             EyeLidRight (0 closed .. 1 open), PupilDilation (0..1, relative: not mm).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <lo/lo_osc_types.h>
#include <toml++/toml.h>

#include "fovea/gaze/sample.hpp"
#include "fovea/result.hpp"

namespace fovea::drivers::osc {

enum class Role {
    kLeftX,
    kLeftY,
    kRightX,
    kRightY,        // one scalar each, in `range`
    kLeftRightVec,  // 6 floats: two gaze direction vectors
    kEyesClosed,    // 0 open .. 1 closed, both eyes
    kLeftLid,
    kRightLid,       // 0 closed .. 1 open
    kPupilDilation,  // relative 0..1, reported in status only
};

struct AddressMap {
    std::string preset;  // "vrchat", "vrcft-v2" or "custom"
    std::vector<std::pair<std::string, Role>> addresses;
    double range_min = -1.0, range_max = 1.0;   // scalar gaze values
    double angle_deg = 45.0;                    // the angle range_max stands for
    double hfov_deg = 100.0, vfov_deg = 100.0;  // the headset's field of view (display plane)
    double closed_above = 0.8;                  // EyesClosedAmount at or above: closed (blink)
    double lid_below = 0.2;                     // EyeLid at or below: that eye closed
};

// `preset` (default "vrchat"); for "custom" an [addresses] table of role = "/osc/address"
// (left_x, left_y, right_x, right_y, left_right_vec, eyes_closed, left_lid, right_lid,
// pupil_dilation); range = [min, max], angle_deg, fov_deg = [h, v], closed_above, lid_below.
Result<AddressMap> parse_address_map(const toml::table& config);

// A message's arguments as numbers (f d i h; T 1, F 0; any other type NaN), replacing `out`.
// liblo's argv points into the packet, 4-byte aligned, so values are copied out, never read
// through lo_arg's 8-byte members.
void arguments_as_numbers(const char* types, lo_arg* const* argv, int argc,
                          std::vector<double>& out);

// Collects the latest value of every mapped address; a sample is complete once every gaze
// address has been updated since the last one (one LeftRightVec message, or all four scalars).
class FrameAssembler {
public:
    explicit FrameAssembler(AddressMap map);
    // Values of one message; false if the address is not mapped or the values do not fit.
    // `out` is set when this message completed a sample (eyes in normalized display units,
    // closed eyes invalid).
    bool message(std::string_view address, const std::vector<double>& values,
                 std::optional<gaze::RawSample>& out);
    const AddressMap& map() const { return map_; }
    double pupil_dilation() const { return dilation_; }

private:
    void to_display(double yaw_tan, double pitch_tan, gaze::EyeSample& e) const;
    AddressMap map_;
    std::vector<bool> gaze_roles_;  // per address: part of the gaze set
    std::vector<bool> updated_;
    double v_[4] = {0, 0, 0, 0};  // scalar left x, y, right x, y
    double vec_[6] = {0, 0, 1, 0, 0, 1};
    double closed_ = 0.0, lid_[2] = {1.0, 1.0}, dilation_ = gaze::kNaN;
};

}  // namespace fovea::drivers::osc
