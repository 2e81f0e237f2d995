// Display profiles (HMDs and monitors) as data files, and the mapping of eye-in-head gaze
// directions to each eye's display coordinates and degrees, plus the binocular vergence point.
// Value types and pure functions: any thread.
//
// Conventions: eye frame +x right, +y down, +z forward (out of the eye), matching the display's
// normalized coordinates (0..1, origin top-left) and the ring's degrees (+x right, +y down).
// Degrees are measured from the eye's optical axis (the projection centre), which is where the
// retina's eccentricity is zero; on a symmetric view it is the display centre.
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "fovea/gaze/sample.hpp"
#include "fovea/result.hpp"

namespace fovea::drivers::profiles {

using Vec3 = std::array<double, 3>;

// One eye's view: a planar image in tangent space bounded by four half-angles.
struct EyeView {
    int width_px = 0;
    int height_px = 0;
    double fov_left_deg = 0, fov_right_deg = 0, fov_up_deg = 0, fov_down_deg = 0;

    // Projection centre (optical axis) in normalized coordinates, from the half-angles.
    double center_x() const;
    double center_y() const;
    // Pixels per degree at the projection centre, horizontal and vertical.
    double pixels_per_degree_x() const;
    double pixels_per_degree_y() const;
};

enum class DisplayKind { kHmd, kMonitor };

struct DisplayProfile {
    std::string name;
    std::string description;
    DisplayKind kind = DisplayKind::kMonitor;
    EyeView left, right;  // a monitor's two views are the same
    double ipd_m = 0.063;
    // Monitors: the physical screen and viewing distance the views were derived from.
    double width_m = 0, height_m = 0, distance_m = 0;

    const EyeView& eye(int index) const { return index == 0 ? left : right; }
    // The flat-screen geometry the gaze chain uses for this eye. Exact for monitors and
    // symmetric HMD views; an asymmetric view keeps its size but is centred (gaze::DisplayGeometry
    // has no projection-centre offset).
    gaze::DisplayGeometry display_geometry(int eye_index = 0) const;
};

struct EyePoint {
    double norm_x = gaze::kNaN, norm_y = gaze::kNaN;  // normalized display coordinates
    double deg_x = gaze::kNaN, deg_y = gaze::kNaN;    // from the optical axis
    double px_x = gaze::kNaN, px_y = gaze::kNaN;      // pixels
    bool valid = false;                               // finite and in front of the eye
    bool inside = false;                              // within the view's field of view
};

// A gaze direction (any length, eye frame) to the eye's display.
EyePoint map_direction(const EyeView& view, const Vec3& direction);
// Normalized display coordinates back to a unit direction.
Vec3 direction_from_normalized(const EyeView& view, double norm_x, double norm_y);
// The same for many points through one view: its half-angles' tangents, computed once.
struct ViewTangents {
    double left = 0, right = 0, up = 0, down = 0;
};
ViewTangents tangents(const EyeView& view);
Vec3 direction_from_normalized(const ViewTangents& view, double norm_x, double norm_y);

struct VergencePoint {
    bool valid = false;                                // false for parallel or diverging rays
    Vec3 point_m{gaze::kNaN, gaze::kNaN, gaze::kNaN};  // midpoint of the rays' closest points
    double distance_m = gaze::kNaN;                    // from the midpoint between the eyes
    double vergence_deg = 0;                           // angle between the two gaze rays
    double miss_m = gaze::kNaN;  // closest distance between the rays (noise indicator)
    Vec3 cyclopean{0, 0, 1};     // unit direction from between the eyes to the point
};

// Closest approach of two gaze rays, in the head frame.
VergencePoint vergence(const Vec3& left_origin, const Vec3& left_dir, const Vec3& right_origin,
                       const Vec3& right_dir);
// Eyes at (-ipd/2, 0, 0) and (+ipd/2, 0, 0), eye frames parallel to the head frame.
VergencePoint vergence(const DisplayProfile& profile, const Vec3& left_dir, const Vec3& right_dir);

// Parse and validate a profile (TOML text; see drivers/profiles/README.md for the keys).
Result<DisplayProfile> parse_profile(std::string_view toml_text, std::string_view origin = "");
Result<DisplayProfile> load_profile_file(const std::string& path);
// By file path, or by name in: $FOVEA_PROFILES_PATH (colon-separated), `extra_dirs`, then the
// built-in directory. Config key: display_profile = "<name or path>".
Result<DisplayProfile> find_profile(const std::string& name_or_path,
                                    const std::vector<std::string>& extra_dirs = {});
// Names of the profiles in the search path, sorted.
std::vector<std::string> list_profiles(const std::vector<std::string>& extra_dirs = {});
// The directory the built-in profiles are installed to (or the source tree's, uninstalled).
std::string builtin_profiles_dir();

}  // namespace fovea::drivers::profiles
