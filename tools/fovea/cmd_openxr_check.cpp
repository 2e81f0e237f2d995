// fovea openxr-check: a headless OpenXR app (Vulkan, no window) that enables
// XR_EXT_eye_gaze_interaction, binds the gaze pose, and compares the poses it gets for N frames
// with fovead's ring (tools/openxr/gaze_check.hpp says what is scored). Exit 0 when every check
// holds, 1 when one does not, 2 when there is no eye gaze to check.
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "command.hpp"
#include "gaze_check.hpp"

namespace fovea::cli {
namespace {

struct Options {
    int frames = 300;
    bool json = false;
    bool allow_no_gaze = false;
    std::string csv;
    double max_error_deg = 0.1;
};

nlohmann::json to_json(const xr::CheckRun& run, const xr::CheckReport& r) {
    return {
        {"runtime", run.runtime},
        {"api_layers", run.offer.api_layers},
        {"eye_gaze_extension", run.eye_gaze},
        {"supports_eye_gaze_interaction", run.supports_eye_gaze_interaction},
        {"frames", r.frames},
        {"valid_frames", r.valid_frames},
        {"invalid_frames", r.invalid_frames},
        {"invalid_runs", r.invalid_runs},
        {"longest_invalid_run_frames", r.longest_invalid_run},
        {"valid_frames_after_longest_invalid_run", r.valid_after_longest_invalid_run},
        {"max_angle_error_deg", r.max_angle_error_deg},
        {"median_angle_error_deg", r.median_angle_error_deg},
        {"probes", r.probes},
        {"probes_compared", r.probes_compared},
        {"validity_mismatches", r.validity_mismatches},
        {"untracked_probes", r.blink_probes},
        {"max_local_error_deg", r.max_local_error_deg},
        {"median_gaze_age_ms", r.median_gaze_age_ms},
        {"p95_gaze_age_ms", r.p95_gaze_age_ms},
        {"locate_p50_us", r.locate_p50_us},
        {"locate_p99_us", r.locate_p99_us},
        {"locate_max_us", r.locate_max_us},
        {"display_frames_compared", r.display_compared},
        {"display_error_p50_deg", r.display_error_p50_deg},
        {"display_error_p95_deg", r.display_error_p95_deg},
        {"hold_error_p50_deg", r.hold_error_p50_deg},
        {"hold_error_p95_deg", r.hold_error_p95_deg},
        {"saccade_frames", r.saccade_frames},
        {"saccade_display_error_p50_deg", r.saccade_display_error_p50_deg},
        {"saccade_hold_error_p50_deg", r.saccade_hold_error_p50_deg},
        {"saccades", r.saccades},
        {"saccade_lag_frames_max", r.saccade_lag_frames_max},
        {"saccade_layer_lag_frames_max", r.saccade_layer_lag_frames_max},
        {"late_data_saccades", r.late_data_saccades},
        {"frame_interval_max_ms", r.frame_interval_max_ms},
        {"ring_records", run.records.size()},
        {"ring_restarts", run.ring_restarts},
        {"failures", r.failures},
    };
}

void write_csv(const std::string& path, const xr::CheckRun& run, const xr::CheckReport& r) {
    std::ofstream out(path);
    if (!out) throw std::runtime_error("cannot write " + path);
    out << "frame,display_ns,active,valid,dir_x,dir_y,dir_z,sample_ns,newest_capture_ns,"
           "newest_event,locate_us,probe_ns,probe_valid,probe_x,probe_y,probe_z,"
           "display_error_deg,hold_error_deg,probe_error_deg\n";
    for (std::size_t k = 0; k < run.frames.size(); ++k) {
        const xr::FrameRecord& f = run.frames[k];
        out << k << ',' << f.display_ns << ',' << f.active << ',' << f.valid << ',' << f.dir[0]
            << ',' << f.dir[1] << ',' << f.dir[2] << ',' << f.sample_ns << ','
            << f.newest_capture_ns << ',' << f.newest_event << ',' << f.locate_us << ','
            << f.probe_ns << ',' << f.probe_valid << ',' << f.probe_dir[0] << ',' << f.probe_dir[1]
            << ',' << f.probe_dir[2] << ',' << r.display_error_deg[k] << ',' << r.hold_error_deg[k]
            << ',' << r.probe_error_deg[k] << '\n';
    }
}

void print_text(const xr::CheckRun& run, const xr::CheckReport& r) {
    std::printf("runtime %s, eye gaze %s, %d frames: %d valid, %d invalid (%d runs, longest %d)\n",
                run.runtime.c_str(), run.eye_gaze ? "on" : "off", r.frames, r.valid_frames,
                r.invalid_frames, r.invalid_runs, r.longest_invalid_run);
    std::printf(
        "matching times: %d probes, error median %.4f max %.4f deg, %d validity "
        "mismatches (%d untracked)\n",
        r.probes_compared, r.median_angle_error_deg, r.max_angle_error_deg, r.validity_mismatches,
        r.blink_probes);
    std::printf(
        "display time: gaze age median %.1f p95 %.1f ms; error p50 %.2f p95 %.2f deg "
        "(holding the newest sample: %.2f / %.2f)\n",
        r.median_gaze_age_ms, r.p95_gaze_age_ms, r.display_error_p50_deg, r.display_error_p95_deg,
        r.hold_error_p50_deg, r.hold_error_p95_deg);
    std::printf("in saccades (%d frames): error p50 %.2f deg (holding: %.2f)\n", r.saccade_frames,
                r.saccade_display_error_p50_deg, r.saccade_hold_error_p50_deg);
    std::printf(
        "saccades: %d, worst lag %d frames after the gaze (%d after the ring had it; %d "
        "reached the ring late); xrLocateSpace p50 %.1f p99 %.1f us\n",
        r.saccades, r.saccade_lag_frames_max, r.saccade_layer_lag_frames_max, r.late_data_saccades,
        r.locate_p50_us, r.locate_p99_us);
    for (const auto& f : r.failures) std::printf("FAILED: %s\n", f.c_str());
}

void setup(CLI::App& app) {
    static Options o;
    app.add_option("--frames", o.frames, "Frames to run")->check(CLI::Range(1, 1000000));
    app.add_flag("--json", o.json, "Print the report as JSON");
    app.add_option("--csv", o.csv, "Write every frame's pose, probe and timing to this CSV");
    app.add_flag("--allow-no-gaze", o.allow_no_gaze,
                 "Run the frames even without eye gaze (e.g. the layer disabled); exit 0");
    app.add_option("--max-error-deg", o.max_error_deg,
                   "Largest pose-vs-ring angle allowed at matching times");
    app.callback([] {
        xr::CheckOptions co;
        co.instance = global_options().instance;
        co.frames = o.frames;
        co.allow_no_gaze = o.allow_no_gaze;
        auto run = xr::run_check(co);
        if (!run) {
            std::fprintf(stderr, "fovea openxr-check: %s\n", run.error().message.c_str());
            throw CLI::RuntimeError(2);
        }
        xr::CheckLimits limits;
        limits.max_angle_error_deg = o.max_error_deg;
        const xr::CheckReport report = xr::evaluate(*run, limits);
        if (!o.csv.empty()) write_csv(o.csv, *run, report);
        if (o.json)
            std::printf("%s\n", to_json(*run, report).dump(2).c_str());
        else
            print_text(*run, report);
        if (!run->eye_gaze) {
            if (!o.allow_no_gaze) throw CLI::RuntimeError(2);
            return;
        }
        if (!report.failures.empty()) throw CLI::RuntimeError(1);
    });
}

const Command kOpenXrCheck{"openxr-check",
                           "Check eye gaze through OpenXR (XR_EXT_eye_gaze_interaction) against "
                           "fovead's ring, headless",
                           &setup};

}  // namespace
}  // namespace fovea::cli
