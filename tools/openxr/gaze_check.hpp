// `fovea openxr-check`: an OpenXR app's view of eye gaze, compared with fovead's ring read
// directly. For N frames it locates the gaze pose at the predicted display time (what an app
// renders with) and at a "matching time" between the two newest ring samples (where the pose
// must equal the ring's gaze), and keeps every ring record, so afterwards it can score:
//   - matching times: angle between the pose and the ring's gaze interpolated at that time,
//     and whether the pose was valid exactly when the ring says the eyes were tracked;
//   - display times: the gaze's age (display time - newest sample's capture), the error of the
//     predicted pose against the gaze that was later recorded at that time (and of simply
//     holding the newest sample), the frames a saccade takes to show up in the pose;
//   - the cost of each xrLocateSpace call.
// One thread.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "fovea/client.h"
#include "fovea/result.hpp"
#include "headless_session.hpp"

namespace fovea::xr {

struct CheckOptions {
    std::string instance = "default";
    int frames = 300;
    bool allow_no_gaze = false;    // run the frames even without the extension (layer disabled)
    int focus_timeout_ms = 20000;  // for the session to reach FOCUSED
    int ring_timeout_ms = 5000;    // for fovead's ring to appear
};

// One frame as the app saw it.
struct FrameRecord {
    int64_t display_ns = 0;         // predicted display time, CLOCK_MONOTONIC
    int64_t begin_ns = 0;           // when the frame began (after xrWaitFrame)
    bool active = false;            // xrGetActionStatePose isActive
    bool valid = false;             // the pose at display time
    double dir[3] = {0, 0, -1};     // its -Z axis in VIEW space
    int64_t sample_ns = 0;          // XrEyeGazeSampleTimeEXT, CLOCK_MONOTONIC (0 if none)
    int64_t newest_before_ns = 0;   // the ring's newest sample right before locating
    int64_t newest_capture_ns = 0;  // the ring's newest sample right after locating
    uint32_t newest_event = 0;      // its fovea_event
    double locate_us = 0;           // the display-time xrLocateSpace call
    // The matching-time probe (probe_ns == 0: none this frame).
    int64_t probe_ns = 0;
    bool probe_valid = false;
    double probe_dir[3] = {0, 0, -1};
    double probe_local_error_deg = -1;  // gaze-in-LOCAL vs VIEW-in-LOCAL x gaze-in-VIEW
};

struct CheckRun {
    std::string runtime;
    Offer offer;
    bool eye_gaze = false;  // the extension was offered and enabled
    bool supports_eye_gaze_interaction = false;
    std::vector<FrameRecord> frames;
    std::vector<fovea_gaze_record> records;  // every ring record seen, in order
    fovea_eye_geometry eyes{};
    uint64_t ring_restarts = 0;
};

// Runs the session; the ring is optional only with allow_no_gaze.
Result<CheckRun> run_check(const CheckOptions& options);

struct CheckReport {
    int frames = 0, valid_frames = 0, invalid_frames = 0;
    int longest_invalid_run = 0, valid_after_longest_invalid_run = 0, invalid_runs = 0;
    int probes = 0, probes_compared = 0, validity_mismatches = 0, blink_probes = 0;
    std::string first_validity_mismatch;  // the probe and its ring neighbours, for the failure
    double max_angle_error_deg = 0, median_angle_error_deg = 0;
    double max_local_error_deg = 0;
    double median_gaze_age_ms = 0, p95_gaze_age_ms = 0;
    double locate_p50_us = 0, locate_p99_us = 0, locate_max_us = 0;
    int display_compared = 0;
    double display_error_p50_deg = 0, display_error_p95_deg = 0;
    double hold_error_p50_deg = 0, hold_error_p95_deg = 0;
    // The same over frames whose newest sample was in a saccade (where prediction matters).
    int saccade_frames = 0;
    double saccade_display_error_p50_deg = 0, saccade_hold_error_p50_deg = 0;
    // Frames from the first displayed after the gaze moved 1 deg to the first whose pose did
    // (worst, over saccades whose moved sample reached the ring in time for the next frame), and
    // from the first frame located with that sample in the ring (all saccades; must be 0); the
    // saccades whose sample came later than that (tracker, fovead or scheduling latency).
    int saccades = 0, saccade_lag_frames_max = 0, saccade_layer_lag_frames_max = 0;
    int late_data_saccades = 0;
    std::string worst_saccade;  // what the slowest one looked like
    double frame_interval_max_ms = 0;
    // Per frame, -1 where not compared: the display-time pose's and the held sample's error,
    // and the probe's.
    std::vector<double> display_error_deg, hold_error_deg, probe_error_deg;
    std::vector<std::string> failures;  // the checks that did not hold, one line each
};

struct CheckLimits {
    double max_angle_error_deg = 0.1;
    int max_saccade_lag_frames = 1;
    double max_local_error_deg = 0.01;
};

CheckReport evaluate(const CheckRun& run, const CheckLimits& limits = {});

}  // namespace fovea::xr
