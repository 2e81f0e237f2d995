#include "config.hpp"

#include <fstream>
#include <sstream>

#include "fovea/gaze/calibration.hpp"
#include "profiles/display_profile.hpp"

namespace fovea::daemon {
namespace {

const char* kKnownTopLevel[] = {"instance",   "log_level",      "ring", "display",
                                "device",     "recording",      "zmq",  "calibration",
                                "processing", "display_profile"};

Error key_error(const std::string& origin, const std::string& key, const std::string& what) {
    return make_error(origin + ": " + key + ": " + what);
}

template <typename T>
Result<void> read_number(const toml::table& t, const char* key, T& out, double lo, double hi,
                         const std::string& origin, const std::string& prefix) {
    const toml::node* n = t.get(key);
    if (!n) return {};
    std::optional<double> v = n->value<double>();
    if (!v || !(*v >= lo && *v <= hi))
        return key_error(
            origin, prefix + key,
            "must be a number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    out = static_cast<T>(*v);
    return {};
}

Result<DaemonConfig> parse_unchecked(const std::string& text, const std::string& origin) {
    DaemonConfig cfg;
    cfg.source_path = origin;
    toml::table root;
    try {
        root = toml::parse(text, origin);
    } catch (const toml::parse_error& e) {
        const auto& where = e.source().begin;
        return make_error(origin + ":" + std::to_string(where.line) + ":" +
                          std::to_string(where.column) + ": " + std::string(e.description()));
    }
    for (const auto& [key, node] : root) {
        bool known = false;
        for (const char* k : kKnownTopLevel) known = known || key.str() == k;
        if (!known) return key_error(origin, std::string(key.str()), "unknown key");
    }
    if (auto v = root["instance"].value<std::string>()) cfg.instance = *v;
    if (auto v = root["log_level"].value<std::string>()) cfg.log_level = *v;
    if (const toml::table* ring = root["ring"].as_table()) {
        if (auto r = read_number(*ring, "slots", cfg.ring_slots, 16, 1 << 20, origin, "ring."); !r)
            return r.error();
    }
    if (const toml::table* d = root["display"].as_table()) {
        auto& g = cfg.display;
        for (auto r : {read_number(*d, "width_px", g.width_px, 1, 65536, origin, "display."),
                       read_number(*d, "height_px", g.height_px, 1, 65536, origin, "display."),
                       read_number(*d, "width_m", g.width_m, 1e-3, 100, origin, "display."),
                       read_number(*d, "height_m", g.height_m, 1e-3, 100, origin, "display."),
                       read_number(*d, "distance_m", g.distance_m, 1e-3, 100, origin, "display.")})
            if (!r) return r.error();
    }
    if (const toml::node* n = root.get("display_profile")) {
        const std::optional<std::string> name = n->value<std::string>();
        if (!name || name->empty())
            return key_error(origin, "display_profile", "must be a profile name or a path");
        if (root.contains("display"))
            return key_error(origin, "display_profile",
                             "set either display_profile or [display], not both");
        auto profile = drivers::profiles::find_profile(*name);
        if (!profile) return key_error(origin, "display_profile", profile.error().message);
        cfg.display_profile = profile->name;
        cfg.display = profile->display_geometry(0);
        if (profile->kind == drivers::profiles::DisplayKind::kHmd) {
            for (int e = 0; e < 2; ++e) {
                const auto& v = profile->eye(e);
                const double fov[4] = {v.fov_left_deg, v.fov_right_deg, v.fov_up_deg,
                                       v.fov_down_deg};
                for (int k = 0; k < 4; ++k) cfg.eyes.fov_deg[e][k] = static_cast<float>(fov[k]);
            }
            cfg.eyes.ipd_m = static_cast<float>(profile->ipd_m);
        }
    }
    if (const toml::node* p = root.get("processing")) {
        const toml::table* t = p->as_table();
        if (!t) return key_error(origin, "processing", "must be a table");
        for (const auto& [key, node] : *t)
            if (key.str() != "publish" && key.str() != "lookahead_ms")
                return key_error(origin, "processing." + std::string(key.str()), "unknown key");
        if (const toml::node* m = t->get("publish")) {
            const std::optional<std::string> v = m->value<std::string>();
            if (!v || (*v != "live" && *v != "final"))
                return key_error(origin, "processing.publish", "must be \"live\" or \"final\"");
            cfg.publish = *v == "live" ? PublishMode::kLive : PublishMode::kFinal;
        }
        if (auto r =
                read_number(*t, "lookahead_ms", cfg.lookahead_ms, 5, 2000, origin, "processing.");
            !r)
            return r.error();
    }
    if (const toml::node* c = root.get("calibration")) {
        const toml::table* t = c->as_table();
        if (!t) return key_error(origin, "calibration", "must be a table");
        for (const auto& [key, node] : *t) {
            const std::string k(key.str());
            if (k != "user" && k != "dir" && k != "settle_ms" && k != "collect_ms")
                return key_error(origin, "calibration." + k, "unknown key");
        }
        auto& cc = cfg.calibration;
        if (const toml::node* u = t->get("user")) {
            if (!u->is_string()) return key_error(origin, "calibration.user", "must be a string");
            cc.user = *u->value<std::string>();
            if (auto p = gaze::Calibration::user_path(".", cc.user); !p)
                return key_error(origin, "calibration.user", p.error().message);
        }
        if (const toml::node* d = t->get("dir")) {
            if (!d->is_string() || d->value<std::string>()->empty() ||
                d->value<std::string>()->front() != '/')
                return key_error(origin, "calibration.dir", "must be an absolute path");
            cc.dir = *d->value<std::string>();
        }
        for (auto r :
             {read_number(*t, "settle_ms", cc.settle_ms, 0, 5000, origin, "calibration."),
              read_number(*t, "collect_ms", cc.collect_ms, 50, 10000, origin, "calibration.")})
            if (!r) return r.error();
    }
    if (const toml::node* z = root.get("zmq")) {
        auto zc = z->is_table() ? parse_zmq_config(*z->as_table(), origin)
                                : Result<ZmqConfig>(key_error(origin, "zmq", "must be a table"));
        if (!zc) return zc.error();
        cfg.zmq = std::move(zc).value();
    }
    if (const toml::node* devs = root.get("device")) {
        const toml::array* arr = devs->as_array();
        if (!arr) return key_error(origin, "device", "must be an array of tables ([[device]])");
        for (std::size_t i = 0; i < arr->size(); ++i) {
            const toml::table* t = arr->get(i)->as_table();
            if (!t)
                return key_error(origin, "device[" + std::to_string(i) + "]", "must be a table");
            if (t->contains("driver") && !(*t)["driver"].is_string())
                return key_error(origin, "device[" + std::to_string(i) + "].driver",
                                 "must be a string");
            cfg.devices.push_back(*t);
        }
    }
    return cfg;
}

}  // namespace

Result<DaemonConfig> parse_config(const std::string& text, const std::string& origin) {
    auto cfg = parse_unchecked(text, origin);
    // Messages quote the text (toml++ the offending bytes, drivers a value, a key its name);
    // a control character there would break the one line a bad config gets.
    if (!cfg) return make_error(printable(cfg.error().message, 2000), cfg.error().code);
    return cfg;
}

Result<DaemonConfig> load_config(const std::string& path) {
    std::ifstream in(path);
    if (!in) return make_error(path + ": cannot open configuration file");
    std::stringstream ss;
    ss << in.rdbuf();
    return parse_config(ss.str(), path);
}

}  // namespace fovea::daemon
