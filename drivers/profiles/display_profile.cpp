#include "profiles/display_profile.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <toml++/toml.h>

namespace fovea::drivers::profiles {
namespace {

constexpr double kDegToRad = 0.017453292519943295;
constexpr double kRadToDeg = 57.29577951308232;
// The loader checks a file's declared pixels_per_degree against its geometry to this tolerance.
constexpr double kPpdTolerance = 0.02;

double tan_deg(double d) { return std::tan(d * kDegToRad); }

double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 add_scaled(const Vec3& a, const Vec3& d, double s) {
    return {a[0] + d[0] * s, a[1] + d[1] * s, a[2] + d[2] * s};
}

Result<EyeView> read_view(const toml::table& t, const std::string& where) {
    EyeView v;
    v.width_px = t["width_px"].value_or(0);
    v.height_px = t["height_px"].value_or(0);
    v.fov_left_deg = t["fov_left_deg"].value_or(gaze::kNaN);
    v.fov_right_deg = t["fov_right_deg"].value_or(gaze::kNaN);
    v.fov_up_deg = t["fov_up_deg"].value_or(gaze::kNaN);
    v.fov_down_deg = t["fov_down_deg"].value_or(gaze::kNaN);
    if (v.width_px <= 0 || v.height_px <= 0)
        return make_error(where + ": width_px and height_px must be positive integers");
    for (double a : {v.fov_left_deg, v.fov_right_deg, v.fov_up_deg, v.fov_down_deg})
        if (!(a > -89.0 && a < 89.0))
            return make_error(where + ": fov_{left,right,up,down}_deg are required half-angles "
                                      "in (-89, 89) degrees");
    if (!(v.fov_left_deg + v.fov_right_deg > 0.1) || !(v.fov_up_deg + v.fov_down_deg > 0.1))
        return make_error(where + ": the field of view must have a positive extent");
    if (auto ppd = t["pixels_per_degree"].value<double>()) {
        const double actual = v.pixels_per_degree_x();
        if (std::fabs(*ppd - actual) > kPpdTolerance * actual) {
            std::ostringstream os;
            os << where << ": pixels_per_degree = " << *ppd << " but the resolution and field "
               << "of view give " << actual;
            return make_error(os.str());
        }
    }
    return v;
}

}  // namespace

double EyeView::center_x() const {
    const double l = tan_deg(fov_left_deg), r = tan_deg(fov_right_deg);
    return l / (l + r);
}
double EyeView::center_y() const {
    const double u = tan_deg(fov_up_deg), d = tan_deg(fov_down_deg);
    return u / (u + d);
}
double EyeView::pixels_per_degree_x() const {
    return width_px / (tan_deg(fov_left_deg) + tan_deg(fov_right_deg)) * tan_deg(1.0);
}
double EyeView::pixels_per_degree_y() const {
    return height_px / (tan_deg(fov_up_deg) + tan_deg(fov_down_deg)) * tan_deg(1.0);
}

gaze::DisplayGeometry DisplayProfile::display_geometry(int eye_index) const {
    gaze::DisplayGeometry g;
    const EyeView& v = eye(eye_index);
    g.width_px = v.width_px;
    g.height_px = v.height_px;
    if (kind == DisplayKind::kMonitor && width_m > 0) {
        g.width_m = width_m;
        g.height_m = height_m;
        g.distance_m = distance_m;
    } else {  // the virtual image plane at 1 m
        g.distance_m = 1.0;
        g.width_m = tan_deg(v.fov_left_deg) + tan_deg(v.fov_right_deg);
        g.height_m = tan_deg(v.fov_up_deg) + tan_deg(v.fov_down_deg);
    }
    return g;
}

EyePoint map_direction(const EyeView& view, const Vec3& d) {
    EyePoint p;
    if (!(std::isfinite(d[0]) && std::isfinite(d[1]) && std::isfinite(d[2])) || !(d[2] > 0))
        return p;  // behind or level with the eye: no point on the display
    const double tx = d[0] / d[2], ty = d[1] / d[2];
    const double l = tan_deg(view.fov_left_deg), r = tan_deg(view.fov_right_deg);
    const double u = tan_deg(view.fov_up_deg), dn = tan_deg(view.fov_down_deg);
    p.norm_x = (tx + l) / (l + r);
    p.norm_y = (ty + u) / (u + dn);
    p.px_x = p.norm_x * view.width_px;
    p.px_y = p.norm_y * view.height_px;
    p.deg_x = std::atan(tx) * kRadToDeg;
    p.deg_y = std::atan(ty) * kRadToDeg;
    p.valid = std::isfinite(p.norm_x) && std::isfinite(p.norm_y);
    p.inside = p.valid && p.norm_x >= 0 && p.norm_x <= 1 && p.norm_y >= 0 && p.norm_y <= 1;
    return p;
}

Vec3 direction_from_normalized(const EyeView& view, double nx, double ny) {
    const double l = tan_deg(view.fov_left_deg), r = tan_deg(view.fov_right_deg);
    const double u = tan_deg(view.fov_up_deg), dn = tan_deg(view.fov_down_deg);
    const double tx = nx * (l + r) - l, ty = ny * (u + dn) - u;
    const double n = std::sqrt(tx * tx + ty * ty + 1.0);
    return {tx / n, ty / n, 1.0 / n};
}

VergencePoint vergence(const Vec3& p1, const Vec3& d1, const Vec3& p2, const Vec3& d2) {
    VergencePoint v;
    const double a = dot(d1, d1), b = dot(d1, d2), c = dot(d2, d2);
    if (!(a > 0) || !(c > 0)) return v;
    const double cosang = std::clamp(b / std::sqrt(a * c), -1.0, 1.0);
    v.vergence_deg = std::acos(cosang) * kRadToDeg;
    const Vec3 w0 = sub(p1, p2);
    const double d = dot(d1, w0), e = dot(d2, w0);
    const double den = a * c - b * b;
    // Parallel rays (relative to their lengths) meet at infinity: no 3D point.
    if (!(den > 1e-12 * a * c)) return v;
    const double s = (b * e - c * d) / den, t = (a * e - b * d) / den;
    if (!(s > 0) || !(t > 0)) return v;  // the rays diverge: they met behind the eyes
    const Vec3 q1 = add_scaled(p1, d1, s), q2 = add_scaled(p2, d2, t);
    const Vec3 gap = sub(q1, q2);
    v.miss_m = std::sqrt(dot(gap, gap));
    v.point_m = {(q1[0] + q2[0]) / 2, (q1[1] + q2[1]) / 2, (q1[2] + q2[2]) / 2};
    const Vec3 mid{(p1[0] + p2[0]) / 2, (p1[1] + p2[1]) / 2, (p1[2] + p2[2]) / 2};
    const Vec3 to = sub(v.point_m, mid);
    v.distance_m = std::sqrt(dot(to, to));
    if (v.distance_m > 0) v.cyclopean = {to[0] / v.distance_m, to[1] / v.distance_m, to[2] / v.distance_m};
    v.valid = std::isfinite(v.distance_m);
    return v;
}

VergencePoint vergence(const DisplayProfile& profile, const Vec3& left_dir, const Vec3& right_dir) {
    const double h = profile.ipd_m / 2;
    return vergence({-h, 0, 0}, left_dir, {h, 0, 0}, right_dir);
}

Result<DisplayProfile> parse_profile(std::string_view text, std::string_view origin) {
    const std::string where = origin.empty() ? std::string("profile") : std::string(origin);
    toml::table t;
    try {
        t = toml::parse(text);
    } catch (const toml::parse_error& e) {
        return make_error(where + ": " + std::string(e.description()));
    }
    DisplayProfile p;
    p.name = t["name"].value_or(std::string());
    p.description = t["description"].value_or(std::string());
    if (p.name.empty()) return make_error(where + ": 'name' is required");
    const std::string kind = t["kind"].value_or(std::string());
    p.ipd_m = t["ipd_m"].value_or(0.063);
    if (!(p.ipd_m > 0.03 && p.ipd_m < 0.09))
        return make_error(where + ": ipd_m must be between 0.03 and 0.09 m");
    if (kind == "hmd") {
        p.kind = DisplayKind::kHmd;
        const toml::table* l = t["left"].as_table();
        const toml::table* r = t["right"].as_table();
        if (!l || !r) return make_error(where + ": an hmd needs [left] and [right] tables");
        auto lv = read_view(*l, where + " [left]");
        if (!lv) return lv.error();
        auto rv = read_view(*r, where + " [right]");
        if (!rv) return rv.error();
        p.left = *lv;
        p.right = *rv;
    } else if (kind == "monitor") {
        p.kind = DisplayKind::kMonitor;
        p.width_m = t["width_m"].value_or(0.0);
        p.height_m = t["height_m"].value_or(0.0);
        p.distance_m = t["distance_m"].value_or(0.0);
        if (!(p.width_m > 0) || !(p.height_m > 0) || !(p.distance_m > 0))
            return make_error(where + ": a monitor needs positive width_m, height_m, distance_m");
        // The views follow from the physical size: a centred screen, square to the line of sight.
        toml::table view;
        view.insert("width_px", t["width_px"].value_or(0));
        view.insert("height_px", t["height_px"].value_or(0));
        const double hx = std::atan(p.width_m / 2 / p.distance_m) * kRadToDeg;
        const double hy = std::atan(p.height_m / 2 / p.distance_m) * kRadToDeg;
        view.insert("fov_left_deg", hx);
        view.insert("fov_right_deg", hx);
        view.insert("fov_up_deg", hy);
        view.insert("fov_down_deg", hy);
        if (auto ppd = t["pixels_per_degree"].value<double>()) view.insert("pixels_per_degree", *ppd);
        auto v = read_view(view, where);
        if (!v) return v.error();
        p.left = p.right = *v;
    } else {
        return make_error(where + ": kind must be \"hmd\" or \"monitor\"");
    }
    return p;
}

Result<DisplayProfile> load_profile_file(const std::string& path) {
    std::ifstream in(path);
    if (!in) return make_error("cannot read display profile " + path);
    std::stringstream ss;
    ss << in.rdbuf();
    return parse_profile(ss.str(), path);
}

std::string builtin_profiles_dir() {
#ifdef FOVEA_PROFILES_INSTALL_DIR
    if (std::filesystem::is_directory(FOVEA_PROFILES_INSTALL_DIR)) return FOVEA_PROFILES_INSTALL_DIR;
#endif
    return FOVEA_PROFILES_SOURCE_DIR;
}

namespace {

std::vector<std::string> search_dirs(const std::vector<std::string>& extra) {
    std::vector<std::string> dirs;
    if (const char* env = std::getenv("FOVEA_PROFILES_PATH")) {
        std::stringstream ss(env);
        std::string d;
        while (std::getline(ss, d, ':'))
            if (!d.empty()) dirs.push_back(d);
    }
    dirs.insert(dirs.end(), extra.begin(), extra.end());
    dirs.push_back(builtin_profiles_dir());
    return dirs;
}

}  // namespace

Result<DisplayProfile> find_profile(const std::string& name_or_path,
                                    const std::vector<std::string>& extra_dirs) {
    if (name_or_path.find('/') != std::string::npos || name_or_path.ends_with(".toml"))
        return load_profile_file(name_or_path);
    for (const auto& dir : search_dirs(extra_dirs)) {
        const std::string path = dir + "/" + name_or_path + ".toml";
        if (std::filesystem::is_regular_file(path)) return load_profile_file(path);
    }
    std::string known;
    for (const auto& n : list_profiles(extra_dirs)) known += (known.empty() ? "" : ", ") + n;
    return make_error("unknown display profile '" + name_or_path + "' (known: " + known + ")");
}

std::vector<std::string> list_profiles(const std::vector<std::string>& extra_dirs) {
    std::vector<std::string> names;
    for (const auto& dir : search_dirs(extra_dirs)) {
        std::error_code ec;
        for (const auto& e : std::filesystem::directory_iterator(dir, ec))
            if (e.path().extension() == ".toml") names.push_back(e.path().stem().string());
    }
    std::sort(names.begin(), names.end());
    names.erase(std::unique(names.begin(), names.end()), names.end());
    return names;
}

}  // namespace fovea::drivers::profiles
