#include "gltf_viewer/scene_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include <toml++/toml.h>

namespace gltfv {
namespace {

namespace fs = std::filesystem;

struct Reader {
    const std::string& file;
    std::string error;

    bool fail(const std::string& what) {
        if (error.empty()) error = file + ": " + what;
        return false;
    }
    bool number(const toml::table& t, const char* key, float& out, double lo, double hi,
                const std::string& where) {
        const toml::node* n = t.get(key);
        if (!n) return true;
        const auto v = n->value<double>();
        if (!v || !std::isfinite(*v) || *v < lo || *v > hi)
            return fail(where + key + " must be a number in [" + std::to_string(lo) + ", " +
                        std::to_string(hi) + "]");
        out = float(*v);
        return true;
    }
    bool vec3(const toml::table& t, const char* key, Vec3& out, const std::string& where) {
        const toml::node* n = t.get(key);
        if (!n) return true;
        const toml::array* a = n->as_array();
        if (!a || a->size() != 3) return fail(where + key + " must be an array of 3 numbers");
        for (size_t i = 0; i < 3; ++i) {
            const auto v = (*a)[i].value<double>();
            if (!v || !std::isfinite(*v)) return fail(where + key + " must hold 3 finite numbers");
            out[i] = float(*v);
        }
        return true;
    }
};

}  // namespace

Mat4 ModelDesc::placement() const {
    return multiply(trs(translation, {0, 0, 0, 1}, {scale, scale, scale}),
                    rotation_xyz_deg(rotation_deg));
}

CameraKey SceneFile::camera_at(double t) const {
    if (camera.empty()) return {};
    if (t <= camera.front().t_s) return camera.front();
    for (size_t i = 0; i + 1 < camera.size(); ++i) {
        const CameraKey &a = camera[i], &b = camera[i + 1];
        if (t > b.t_s) continue;
        double u = (t - a.t_s) / std::max(b.t_s - a.t_s, 1e-9);
        u = u * u * (3.0 - 2.0 * u);
        CameraKey k;
        k.t_s = t;
        k.position = lerp(a.position, b.position, float(u));
        k.target = lerp(a.target, b.target, float(u));
        return k;
    }
    return camera.back();
}

std::string load_scene_file(const std::string& path, const std::string& data_dir_override,
                            SceneFile& out) {
    out = SceneFile{};
    out.path = path;
    Reader r{path, {}};
    toml::table root;
    try {
        root = toml::parse_file(path);
    } catch (const toml::parse_error& e) {
        return path + ":" + std::to_string(e.source().begin.line) + ": " +
               std::string(e.description());
    }
    const fs::path base = fs::path(path).parent_path();
    std::string data_dir = base.string();
    if (const auto d = root["data_dir"].value<std::string>()) data_dir = (base / *d).string();
    if (const char* env = std::getenv("FOVEA_SHARED_DATA_DIR"); env && *env) data_dir = env;
    if (!data_dir_override.empty()) data_dir = data_dir_override;

    if (const toml::table* d = root["display"].as_table()) {
        float w = float(out.width), h = float(out.height);
        r.number(*d, "width", w, 16, 16384, "[display] ");
        r.number(*d, "height", h, 16, 16384, "[display] ");
        out.width = uint32_t(w);
        out.height = uint32_t(h);
        r.number(*d, "fov_h_deg", out.fov_h_deg, 1, 170, "[display] ");
        r.number(*d, "fov_v_deg", out.fov_v_deg, 1, 170, "[display] ");
    }
    if (const toml::table* e = root["environment"].as_table()) {
        r.vec3(*e, "sky", out.sky, "[environment] ");
        r.vec3(*e, "horizon", out.horizon, "[environment] ");
        r.vec3(*e, "ground", out.ground, "[environment] ");
        r.number(*e, "intensity", out.env_intensity, 0, 1e4, "[environment] ");
    }
    if (const toml::array* lights = root["light"].as_array()) {
        for (size_t i = 0; i < lights->size(); ++i) {
            const toml::table* t = (*lights)[i].as_table();
            const std::string where = "[[light]] #" + std::to_string(i + 1) + " ";
            if (!t) return path + ": " + where + "must be a table";
            LightDesc l;
            const std::string type = (*t)["type"].value_or(std::string("directional"));
            if (type != "directional" && type != "point")
                return path + ": " + where + "type must be \"directional\" or \"point\"";
            l.directional = type == "directional";
            r.vec3(*t, "direction", l.direction, where);
            r.vec3(*t, "position", l.position, where);
            r.vec3(*t, "color", l.color, where);
            r.number(*t, "intensity", l.intensity, 0, 1e6, where);
            if (l.directional && length(l.direction) <= 0.f)
                return path + ": " + where + "direction must not be zero";
            out.lights.push_back(l);
        }
    }
    if (out.lights.size() > 8) return path + ": at most 8 lights";
    if (const toml::table* c = root["camera"].as_table()) {
        r.number(*c, "near", out.near_z, 1e-5, 1e3, "[camera] ");
        r.number(*c, "far", out.far_z, 1e-3, 1e7, "[camera] ");
        if (const toml::array* keys = (*c)["key"].as_array())
            for (size_t i = 0; i < keys->size(); ++i) {
                const toml::table* t = (*keys)[i].as_table();
                const std::string where = "[[camera.key]] #" + std::to_string(i + 1) + " ";
                if (!t) return path + ": " + where + "must be a table";
                CameraKey k;
                float ts = 0.f;
                r.number(*t, "t", ts, 0, 1e6, where);
                k.t_s = ts;
                r.vec3(*t, "position", k.position, where);
                r.vec3(*t, "target", k.target, where);
                if (length(k.target - k.position) <= 0.f)
                    return path + ": " + where + "target must differ from position";
                if (!out.camera.empty() && k.t_s <= out.camera.back().t_s)
                    return path + ": " + where + "t must increase from key to key";
                out.camera.push_back(k);
            }
    }
    if (!(out.far_z > out.near_z)) return path + ": [camera] far must exceed near";
    if (out.camera.empty()) out.camera.push_back({0.0, {0.f, 0.5f, 2.f}, {0.f, 0.3f, 0.f}});
    const toml::array* models = root["model"].as_array();
    if (!models || models->empty()) return path + ": needs at least one [[model]] with a file";
    for (size_t i = 0; i < models->size(); ++i) {
        const toml::table* t = (*models)[i].as_table();
        const std::string where = "[[model]] #" + std::to_string(i + 1) + " ";
        if (!t) return path + ": " + where + "must be a table";
        ModelDesc m;
        const auto file = (*t)["file"].value<std::string>();
        if (!file || file->empty()) return path + ": " + where + "needs file = \"...\"";
        m.file = (fs::path(data_dir) / *file).lexically_normal().string();
        r.number(*t, "fit", m.fit, 0, 1e6, where);
        r.vec3(*t, "translation", m.translation, where);
        r.vec3(*t, "rotation_deg", m.rotation_deg, where);
        r.number(*t, "scale", m.scale, 1e-9, 1e9, where);
        out.models.push_back(m);
    }
    return r.error;
}

}  // namespace gltfv
