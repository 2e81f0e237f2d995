// One Pupil Labs datum (a msgpack map, as Pupil Capture publishes it on its bus and stores it in
// .pldata files), decoded with msgpack-cxx: the single decoder for the Pupil recording importer
// and the live `pupil` driver. Pure functions; any thread.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include "fovea/gaze/sample.hpp"
#include "fovea/result.hpp"

namespace fovea::import {

struct PupilDatum {
    std::string topic;    // "gaze.3d.01.", "gaze.2d.0.", "pupil.1", "notify.x", "blinks", ...
    std::string subject;  // notifications: "calibration.successful", ...
    std::string type;     // blinks: "onset" / "offset"
    double timestamp = gaze::kNaN;    // Pupil time, seconds
    double confidence = gaze::kNaN;   // 0..1
    double duration_ms = gaze::kNaN;  // fixations
    // As sent: normalized world (gaze) or eye (pupil) camera image, origin bottom-left.
    double norm_x = gaze::kNaN, norm_y = gaze::kNaN;
    int eye_id = -1;  // pupil datums: 0 (Pupil's eye0, the right eye) or 1 (left)
    // Per eye id: pupil diameter in mm (3d model) and in eye camera pixels; for gaze datums
    // taken from the pupil datums in base_data (msgpack ExtType 13 wrapping a map).
    std::array<double, 2> diameter_mm{gaze::kNaN, gaze::kNaN};
    std::array<double, 2> diameter_px{gaze::kNaN, gaze::kNaN};
    // 3d gaze, per eye id: "eye_centers_3d"/"gaze_normals_3d" keyed 0/1 (binocular) or
    // "eye_center_3d"/"gaze_normal_3d" (monocular, for the topic's eye), mm / unit vectors.
    std::array<bool, 2> has_3d{false, false};
    std::array<std::array<double, 3>, 2> eye_center_mm{};
    std::array<std::array<double, 3>, 2> gaze_normal{};
    std::array<double, 3> gaze_point_mm{gaze::kNaN, gaze::kNaN, gaze::kNaN};
    int base_data = 0;  // pupil datums found in base_data

    bool is_gaze() const { return topic.starts_with("gaze."); }
    bool is_pupil() const { return topic.starts_with("pupil."); }
    // Which eyes a gaze datum comes from: "gaze.3d.01." both, "...0." eye0, "...1." eye1.
    bool from_eye(int id) const;
};

// Decode one datum. Errors say what is missing ("not a msgpack map", "no timestamp").
Result<PupilDatum> decode_pupil_datum(std::string_view msgpack);

// A gaze or pupil datum as a chain sample: Pupil's eye0 is the right eye, eye1 the left; a
// binocular gaze point goes to both eyes (it is one point); y flipped to origin top-left;
// confidence below `min_confidence` leaves the eyes invalid. device_ticks = ns of Pupil time.
// False for datums that are neither gaze nor pupil, or have no norm_pos or time stamp.
bool pupil_sample(const PupilDatum& d, double min_confidence, gaze::RawSample& out);

}  // namespace fovea::import
