// Recording and latency statistics inside fovead (issue 9), attached to the daemon through its
// extension points (observers, control commands, status sections):
//   record.start {"path": "/abs/file.xdf"}  (admin)  start an XDF recording (raw, gaze, latency);
//                                                     the raw stream begins with a pre-roll of
//                                                     up to 65536 earlier raw samples (flagged)
//                                                     so `fovea replay` can rebuild the chain state
//   record.stop                              (admin)  stop it; replies with the counters
//   latency.report {"hops": {...}}                    an SDK client's render-side histograms
//                                                     (LatencyStats JSON with buckets), kept per
//                                                     client pid, replacing its previous report;
//                                                     fovea_frame_latency_report() also sends the
//                                                     gaze-age hops (capture_to_frame_begin,
//                                                     publish_to_frame_begin, capture_to_present)
//                                                     in "hops" and "frames", "stale_frames",
//                                                     "frames_without_gaze", "stale_threshold_ns"
//   latency.reset                            (admin)  zero the daemon's histograms
// Status sections: "latency" (device hops: capture_to_receive, receive_to_processed,
// processed_to_publish, each {count, negative, p50_us, p90_us, p99_us, p999_us, max_us, min_us,
// mean_us}), "latency_clients" (the merged client reports, same form, plus "gaze_age": {hop:
// summary}, "frames": {frames, stale, without_gaze, stale_threshold_ms_min/max}, "clients") and
// "recording".
#pragma once

namespace fovea::daemon {

class Daemon;

// Call once from Daemon::start(), on the loop thread, after the built-in commands are
// registered. Everything it creates lives as long as the daemon; a recording still running at
// shutdown is closed (footers written) when the daemon is destroyed.
void attach_recording(Daemon& daemon);

}  // namespace fovea::daemon
