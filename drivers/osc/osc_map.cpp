#include "osc/osc_map.hpp"

#include <lo/lo.h>

#include <cmath>
#include <cstdint>
#include <cstring>

namespace fovea::drivers::osc {
namespace {

constexpr double kDegToRad = 0.017453292519943295;

struct RoleName {
    const char* key;
    Role role;
};
constexpr RoleName kRoles[] = {
    {"left_x", Role::kLeftX},
    {"left_y", Role::kLeftY},
    {"right_x", Role::kRightX},
    {"right_y", Role::kRightY},
    {"left_right_vec", Role::kLeftRightVec},
    {"eyes_closed", Role::kEyesClosed},
    {"left_lid", Role::kLeftLid},
    {"right_lid", Role::kRightLid},
    {"pupil_dilation", Role::kPupilDilation},
};

bool is_gaze(Role r) { return r <= Role::kLeftRightVec; }

Result<void> pair(const toml::table& t, const char* key, double& a, double& b) {
    const toml::node* n = t.get(key);
    if (!n) return {};
    const toml::array* arr = n->as_array();
    if (!arr || arr->size() != 2 || !(*arr)[0].value<double>() || !(*arr)[1].value<double>())
        return make_error(std::string("osc: ") + key + " must be [a, b] (two numbers)");
    a = *(*arr)[0].value<double>();
    b = *(*arr)[1].value<double>();
    return {};
}

Result<void> number(const toml::table& t, const char* key, double& out) {
    const toml::node* n = t.get(key);
    if (!n) return {};
    const auto v = n->value<double>();
    if (!v || !std::isfinite(*v))
        return make_error(std::string("osc: ") + key + " must be a number");
    out = *v;
    return {};
}

}  // namespace

Result<AddressMap> parse_address_map(const toml::table& t) {
    AddressMap m;
    m.preset = t["preset"].value_or(std::string("vrchat"));
    if (m.preset == "vrchat") {
        m.addresses = {{"/tracking/eye/LeftRightVec", Role::kLeftRightVec},
                       {"/tracking/eye/EyesClosedAmount", Role::kEyesClosed}};
    } else if (m.preset == "vrcft-v2") {
        const std::string p = "/avatar/parameters/v2/";
        m.addresses = {{p + "EyeLeftX", Role::kLeftX},
                       {p + "EyeLeftY", Role::kLeftY},
                       {p + "EyeRightX", Role::kRightX},
                       {p + "EyeRightY", Role::kRightY},
                       {p + "EyeLidLeft", Role::kLeftLid},
                       {p + "EyeLidRight", Role::kRightLid},
                       {p + "PupilDilation", Role::kPupilDilation}};
    } else if (m.preset == "custom") {
        const toml::table* a = t["addresses"].as_table();
        if (!a) return make_error("osc: preset \"custom\" needs an [addresses] table");
        for (const auto& [key, node] : *a) {
            const auto addr = node.value<std::string>();
            const RoleName* role = nullptr;
            for (const auto& r : kRoles)
                if (key.str() == r.key) role = &r;
            if (!role)
                return make_error("osc: addresses." + std::string(key.str()) +
                                  ": unknown role (left_x, left_y, right_x, right_y, "
                                  "left_right_vec, eyes_closed, left_lid, right_lid, "
                                  "pupil_dilation)");
            if (!addr || addr->empty() || addr->front() != '/')
                return make_error("osc: addresses." + std::string(key.str()) +
                                  " must be an OSC address starting with '/'");
            m.addresses.emplace_back(*addr, role->role);
        }
    } else {
        return make_error("osc: preset must be \"vrchat\", \"vrcft-v2\" or \"custom\", got '" +
                          m.preset + "'");
    }
    if (auto r = pair(t, "range", m.range_min, m.range_max); !r) return r.error();
    if (auto r = pair(t, "fov_deg", m.hfov_deg, m.vfov_deg); !r) return r.error();
    if (auto r = number(t, "angle_deg", m.angle_deg); !r) return r.error();
    if (auto r = number(t, "closed_above", m.closed_above); !r) return r.error();
    if (auto r = number(t, "lid_below", m.lid_below); !r) return r.error();
    if (!(m.range_max > m.range_min)) return make_error("osc: range must be [min, max], min < max");
    if (!(m.angle_deg > 0 && m.angle_deg < 89)) return make_error("osc: angle_deg must be 0..89");
    if (!(m.hfov_deg > 0 && m.hfov_deg < 179 && m.vfov_deg > 0 && m.vfov_deg < 179))
        return make_error("osc: fov_deg must be [h, v], each 0..179");
    bool has_gaze = false, scalar[4] = {false, false, false, false};
    for (const auto& [addr, role] : m.addresses) {
        has_gaze |= role == Role::kLeftRightVec;
        if (role <= Role::kRightY) scalar[static_cast<int>(role)] = true;
    }
    if (!has_gaze && !(scalar[0] && scalar[1]) && !(scalar[2] && scalar[3]))
        return make_error(
            "osc: the address map has no gaze (left_right_vec, or x and y of an eye)");
    return m;
}

FrameAssembler::FrameAssembler(AddressMap map) : map_(std::move(map)) {
    for (const auto& [addr, role] : map_.addresses) gaze_roles_.push_back(is_gaze(role));
    updated_.assign(map_.addresses.size(), false);
}

void FrameAssembler::to_display(double yaw_tan, double pitch_tan, gaze::EyeSample& e) const {
    // A plane filling the field of view: the chain's normalized display, y down.
    e.x = 0.5 + yaw_tan / (2 * std::tan(map_.hfov_deg * 0.5 * kDegToRad));
    e.y = 0.5 - pitch_tan / (2 * std::tan(map_.vfov_deg * 0.5 * kDegToRad));
    e.valid = std::isfinite(e.x) && std::isfinite(e.y);
}

bool FrameAssembler::message(std::string_view address, const std::vector<double>& values,
                             std::optional<gaze::RawSample>& out) {
    out.reset();
    std::size_t i = 0;
    while (i < map_.addresses.size() && map_.addresses[i].first != address) ++i;
    if (i == map_.addresses.size()) return false;
    const Role role = map_.addresses[i].second;
    const std::size_t need = role == Role::kLeftRightVec ? 6 : 1;
    if (values.size() < need) return false;
    for (std::size_t k = 0; k < need; ++k)
        if (!std::isfinite(values[k])) return false;
    switch (role) {
        case Role::kLeftRightVec:
            for (int k = 0; k < 6; ++k) vec_[k] = values[static_cast<std::size_t>(k)];
            break;
        case Role::kEyesClosed: closed_ = values[0]; break;
        case Role::kLeftLid: lid_[0] = values[0]; break;
        case Role::kRightLid: lid_[1] = values[0]; break;
        case Role::kPupilDilation: dilation_ = values[0]; break;
        default: v_[static_cast<int>(role)] = values[0]; break;
    }
    updated_[i] = true;
    for (std::size_t k = 0; k < updated_.size(); ++k)
        if (gaze_roles_[k] && !updated_[k]) return true;
    if (!gaze_roles_[i]) return true;  // a lid update does not make a new gaze sample
    // Every gaze address is fresh: one sample.
    updated_.assign(updated_.size(), false);
    gaze::RawSample s;
    bool vec = false, eye[2] = {false, false};
    for (const auto& [addr, r] : map_.addresses) {
        vec |= r == Role::kLeftRightVec;
        if (r == Role::kLeftX || r == Role::kLeftY) eye[0] = true;
        if (r == Role::kRightX || r == Role::kRightY) eye[1] = true;
    }
    const double mid = 0.5 * (map_.range_min + map_.range_max);
    const double half = 0.5 * (map_.range_max - map_.range_min);
    const auto angle_tan = [&](double v) {
        return std::tan((v - mid) / half * map_.angle_deg * kDegToRad);
    };
    for (int k = 0; k < 2; ++k) {
        gaze::EyeSample& e = k == 0 ? s.left : s.right;
        if (vec) {
            const double* d = vec_ + 3 * k;
            if (d[2] > 0) to_display(d[0] / d[2], d[1] / d[2], e);
        } else if (eye[k]) {
            to_display(angle_tan(v_[2 * k]), angle_tan(v_[2 * k + 1]), e);
        }
        const bool closed = closed_ >= map_.closed_above || lid_[k] <= map_.lid_below;
        if (closed) e = gaze::EyeSample{};
    }
    out = s;
    return true;
}

void arguments_as_numbers(const char* types, lo_arg* const* argv, int argc,
                          std::vector<double>& out) {
    auto copy = [](const lo_arg* a, auto v) {
        std::memcpy(&v, a, sizeof v);
        return static_cast<double>(v);
    };
    out.clear();
    for (int i = 0; i < argc; ++i) {
        const lo_arg* a = argv[i];
        switch (types[i]) {
            case 'f': out.push_back(copy(a, float{})); break;
            case 'd': out.push_back(copy(a, double{})); break;
            case 'i': out.push_back(copy(a, int32_t{})); break;
            case 'h': out.push_back(copy(a, int64_t{})); break;
            case 'T': out.push_back(1.0); break;
            case 'F': out.push_back(0.0); break;
            default: out.push_back(gaze::kNaN); break;
        }
    }
}

}  // namespace fovea::drivers::osc
