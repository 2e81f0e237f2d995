// Ring records to gaze directions in OpenXR's view space (+x right, +y up, -z forward, origin
// between the eyes), from the eye geometry fovead publishes in the ring header (its HMD
// display_profile). Used by the layer and by `fovea openxr-check`, so both map a record the same
// way. Immutable after construction: any thread.
#pragma once

#include <optional>

#include "fovea/ring.h"
#include "pose_math.hpp"
#include "profiles/display_profile.hpp"

namespace fovea::openxr {

class GazeGeometry {
public:
    // ipd_m == 0 (fovead without an HMD profile): directions come from the ring's degrees from
    // the display centre, the display taken as centred on the view.
    explicit GazeGeometry(const fovea_eye_geometry& eyes = {});

    bool has_eye_views() const { return has_views_; }
    double ipd_m() const { return ipd_m_; }

    // The combined gaze of one record, nullopt when the record says the eyes are not tracked.
    // Both eyes tracked: from between the eyes towards the point where the two eyes' rays
    // (each eye's display coordinates through its own view) meet, or their mean direction when
    // they do not meet in front; one eye: that eye's direction; neither but the combined point:
    // that point through the mean of the two views.
    std::optional<Vec3> combined(const fovea_gaze_record& r) const;

    // Where the record predicts the saccade lands: `current` (its combined direction) turned by
    // the display-space move from the combined point to the landing point. nullopt without a
    // landing prediction.
    std::optional<Vec3> landing(const fovea_gaze_record& r, const Vec3& current) const;

private:
    Vec3 through_mean_view(double norm_x, double norm_y) const;

    bool has_views_ = false;
    double ipd_m_ = 0;
    drivers::profiles::ViewTangents eyes_[2], mean_;
};

// Eye frame of drivers/profiles (+y down, +z forward) to OpenXR's view frame.
inline Vec3 eye_to_view(const drivers::profiles::Vec3& d) { return {d[0], -d[1], -d[2]}; }

}  // namespace fovea::openxr
