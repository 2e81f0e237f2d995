// Which of the samples collected while a calibration target was shown show the eyes settled on
// it. A fixed settle time cannot cover everything a real eye does after a target appears: a
// blink delays the saccade by up to ~0.4 s, the lid's edges drag the tracked pupil for tens of
// ms around the lost samples, and a corrective saccade follows an undershoot. Samples from
// those moments, fitted as if the eye had been on the target, bend the whole calibration.
//
//   auto d = target_dwell(in_degrees, true, true, {}, &last.at);  // once the collection ended
//   for (size_t i : d.keep) calibration.add_sample(target, raw[i].left, raw[i].right);
//
// Pure function; thread-safe.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "fovea/gaze/event_detector.hpp"
#include "fovea/gaze/sample.hpp"

namespace fovea::gaze {

// One sample in arrival order, x/y in degrees of visual angle: the daemon converts the raw
// samples it fits (nominally normalized display coordinates) through the display; a validation
// passes the published degrees.
struct TargetSample {
    int64_t t_ns = 0;
    EyeSample left, right;
};

struct TargetDwellRules {
    // Around a lost sample (no used eye tracked), the lid's artefacts: the spans the event
    // detector labels blink.
    double lid_before_s = DetectorParams{}.blink_pre_s;
    double lid_after_s = DetectorParams{}.blink_post_s;
    // A dwell ends, walking back in time, where two consecutive samples lie farther than
    // this from its median: fixational eye movements (drift, microsaccades) stay within ~1 deg
    // (Martinez-Conde et al. 2004), so a larger step is a saccade to the target.
    double dwell_radius_deg = 1.5;
    // ... or farther than this many times the dwell's own sample noise (RMS sample-to-sample
    // distance / sqrt 2), for trackers noisier than the radius allows.
    double noise_radius_factor = 3.0;
    // A dwell entered by a saccade starts this much later: the saccade's last, slow part is
    // within the radius, and post-saccadic oscillations last 10-40 ms (Nystrom & Holmqvist
    // 2010's glissades; the simulated tracker's PSO).
    double settle_after_saccade_s = 0.040;
    // A dwell shorter than this is no fixation (the conventional minimum fixation duration of
    // dispersion-based detectors, Salvucci & Goldberg 2000): nothing is kept.
    double min_dwell_s = 0.100;
};

struct TargetDwell {
    std::vector<size_t> keep;  // indices into the samples, in order
    size_t lost = 0;           // no used eye tracked
    size_t lid = 0;            // within a blink's lid artefacts
    size_t unsettled = 0;      // outside the dwell (the eyes still on their way, a one-
                               // sample spike), or every other sample if the dwell was too short
    double dwell_s = 0;        // duration of the dwell, from its first kept sample
    // Where the eyes dwelt (per eye, the median over the dwell's final min_dwell_s; invalid
    // when nothing is kept): the next target's `previous`.
    TargetSample at;
};

// `use_left` / `use_right`: the eyes being calibrated. A sample with one of them lost is kept (the
// calibration skips that eye); with none tracked it is lost.
// Which dwell: without `previous`, the final one. With `previous` (where the eyes dwelt at the
// target before, e.g. the last call's `at`), the longest one elsewhere: the eyes may still be at
// the previous target when the collection starts, and may leave this one before it ends (a
// glance, or anticipating the next target: seen on a real Pupil Capture calibration); the final
// one again if every dwell is there.
TargetDwell target_dwell(const std::vector<TargetSample>& samples, bool use_left, bool use_right,
                         const TargetDwellRules& rules = {},
                         const TargetSample* previous = nullptr);

}  // namespace fovea::gaze
