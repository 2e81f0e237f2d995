#include "calibration_commands.hpp"

#include <time.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "daemon.hpp"
#include "fovea/gaze/calibration.hpp"
#include "fovea/gaze/target_dwell.hpp"
#include "fovea/json_integer.hpp"
#include "paths.hpp"

namespace fovea::daemon {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr std::size_t kMaxPoints = 64;
constexpr std::size_t kMaxSamplesPerPoint = 100'000;
// A live point ends when the device sends a sample past its window; a device that went quiet
// ends it this long after the window instead.
constexpr int64_t kStallNs = 500'000'000;

std::shared_ptr<spdlog::logger> log() {
    auto l = spdlog::get("daemon");
    return l ? l : spdlog::default_logger();
}

int64_t now_ns() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

[[noreturn]] void fail(const std::string& what) { throw std::runtime_error(what); }

double number(const json& req, const char* key, const std::string& cmd) {
    const auto it = req.find(key);
    if (it == req.end() || !it->is_number() || !std::isfinite(it->get<double>()))
        fail(cmd + ": \"" + key + "\" must be a finite number");
    return it->get<double>();
}

bool flag(const json& req, const char* key, bool fallback, const std::string& cmd) {
    const auto it = req.find(key);
    if (it == req.end()) return fallback;
    if (!it->is_boolean()) fail(cmd + ": \"" + key + "\" must be true or false");
    return it->get<bool>();
}

std::string user_arg(const json& req, const std::string& cmd) {
    const auto it = req.find("user");
    if (it == req.end() || !it->is_string()) fail(cmd + " needs \"user\": a name like \"ana\"");
    return it->get<std::string>();
}

// A target in normalized display coordinates, from {"x", "y"} or {"deg_x", "deg_y"}.
std::pair<double, double> target_arg(const json& req, const gaze::DisplayGeometry& display,
                                     const std::string& cmd) {
    double x = 0, y = 0;
    if (req.contains("x") || req.contains("y")) {
        x = number(req, "x", cmd);
        y = number(req, "y", cmd);
    } else if (req.contains("deg_x") || req.contains("deg_y")) {
        display.to_normalized(number(req, "deg_x", cmd), number(req, "deg_y", cmd), x, y);
    } else {
        fail(cmd +
             " needs a target: {\"x\", \"y\"} in normalized display coordinates (0..1) or "
             "{\"deg_x\", \"deg_y\"} in degrees from the display centre");
    }
    if (!(x >= 0 && x <= 1 && y >= 0 && y <= 1)) fail(cmd + ": the target must be on the display");
    return {x, y};
}

gaze::EyeSample eye_arg(const json& e, std::size_t i, const char* side) {
    gaze::EyeSample out;
    if (e.is_null()) return out;  // invalid eye
    if (!e.is_array() || e.size() != 2 || !e[0].is_number() || !e[1].is_number()) {
        fail("calibrate.point: samples[" + std::to_string(i) + "]." + side +
             " must be [x, y] (raw tracker units) or null");
    }
    out.x = e[0].get<double>();
    out.y = e[1].get<double>();
    out.valid = true;  // non-finite values are skipped and counted by the Calibration
    return out;
}

json eye_json(const gaze::EyeQuality& q) {
    if (q.samples_used == 0 && !q.fitted) return nullptr;
    json j = {{"accuracy_deg", q.accuracy_deg},
              {"precision_rms_deg", q.precision_rms_deg},
              {"precision_sd_deg", q.precision_sd_deg},
              {"samples", q.samples_used}};
    if (q.fitted) {
        j["rejected"] = q.samples_rejected;
        json checks = json::array();
        for (const gaze::TargetCheck& c : q.target_checks) {
            checks.push_back({{"x", c.x},
                              {"y", c.y},
                              {"residual_deg", c.residual_deg},
                              {"expected_deg", c.expected_deg},
                              {"samples", c.samples},
                              {"left_out", c.left_out}});
        }
        j["target_checks"] = checks;
    }
    return j;
}

json quality_json(const gaze::CalibrationQuality& q) {
    return {{"targets", q.targets}, {"left", eye_json(q.left)}, {"right", eye_json(q.right)}};
}

void write_atomically(const std::string& path, const std::string& text) {
    const std::string tmp = path + ".tmp";
    {
        std::ofstream f(tmp, std::ios::trunc);
        if (!f) fail("cannot write " + tmp);
        f << text << '\n';
        if (!f.flush()) fail("write failed: " + tmp);
    }
    // Rename so a crash never leaves a half-written calibration.
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) fail("cannot rename " + tmp + " to " + path + ": " + ec.message());
}

struct Point {
    double x = 0, y = 0;
    bool live = false;
    bool done = false;
    std::size_t samples = 0, invalid = 0, settle_discarded = 0;
    int64_t collect_from_ns = 0, collect_until_ns = 0;  // live points
    // Live points: what arrived in the window, fitted from once it ends (gaze/target_dwell.hpp).
    std::vector<gaze::TargetSample> collected;
    gaze::TargetDwell dwell;
};

struct Session {
    std::string user;
    uint32_t device = 0;
    bool left = true, right = true;
    gaze::Calibration calibration;
    std::vector<Point> points;
};

struct Active {
    std::string user;
    uint32_t device = 0;
    gaze::Calibration calibration;
};

class CalibrationService {
public:
    explicit CalibrationService(Daemon& d)
        : daemon_(d), display_(d.config().display), settings_(d.config().calibration) {
        dir_ = settings_.dir.empty() ? state_dir() + "/calibrations" : settings_.dir;
    }

    void load_configured_user() {
        if (settings_.user.empty()) return;
        try {
            apply_stored(settings_.user, std::nullopt);
            log()->info("calibration: applied {}'s calibration from {}", settings_.user, dir_);
        } catch (const std::exception& e) {
            load_error_ = e.what();
            log()->warn("calibration: {}; running uncalibrated", load_error_);
        }
    }

    void on_raw(const gaze::RawSample& raw) {
        if (!session_ || session_->points.empty()) return;
        Point& p = session_->points.back();
        if (p.done || raw.device_id != session_->device) return;
        const int64_t t = raw.t_receive_ns;
        if (t < p.collect_from_ns) {
            ++p.settle_discarded;
            return;
        }
        if (t >= p.collect_until_ns) {
            end_live_point(p);
            return;
        }
        if (p.collected.size() < kMaxSamplesPerPoint)
            p.collected.push_back({t, raw.left, raw.right});
    }

    json start(const json& req) {
        const std::string user = user_arg(req, "calibrate.start");
        if (auto p = gaze::Calibration::user_path(dir_, user); !p) fail(p.error().message);
        Session s;
        s.user = user;
        s.calibration = gaze::Calibration(display_);
        s.device = device_arg(req, "calibrate.start");
        const std::string eyes = req.value("eyes", std::string("both"));
        if (eyes != "both" && eyes != "left" && eyes != "right")
            fail("calibrate.start: \"eyes\" must be \"both\", \"left\" or \"right\"");
        s.left = eyes != "right";
        s.right = eyes != "left";
        s.calibration.begin();
        const bool restarted = session_.has_value();
        session_ = std::move(s);
        log()->info("calibration: session for {} on device {} ({} eyes)", user, session_->device,
                    eyes);
        return {{"user", user},
                {"device", session_->device},
                {"eyes", eyes},
                {"restarted", restarted},
                {"settle_ms", settings_.settle_ms},
                {"collect_ms", settings_.collect_ms}};
    }

    json point(const json& req) {
        Session& s = need_session("calibrate.point");
        end_stalled_point();
        if (!s.points.empty() && !s.points.back().done) {
            fail("calibrate.point: point " + std::to_string(s.points.size() - 1) +
                 " is still collecting (" + std::to_string(remaining_ms(s.points.back())) +
                 " ms left); poll calibrate.status");
        }
        if (s.points.size() >= kMaxPoints)
            fail("calibrate.point: at most " + std::to_string(kMaxPoints) + " points per session");
        const auto [x, y] = target_arg(req, display_, "calibrate.point");
        Point p;
        p.x = x;
        p.y = y;
        p.live = !req.contains("samples");
        json reply = {{"point", s.points.size()}, {"x", x}, {"y", y}};
        if (!p.live) {
            const json& samples = req["samples"];
            if (!samples.is_array() || samples.size() > kMaxSamplesPerPoint)
                fail(
                    "calibrate.point: \"samples\" must be an array of {\"left\": [x, y], "
                    "\"right\": "
                    "[x, y]} (at most " +
                    std::to_string(kMaxSamplesPerPoint) + ")");
            std::vector<std::pair<gaze::EyeSample, gaze::EyeSample>> parsed;
            for (std::size_t i = 0; i < samples.size(); ++i) {
                const json& e = samples[i];
                if (!e.is_object())
                    fail("calibrate.point: samples[" + std::to_string(i) + "] must be an object");
                parsed.emplace_back(eye_arg(e.value("left", json()), i, "left"),
                                    eye_arg(e.value("right", json()), i, "right"));
            }
            // Parsed in full before any is added: a bad request leaves the session unchanged.
            for (const auto& [l, r] : parsed) add(p, l, r);
            p.done = true;
            reply["samples"] = p.samples;
            reply["invalid"] = p.invalid;
        } else {
            const int64_t now = now_ns();
            p.collect_from_ns = now + static_cast<int64_t>(settings_.settle_ms * 1e6);
            p.collect_until_ns =
                p.collect_from_ns + static_cast<int64_t>(settings_.collect_ms * 1e6);
            const int following = daemon_.show_target(true, x, y);
            reply["collecting"] = true;
            reply["ready_in_ms"] = settings_.settle_ms + settings_.collect_ms;
            reply["devices_following"] = following;
        }
        s.points.push_back(p);
        return reply;
    }

    json finish(const json& req) {
        Session& s = need_session("calibrate.finish");
        end_stalled_point();
        if (!s.points.empty() && !s.points.back().done)
            fail("calibrate.finish: the last point is still collecting (" +
                 std::to_string(remaining_ms(s.points.back())) + " ms left)");
        const bool store = flag(req, "store", true, "calibrate.finish");
        const bool apply = flag(req, "apply", true, "calibrate.finish");
        const gaze::CalibrationQuality before = s.calibration.evaluate_unmapped();
        auto after = s.calibration.fit();
        if (!after)
            fail("calibrate.finish: " + after.error().message + " (the session stays open)");
        json reply = {{"user", s.user},
                      {"device", s.device},
                      {"before", quality_json(before)},
                      {"after", quality_json(*after)},
                      {"stored", nullptr},
                      {"applied", apply}};
        if (store) reply["stored"] = save(s);
        if (apply) {
            daemon_.set_calibration(s.device, &s.calibration);
            active_ = Active{s.user, s.device, s.calibration};
            load_error_.clear();
        }
        daemon_.show_target(false, 0, 0);
        log()->info("calibration: {} fitted on {} targets: {}", s.user, after->targets,
                    reply["after"].dump());
        session_.reset();
        return reply;
    }

    json cancel() {
        if (!session_) fail("calibrate.cancel: no calibration session");
        session_.reset();
        daemon_.show_target(false, 0, 0);
        return {{"cancelled", true}};
    }

    json apply(const json& req) {
        const std::string user = user_arg(req, "calibrate.apply");
        std::optional<uint32_t> device;
        if (req.contains("device")) device = device_arg(req, "calibrate.apply");
        apply_stored(user, device);
        load_error_.clear();
        return active_json();
    }

    json clear() {
        const bool was = active_.has_value();
        if (active_) daemon_.set_calibration(active_->device, nullptr);
        active_.reset();
        return {{"cleared", was}};
    }

    json target(const json& req) {
        if (flag(req, "hide", false, "calibrate.target"))
            return {{"shown", false}, {"devices_following", daemon_.show_target(false, 0, 0)}};
        const auto [x, y] = target_arg(req, display_, "calibrate.target");
        double dx = 0, dy = 0;
        display_.to_degrees(x, y, dx, dy);
        return {{"shown", true}, {"x", x},
                {"y", y},        {"deg_x", dx},
                {"deg_y", dy},   {"devices_following", daemon_.show_target(true, x, y)}};
    }

    json list() const {
        json users = json::array();
        std::error_code ec;
        for (const auto& entry : fs::directory_iterator(dir_, ec)) {
            if (entry.path().extension() != ".json") continue;
            json u = {{"user", entry.path().stem().string()}};
            auto c = gaze::Calibration::load(entry.path().string(), display_);
            if (c) {
                const auto& q = c->quality();
                u["targets"] = q.targets;
                u["left"] = eye_json(q.left);
                u["right"] = eye_json(q.right);
            } else {
                u["error"] = c.error().message;
            }
            users.push_back(u);
        }
        std::sort(users.begin(), users.end(),
                  [](const json& a, const json& b) { return a["user"] < b["user"]; });
        return {{"dir", dir_},
                {"calibrations", users},
                {"active", active_ ? json(active_->user) : json(nullptr)}};
    }

    json status() {
        end_stalled_point();
        json j = {{"dir", dir_}, {"active", active_json()}};
        if (!load_error_.empty()) j["error"] = load_error_;
        if (!session_) {
            j["session"] = nullptr;
            return j;
        }
        json points = json::array();
        for (const Point& p : session_->points) {
            json pj = {{"x", p.x},
                       {"y", p.y},
                       {"done", p.done},
                       {"samples", p.samples},
                       {"invalid", p.invalid}};
            if (p.live) {
                pj["settle_discarded"] = p.settle_discarded;
                if (!p.done) pj["remaining_ms"] = remaining_ms(p);
                if (p.done) {
                    pj["lost"] = p.dwell.lost;
                    pj["blink_edges"] = p.dwell.lid;
                    pj["not_settled"] = p.dwell.unsettled;
                    pj["dwell_ms"] = p.dwell.dwell_s * 1000;
                }
            }
            points.push_back(pj);
        }
        const bool collecting = !session_->points.empty() && !session_->points.back().done;
        j["session"] = {{"user", session_->user},
                        {"device", session_->device},
                        {"points", points},
                        {"collecting", collecting}};
        return j;
    }

private:
    Session& need_session(const std::string& cmd) {
        if (!session_) fail(cmd + ": no calibration session (calibrate.start first)");
        return *session_;
    }

    uint32_t device_arg(const json& req, const std::string& cmd) const {
        const auto it = req.find("device");
        if (it == req.end()) return 0;
        const auto device = json_integer(*it, 0, static_cast<int64_t>(daemon_.device_count()) - 1);
        if (!device)
            fail(cmd + ": \"device\" must be a device index below " +
                 std::to_string(daemon_.device_count()));
        return static_cast<uint32_t>(*device);
    }

    // One raw sample for the current point, restricted to the session's eyes.
    void add(Point& p, gaze::EyeSample left, gaze::EyeSample right) {
        if (!session_->left) left = gaze::EyeSample{};
        if (!session_->right) right = gaze::EyeSample{};
        const std::size_t before = session_->calibration.samples();
        session_->calibration.add_sample(p.x, p.y, left, right);
        (session_->calibration.samples() > before ? p.samples : p.invalid)++;
    }

    void end_stalled_point() {
        if (!session_ || session_->points.empty()) return;
        Point& p = session_->points.back();
        if (!p.done && p.live && now_ns() > p.collect_until_ns + kStallNs) end_live_point(p);
    }

    // Only the samples with the eyes settled on the target go into the fit: not those before
    // they arrived, nor a blink's lid artefacts. A point without a fixation adds nothing, and the
    // log and calibrate.status say why.
    void end_live_point(Point& p) {
        p.done = true;
        std::vector<gaze::TargetSample> in_degrees = p.collected;
        for (auto& s : in_degrees) {
            for (gaze::EyeSample* e : {&s.left, &s.right}) {
                double x, y;
                display_.to_degrees(e->x, e->y, x, y);
                e->x = x;
                e->y = y;
            }
        }
        // Where the eyes dwelt at the point before, if it kept samples: they may still be there
        // when this collection starts. (After a point that kept none, where they were is not
        // known.)
        const gaze::TargetSample* previous = nullptr;
        const auto& points = session_->points;
        if (points.size() >= 2 && &points.back() == &p) {
            const Point& before = points[points.size() - 2];
            if (before.live && !before.dwell.keep.empty()) previous = &before.dwell.at;
        }
        p.dwell = gaze::target_dwell(in_degrees, session_->left, session_->right, {}, previous);
        for (const std::size_t i : p.dwell.keep) add(p, p.collected[i].left, p.collected[i].right);
        if (p.dwell.keep.empty()) {
            log()->warn(
                "calibration: point {} ({:.3f}, {:.3f}) adds no samples: no fixation of {} ms on "
                "it ({} samples, {} lost, {} at a blink's edges, {} moving; the last dwell {:.0f} "
                "ms)",
                session_->points.size() - 1, p.x, p.y, gaze::TargetDwellRules{}.min_dwell_s * 1000,
                p.collected.size(), p.dwell.lost, p.dwell.lid, p.dwell.unsettled,
                p.dwell.dwell_s * 1000);
        }
        p.collected = {};
    }

    int64_t remaining_ms(const Point& p) const {
        return std::max<int64_t>(0, (p.collect_until_ns - now_ns()) / 1'000'000);
    }

    std::string save(const Session& s) const {
        auto path = gaze::Calibration::user_path(dir_, s.user);
        if (!path) fail(path.error().message);
        std::error_code ec;
        fs::create_directories(dir_, ec);
        if (ec) fail("cannot create " + dir_ + ": " + ec.message());
        json j = json::parse(s.calibration.to_json());
        j["user"] = s.user;
        j["device"] = s.device;
        j["created_unix"] = static_cast<int64_t>(::time(nullptr));
        write_atomically(*path, j.dump(2));
        return *path;
    }

    void apply_stored(const std::string& user, std::optional<uint32_t> device) {
        auto path = gaze::Calibration::user_path(dir_, user);
        if (!path) fail(path.error().message);
        std::ifstream in(*path);
        if (!in) fail("no stored calibration for '" + user + "' (" + *path + ")");
        std::stringstream text;
        text << in.rdbuf();
        auto c = gaze::Calibration::from_json(text.str(), display_);
        if (!c) fail(*path + ": " + c.error().message);
        if (!device) {
            const json j = json::parse(text.str(), nullptr, false);
            const json d = j.is_object() ? j.value("device", json(0)) : json(0);
            device = static_cast<uint32_t>(
                json_integer(d, 0, std::numeric_limits<uint32_t>::max()).value_or(0));
        }
        if (!daemon_.set_calibration(*device, &*c))
            fail(*path + ": device " + std::to_string(*device) + " does not exist");
        if (active_ && active_->device != *device)
            daemon_.set_calibration(active_->device, nullptr);
        active_ = Active{user, *device, std::move(c).value()};
    }

    json active_json() const {
        if (!active_) return nullptr;
        json j = quality_json(active_->calibration.quality());
        j["user"] = active_->user;
        j["device"] = active_->device;
        return j;
    }

    Daemon& daemon_;
    gaze::DisplayGeometry display_;
    CalibrationConfig settings_;
    std::string dir_;
    std::optional<Session> session_;
    std::optional<Active> active_;
    std::string load_error_;
};

}  // namespace

void attach_calibration(Daemon& daemon) {
    auto svc = std::make_shared<CalibrationService>(daemon);
    svc->load_configured_user();
    daemon.add_raw_observer([svc](const gaze::RawSample& raw) { svc->on_raw(raw); });
    auto& c = daemon.control();
    using H = std::function<json(CalibrationService&, const json&)>;
    auto add = [&](const char* name, bool admin, const char* help, H h) {
        c.add_command(
            name, [svc, h](const json& req, const PeerCredentials&) { return h(*svc, req); }, admin,
            help);
    };
    add("calibrate.start", true, "begin a calibration: {\"user\": NAME, \"eyes\": \"both\"}",
        [](CalibrationService& s, const json& r) { return s.start(r); });
    add("calibrate.point", true,
        "a target {\"x\", \"y\"} (normalized) or {\"deg_x\", \"deg_y\"}, optionally with raw "
        "\"samples\"; otherwise collected from the device",
        [](CalibrationService& s, const json& r) { return s.point(r); });
    add("calibrate.finish", true, "fit, report accuracy/precision, store and apply",
        [](CalibrationService& s, const json& r) { return s.finish(r); });
    add("calibrate.cancel", true, "abandon the calibration session",
        [](CalibrationService& s, const json&) { return s.cancel(); });
    add("calibrate.apply", true, "apply a stored calibration: {\"user\": NAME}",
        [](CalibrationService& s, const json& r) { return s.apply(r); });
    add("calibrate.clear", true, "stop applying a calibration",
        [](CalibrationService& s, const json&) { return s.clear(); });
    add("calibrate.target", true,
        "show a target {\"x\", \"y\"} or {\"hide\": true} without collecting",
        [](CalibrationService& s, const json& r) { return s.target(r); });
    add("calibrate.list", false, "stored calibrations per user",
        [](CalibrationService& s, const json&) { return s.list(); });
    add("calibrate.status", false, "the calibration session's progress and the active calibration",
        [](CalibrationService& s, const json&) { return s.status(); });
    daemon.add_status_section("calibration", [svc] { return svc->status(); });
}

}  // namespace fovea::daemon
