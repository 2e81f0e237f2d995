// Calibration inside fovead (issue 3, part 5), attached through the daemon's extension points
// (raw observer, control commands, status section). Admin-only commands are marked (admin).
//   calibrate.start  {"user": "ana", "eyes": "both"|"left"|"right", "device": 0}       (admin)
//       begin a session (replaces an unfinished one)
//   calibrate.point  {"x": 0.5, "y": 0.5} or {"deg_x": 0, "deg_y": 0}                   (admin)
//       [, "samples": [{"left": [x, y], "right": [x, y] or null}, ...]]
//       with "samples": those raw samples belong to this target. Without: the daemon shows the
//       target (simulated trackers look at it), discards settle_ms of raw samples (saccadic
//       latency), collects collect_ms of them, and the reply says when; poll calibrate.status
//       until the point is "done". Of the collected samples only the eyes' dwell on the target
//       is fitted (gaze/target_dwell.hpp): not the eyes on their way, nor a blink's lid
//       artefacts; the point's status counts "lost", "blink_edges", "not_settled" and
//       "dwell_ms", and a point without a 100 ms fixation adds no "samples" (redo it).
//   calibrate.finish {"store": true, "apply": true}                                    (admin)
//       fit; reply per eye accuracy (mean angular offset) and precision (RMS sample-to-sample,
//       SD) in degrees "before" (raw as the chain shows it uncalibrated) and "after" the fit,
//       "after" with each target checked against the fit through the others
//       ("target_checks": x, y, residual_deg, expected_deg, samples, left_out: left out of
//       that eye's fit; gaze/calibration.hpp);
//       store <dir>/<user>.json and apply it to the device's chain (FOVEA_FLAG_CALIBRATED)
//   calibrate.cancel                                                                   (admin)
//   calibrate.apply  {"user": "ana"}  apply a stored calibration                        (admin)
//   calibrate.clear                   run uncalibrated (the stored file stays)          (admin)
//   calibrate.target {"x", "y"} or {"hide": true}: show a target without collecting    (admin)
//       (validation, and steering the simulated tracker's gaze)
//   calibrate.list                    stored calibrations and their quality
//   calibrate.status                  the session's progress and the active calibration
// [calibration] in fovead.toml: user (applied at start), dir (default
// <state_dir()>/calibrations), settle_ms (300), collect_ms (1000). Status section "calibration".
#pragma once

namespace fovea::daemon {

class Daemon;

// Call once from Daemon::start(), on the loop thread, after the devices are built. Loads and
// applies the configured user's calibration; a missing or bad file is logged and shown in
// status, and the daemon runs uncalibrated.
void attach_calibration(Daemon& daemon);

}  // namespace fovea::daemon
