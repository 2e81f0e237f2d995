// Display profiles as TOML data: parsing, validation and the search path.
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

constexpr double kRadToDeg = 57.29577951308232;
// The loader checks a file's declared pixels_per_degree against its geometry to this tolerance.
constexpr double kPpdTolerance = 0.02;

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
            return make_error(where +
                              ": fov_{left,right,up,down}_deg are required half-angles "
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
        if (auto ppd = t["pixels_per_degree"].value<double>())
            view.insert("pixels_per_degree", *ppd);
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
    std::error_code ec;
    if (std::filesystem::is_directory(FOVEA_PROFILES_INSTALL_DIR, ec))
        return FOVEA_PROFILES_INSTALL_DIR;
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
        std::error_code ec;  // a name past NAME_MAX is an unknown profile, not an exception
        if (std::filesystem::is_regular_file(path, ec)) return load_profile_file(path);
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
