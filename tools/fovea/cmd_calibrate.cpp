// fovea calibrate: drive a calibration through fovead's control socket (calibrate.* in
// daemon/src/calibration_commands.hpp). Each target is shown to the devices (the simulated
// tracker's eyes look at it), the daemon collects the raw samples, fits, stores and applies.
// Then a validation pass shows fresh targets and measures the published, calibrated gaze in the
// ring: accuracy on samples the fit never saw.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "command.hpp"
#include "control_client.hpp"
#include "fovea/gaze/target_dwell.hpp"
#include "fovea/ring.h"
#include "gaze_format.hpp"
#include "paths.hpp"
#include "ring_session.hpp"

namespace fovea::cli {
namespace {

using nlohmann::json;
using namespace std::chrono_literals;

struct CalibrateOptions {
    std::string user;
    int points = 9;
    int device = 0;
    std::string eyes = "both";
    bool json_out = false;
    bool validate = true;
};

json request(const json& req, int timeout_ms = 5000) {
    auto reply = daemon::control_request(daemon::control_socket_path(global_options().instance),
                                         req, timeout_ms);
    if (!reply) throw std::runtime_error(reply.error().message);
    if (!reply->value("ok", false))
        throw std::runtime_error(req["cmd"].get<std::string>() + ": " +
                                 reply->value("error", std::string("request failed")));
    reply->erase("ok");
    return *reply;
}

// 9: a 3x3 grid over 10..90 % of the display; 13 adds the four points between its rows.
std::vector<std::pair<double, double>> calibration_targets(int n) {
    std::vector<std::pair<double, double>> t = {{0.5, 0.5}, {0.1, 0.1}, {0.5, 0.1},
                                                {0.9, 0.1}, {0.9, 0.5}, {0.9, 0.9},
                                                {0.5, 0.9}, {0.1, 0.9}, {0.1, 0.5}};
    if (n == 13) {
        for (auto p : {std::pair{0.3, 0.3}, {0.7, 0.3}, {0.7, 0.7}, {0.3, 0.7}}) t.push_back(p);
    }
    return t;
}

constexpr int kRetriesPerTarget = 2;

// Validation targets differ from the calibration targets: the fit has not seen them.
const std::vector<std::pair<double, double>> kValidationTargets = {
    {0.4, 0.45}, {0.2, 0.25}, {0.8, 0.3}, {0.75, 0.75}, {0.25, 0.7}};

// The point's calibrate.status entry once it is done.
json wait_for_point(std::size_t index) {
    for (;;) {
        const json s = request({{"cmd", "calibrate.status"}});
        const json& session = s["session"];
        if (session.is_null()) throw std::runtime_error("the calibration session was cancelled");
        const json& p = session["points"].at(index);
        if (p["done"].get<bool>()) return p;
        const int64_t left = p.value("remaining_ms", int64_t{50});
        std::this_thread::sleep_for(std::chrono::milliseconds(std::clamp<int64_t>(left, 20, 200)));
    }
}

// Accuracy and precision (degrees) per eye of the published gaze while fresh targets are shown:
// the offset of every valid sample from its target, and per target the RMS sample-to-sample
// distance and the SD around the mean (the published gaze is filtered, so precision is better
// than the raw figures). Only the eyes' dwell on each target counts, as in the fit
// (gaze/target_dwell.hpp: not the eyes on their way, nor a blink's lid edges). As in common
// eye-tracker practice (Pupil's accuracy visualiser, for one), samples more than kOutlierDeg
// from the target are excluded and counted too: the eye was not on the target then, which says
// nothing about the calibration.
constexpr double kOutlierDeg = 5.0;

json validate(int device, double settle_ms, double collect_ms) {
    auto ring = open_ring(global_options().instance, 2000);
    std::map<std::string, std::vector<std::vector<std::pair<double, double>>>>
        per_eye;  // per target
    std::map<std::string, double> offset_sum, offset_n;
    std::map<std::string, uint64_t> excluded;
    uint64_t calibrated = 0, records = 0, lost = 0, blink_edges = 0, not_settled = 0;
    json per_target = json::array();
    std::optional<gaze::TargetSample> previous;  // where the eyes dwelt at the last target
    for (const auto& [x, y] : kValidationTargets) {
        // Records are selected by capture time: the chain publishes with a look-ahead delay, so
        // what arrives right after the settle time may still show the previous target.
        uint64_t cursor = ring->head();
        const int64_t shown_ns = monotonic_ns();
        const int64_t from_ns = shown_ns + static_cast<int64_t>(settle_ms * 1e6);
        const int64_t until_ns = from_ns + static_cast<int64_t>(collect_ms * 1e6);
        // The daemon converts the target to degrees with its own display geometry.
        const json shown = request({{"cmd", "calibrate.target"}, {"x", x}, {"y", y}});
        const double tx = shown["deg_x"].get<double>(), ty = shown["deg_y"].get<double>();
        std::vector<gaze::TargetSample> window;
        bool past = false;
        while (!past && monotonic_ns() < until_ns + 2'000'000'000) {
            if (!ring->wait(cursor, 100)) continue;
            for (const auto& r : ring->read(cursor, 256).records) {
                if (static_cast<int>(r.device_id) != device) continue;
                past = past || r.t_capture_ns >= until_ns;
                if (r.t_capture_ns < from_ns || r.t_capture_ns >= until_ns) continue;
                ++records;
                calibrated += (r.flags & FOVEA_FLAG_CALIBRATED) != 0;
                gaze::TargetSample t;
                t.t_ns = r.t_capture_ns;
                for (auto [out, eye] : {std::pair{&t.left, &r.left}, {&t.right, &r.right}}) {
                    out->valid = (eye->valid & FOVEA_VALID) != 0;
                    out->x = eye->deg_x;
                    out->y = eye->deg_y;
                }
                window.push_back(t);
            }
        }
        const gaze::TargetDwell dwell =
            gaze::target_dwell(window, true, true, {}, previous ? &*previous : nullptr);
        previous.reset();  // where the eyes went is known only from a kept dwell
        if (!dwell.keep.empty()) previous = dwell.at;
        lost += dwell.lost;
        blink_edges += dwell.lid;
        not_settled += dwell.unsettled;
        std::map<std::string, std::vector<std::pair<double, double>>> here;
        std::map<std::string, double> target_sum;
        for (const std::size_t i : dwell.keep) {
            for (auto [name, eye] :
                 {std::pair{"left", &window[i].left}, {"right", &window[i].right}}) {
                if (!eye->valid) continue;
                const double offset = std::hypot(eye->x - tx, eye->y - ty);
                if (!(offset <= kOutlierDeg)) {
                    ++excluded[name];
                    continue;
                }
                here[name].emplace_back(eye->x, eye->y);
                target_sum[name] += offset;
                offset_sum[name] += offset;
                offset_n[name] += 1;
            }
        }
        // Each target's own accuracy: a region the calibration misses shows here, not in the
        // mean over all of them.
        json target = {{"x", x},
                       {"y", y},
                       {"lost_records", dwell.lost},
                       {"blink_edge_records", dwell.lid},
                       {"not_settled_records", dwell.unsettled}};
        for (const char* name : {"left", "right"}) {
            const std::size_t n = here[name].size();
            target[std::string(name) + "_deg"] = n ? json(target_sum[name] / n) : json(nullptr);
            target[std::string(name) + "_samples"] = n;
        }
        per_target.push_back(target);
        for (auto& [name, v] : here) per_eye[name].push_back(std::move(v));
    }
    request({{"cmd", "calibrate.target"}, {"hide", true}});
    json out = {{"targets", kValidationTargets.size()},
                {"records", records},
                {"calibrated_records", calibrated},
                {"lost_records", lost},
                {"blink_edge_records", blink_edges},
                {"not_settled_records", not_settled},
                {"per_target", per_target}};
    for (const char* name : {"left", "right"}) {
        if (!offset_n[name]) {
            out[name] = nullptr;
            continue;
        }
        double s2s = 0, dev = 0, n2s = 0, ndev = 0;
        for (const auto& v : per_eye[name]) {
            double cx = 0, cy = 0;
            for (const auto& p : v) {
                cx += p.first / static_cast<double>(v.size());
                cy += p.second / static_cast<double>(v.size());
            }
            for (std::size_t k = 0; k < v.size(); ++k) {
                dev += std::pow(v[k].first - cx, 2) + std::pow(v[k].second - cy, 2);
                ++ndev;
                if (k > 0) {
                    s2s += std::pow(v[k].first - v[k - 1].first, 2) +
                           std::pow(v[k].second - v[k - 1].second, 2);
                    ++n2s;
                }
            }
        }
        out[name] = {{"accuracy_deg", offset_sum[name] / offset_n[name]},
                     {"precision_rms_deg", n2s ? std::sqrt(s2s / n2s) : 0.0},
                     {"precision_sd_deg", ndev ? std::sqrt(dev / ndev) : 0.0},
                     {"samples", static_cast<int64_t>(offset_n[name])},
                     {"excluded_samples", excluded[name]},
                     {"outlier_threshold_deg", kOutlierDeg}};
    }
    return out;
}

std::string fmt_deg(double deg) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3f°", deg);
    return buf;
}

std::string fmt(const json& eye, const char* key) {
    if (eye.is_null() || !eye.contains(key) || !eye[key].is_number()) return "     -";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%6.3f", eye[key].get<double>());
    return buf;
}

void print_table(const json& result) {
    std::printf("calibration for '%s' on device %d: %d targets, stored %s\n",
                result["user"].get<std::string>().c_str(), result["device"].get<int>(),
                result["after"]["targets"].get<int>(),
                result["stored"].is_string() ? result["stored"].get<std::string>().c_str()
                                             : "(not stored)");
    std::printf("%-26s %-5s %9s %9s %9s %8s\n", "", "eye", "accuracy", "prec RMS", "prec SD",
                "samples");
    auto row = [](const char* what, const char* eye, const json& q) {
        if (q.is_null()) return;
        std::printf("%-26s %-5s %8s° %8s° %8s° %8d\n", what, eye, fmt(q, "accuracy_deg").c_str(),
                    fmt(q, "precision_rms_deg").c_str(), fmt(q, "precision_sd_deg").c_str(),
                    q.value("samples", 0));
    };
    for (const char* eye : {"left", "right"}) {
        row("before (raw)", eye, result["before"][eye]);
        row("after (fit)", eye, result["after"][eye]);
        if (result.contains("validation"))
            row("validation (published)", eye, result["validation"][eye]);
    }
    for (const char* eye : {"left", "right"}) {
        const json& after = result["after"][eye];
        if (after.is_null() || !after.contains("target_checks")) continue;
        for (const json& d : after["target_checks"]) {
            if (!d["left_out"].get<bool>()) continue;
            std::printf(
                "%s eye: target (%.2f, %.2f) left out of the fit: the other targets put its %d "
                "samples %s away (%s expected); the tracker misread the eye there, or it looked "
                "elsewhere\n",
                eye, d["x"].get<double>(), d["y"].get<double>(), d["samples"].get<int>(),
                fmt_deg(d["residual_deg"].get<double>()).c_str(),
                fmt_deg(d["expected_deg"].get<double>()).c_str());
        }
    }
    if (result.contains("validation")) {
        const json& v = result["validation"];
        const auto count = [&](const char* key) {
            return static_cast<unsigned long long>(v[key].get<uint64_t>());
        };
        std::printf(
            "validation: %d fresh targets, %llu of %llu published records flagged calibrated; "
            "left out: %llu lost, %llu at a blink's edges, %llu before the eyes settled\n",
            v["targets"].get<int>(), count("calibrated_records"), count("records"),
            count("lost_records"), count("blink_edge_records"), count("not_settled_records"));
        std::printf("validation per target, left / right accuracy:");
        for (const json& t : v["per_target"]) {
            const auto deg = [](const json& d) {
                return d.is_number() ? fmt_deg(d.get<double>()) : std::string("-");
            };
            std::printf("  (%.2f, %.2f) %s / %s", t["x"].get<double>(), t["y"].get<double>(),
                        deg(t["left_deg"]).c_str(), deg(t["right_deg"]).c_str());
        }
        std::printf("\n");
    }
}

void run_calibrate(const CalibrateOptions& o) {
    const std::string user = !o.user.empty()                               ? o.user
                             : std::getenv("USER") && *std::getenv("USER") ? std::getenv("USER")
                                                                           : "default";
    const json started = request(
        {{"cmd", "calibrate.start"}, {"user", user}, {"eyes", o.eyes}, {"device", o.device}});
    const double settle_ms = started["settle_ms"].get<double>();
    const double collect_ms = started["collect_ms"].get<double>();
    try {
        const auto targets = calibration_targets(o.points);
        std::size_t shown = 0;  // the session's point index
        for (std::size_t i = 0; i < targets.size(); ++i) {
            const auto [x, y] = targets[i];
            // A target the eyes never settled on (a blink, a late look) adds nothing to the fit;
            // it is shown again, as eye-tracker calibrations redo a point.
            for (int attempt = 0; attempt <= kRetriesPerTarget; ++attempt) {
                const json p = request({{"cmd", "calibrate.point"}, {"x", x}, {"y", y}});
                if (shown == 0 && p.value("devices_following", 0) == 0 && !o.json_out)
                    std::fprintf(stderr,
                                 "fovea calibrate: no device moves its gaze to the targets by "
                                 "itself; the user must look at each target as it is shown\n");
                if (!o.json_out)
                    std::fprintf(stderr, "target %zu/%zu at (%.2f, %.2f)\n", i + 1, targets.size(),
                                 x, y);
                const json done = wait_for_point(shown++);
                if (done.value("samples", 0) > 0) break;
                std::fprintf(stderr,
                             "fovea calibrate: target %zu/%zu: the eyes did not settle on it "
                             "(%d samples: %d lost, %d at a blink's edges, %d moving)%s\n",
                             i + 1, targets.size(),
                             done.value("samples", 0) + done.value("not_settled", 0) +
                                 done.value("blink_edges", 0) + done.value("lost", 0),
                             done.value("lost", 0), done.value("blink_edges", 0),
                             done.value("not_settled", 0),
                             attempt < kRetriesPerTarget ? "; showing it again" : "; skipped");
            }
        }
    } catch (...) {
        (void)daemon::control_request(daemon::control_socket_path(global_options().instance),
                                      {{"cmd", "calibrate.cancel"}});
        throw;
    }
    json result = request({{"cmd", "calibrate.finish"}});
    if (o.validate) {
        if (!o.json_out)
            std::fprintf(stderr, "validating on %zu fresh targets\n", kValidationTargets.size());
        result["validation"] = validate(o.device, settle_ms, collect_ms);
    }
    if (o.json_out) {
        std::printf("%s\n", result.dump(2).c_str());
    } else {
        print_table(result);
    }
}

void setup_calibrate(CLI::App& app) {
    static CalibrateOptions o;
    app.add_option("--user", o.user, "Whose calibration this is (default: $USER)");
    app.add_option("--points", o.points, "Calibration targets: 9 or 13")
        ->check(CLI::IsMember({9, 13}));
    app.add_option("--device", o.device, "Device index to calibrate")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--eyes", o.eyes, "both, left or right")
        ->check(CLI::IsMember({"both", "left", "right"}));
    app.add_flag("--json", o.json_out, "Print one JSON object: before, after, validation");
    app.add_flag("!--no-validate", o.validate, "Skip the validation pass on fresh targets");
    app.callback([] { run_calibrate(o); });
}

const Command kCalibrate{"calibrate",
                         "Calibrate a user: show targets, fit, store and apply; print accuracy "
                         "and precision before and after",
                         &setup_calibrate};

}  // namespace
}  // namespace fovea::cli
