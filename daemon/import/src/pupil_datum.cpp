#include "fovea/import/pupil_datum.hpp"

#include <cmath>
#include <cstring>
#include <optional>

#include "fovea/msgpack_read.hpp"

namespace fovea::import {
namespace {

using msgpack_read::find;
using msgpack_read::number;
using msgpack_read::text;

constexpr int8_t kPupilExt = 13;  // Pupil's ExtType for a nested serialized datum

// An eye id from a map key: 0/1 as an integer (what Pupil sends) or "0"/"1".
std::optional<int> eye_key(const msgpack::object& k) {
    if (k.type == msgpack::type::POSITIVE_INTEGER && k.via.u64 <= 1)
        return static_cast<int>(k.via.u64);
    if (k.type == msgpack::type::STR && k.via.str.size == 1 &&
        (k.via.str.ptr[0] == '0' || k.via.str.ptr[0] == '1'))
        return k.via.str.ptr[0] - '0';
    return std::nullopt;
}

bool vec3(const msgpack::object* o, std::array<double, 3>& out) {
    if (!o || o->type != msgpack::type::ARRAY || o->via.array.size != 3) return false;
    for (int i = 0; i < 3; ++i) {
        const auto v = number(&o->via.array.ptr[i]);
        if (!v) return false;
        out[static_cast<std::size_t>(i)] = *v;
    }
    return true;
}

// eye_centers_3d / gaze_normals_3d: {0: [x, y, z], 1: [...]}.
void per_eye(const msgpack::object* o, std::array<std::array<double, 3>, 2>& out,
             std::array<bool, 2>& have) {
    if (!o || o->type != msgpack::type::MAP) return;
    for (uint32_t i = 0; i < o->via.map.size; ++i) {
        const auto id = eye_key(o->via.map.ptr[i].key);
        if (id && vec3(&o->via.map.ptr[i].val, out[static_cast<std::size_t>(*id)]))
            have[static_cast<std::size_t>(*id)] = true;
    }
}

void pupil_fields(const msgpack::object& m, PupilDatum& d, int id) {
    if (id < 0 || id > 1) return;
    if (auto v = number(find(m, "diameter_3d"))) d.diameter_mm[static_cast<std::size_t>(id)] = *v;
    if (auto v = number(find(m, "diameter"))) d.diameter_px[static_cast<std::size_t>(id)] = *v;
}

}  // namespace

bool PupilDatum::from_eye(int id) const {
    if (!is_gaze()) return eye_id == id;
    // "gaze.3d.01." / "gaze.2d.0." ...: the digits after the second dot.
    const auto dot = topic.find('.', 5);
    if (dot == std::string::npos) return true;  // plain "gaze": no eye information
    const std::string_view eyes = std::string_view(topic).substr(dot + 1);
    return eyes.find(static_cast<char>('0' + id)) != std::string_view::npos;
}

Result<PupilDatum> decode_pupil_datum(std::string_view bytes) {
    msgpack::object_handle oh;
    if (auto r = msgpack_read::unpack_one(bytes, oh); !r) return r.error();
    const msgpack::object& m = oh.get();
    if (m.type != msgpack::type::MAP) return make_error("not a msgpack map");
    PupilDatum d;
    if (auto t = text(find(m, "topic"))) d.topic = *t;
    if (auto t = text(find(m, "subject"))) d.subject = *t;
    if (auto t = text(find(m, "type"))) d.type = *t;
    if (auto v = number(find(m, "timestamp"))) d.timestamp = *v;
    if (auto v = number(find(m, "confidence"))) d.confidence = *v;
    if (auto v = number(find(m, "duration"))) d.duration_ms = *v;
    if (const msgpack::object* np = find(m, "norm_pos");
        np && np->type == msgpack::type::ARRAY && np->via.array.size == 2) {
        const auto x = number(&np->via.array.ptr[0]), y = number(&np->via.array.ptr[1]);
        if (x && y) {
            d.norm_x = *x;
            d.norm_y = *y;
        }
    }
    if (auto v = number(find(m, "id")); v && (*v == 0 || *v == 1)) d.eye_id = static_cast<int>(*v);
    if (d.eye_id < 0 && (d.topic.starts_with("pupil.0") || d.topic.starts_with("pupil.1")))
        d.eye_id = d.topic[6] - '0';
    if (d.is_pupil()) pupil_fields(m, d, d.eye_id);
    per_eye(find(m, "eye_centers_3d"), d.eye_center_mm, d.has_3d);
    std::array<bool, 2> normals{false, false};
    per_eye(find(m, "gaze_normals_3d"), d.gaze_normal, normals);
    const bool mono_center = find(m, "eye_center_3d") != nullptr;
    if (mono_center && d.is_gaze()) {  // monocular 3d gaze: the topic says which eye
        const int id = d.from_eye(0) ? 0 : 1;
        const auto k = static_cast<std::size_t>(id);
        d.has_3d[k] = vec3(find(m, "eye_center_3d"), d.eye_center_mm[k]) &&
                      vec3(find(m, "gaze_normal_3d"), d.gaze_normal[k]);
    } else {
        for (std::size_t k = 0; k < 2; ++k) d.has_3d[k] = d.has_3d[k] && normals[k];
    }
    vec3(find(m, "gaze_point_3d"), d.gaze_point_mm);
    if (const msgpack::object* base = find(m, "base_data");
        base && base->type == msgpack::type::ARRAY) {
        for (uint32_t i = 0; i < base->via.array.size; ++i) {
            const msgpack::object& b = base->via.array.ptr[i];
            msgpack::object_handle inner;
            const msgpack::object* p = &b;  // older recordings store the map itself
            if (b.type == msgpack::type::EXT && b.via.ext.type() == kPupilExt) {
                if (!msgpack_read::unpack_one(std::string_view(b.via.ext.data(), b.via.ext.size),
                                              inner))
                    continue;
                p = &inner.get();
            }
            if (p->type != msgpack::type::MAP) continue;
            const auto id = number(find(*p, "id"));
            if (!id || !(*id == 0 || *id == 1)) continue;
            pupil_fields(*p, d, static_cast<int>(*id));
            ++d.base_data;
        }
    }
    return d;
}

bool pupil_sample(const PupilDatum& d, double min_confidence, gaze::RawSample& out) {
    if (!(d.is_gaze() || d.is_pupil()) || !std::isfinite(d.timestamp)) return false;
    out = gaze::RawSample{};
    const double t_ns = d.timestamp * 1e9;
    out.device_ticks = t_ns > 0 && t_ns < 9.2e18 ? static_cast<uint64_t>(std::llround(t_ns)) : 0;
    const bool good =
        std::isfinite(d.norm_x) && std::isfinite(d.norm_y) && d.confidence >= min_confidence;
    for (int id = 0; id < 2; ++id) {
        gaze::EyeSample& e = id == 0 ? out.right : out.left;  // eye0 is the right eye
        if (!d.from_eye(id)) continue;
        const double mm = d.diameter_mm[static_cast<std::size_t>(id)];
        if (std::isfinite(mm) && mm > 0) e.pupil_mm = mm;
        if (!good) continue;
        e.x = d.norm_x;
        e.y = 1.0 - d.norm_y;  // Pupil's origin is bottom-left
        e.valid = true;
    }
    return true;
}

}  // namespace fovea::import
