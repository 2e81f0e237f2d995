// The recent gaze as a timeline, and the gaze direction it implies at any time an OpenXR app
// asks for: interpolated between samples, held or extrapolated a bounded interval past the
// newest one (towards the predicted landing point during a saccade, along the eye's angular
// velocity during smooth pursuit), invalid when the eyes are untracked or the data is stale.
// Pure: no clocks, no I/O. One thread at a time (GazeSource serialises).
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>

#include "pose_math.hpp"

namespace fovea::openxr {

// One ring record, mapped to view space (GazeGeometry).
struct GazeSample {
    int64_t t_ns = 0;  // capture time, host CLOCK_MONOTONIC
    bool valid = false;
    Vec3 direction{0, 0, -1};  // unit, when valid
    bool pursuit = false;
    // A saccade in flight with a landing prediction.
    bool saccade = false;
    Vec3 landing{0, 0, -1};
    int64_t saccade_onset_ns = 0;
    double saccade_amplitude_deg = 0;  // covered so far
};

struct TimelineParams {
    int64_t max_prediction_ns = 50'000'000;  // never extrapolate further past the newest sample
    int64_t stale_ns = 100'000'000;          // newest sample older than this: no gaze
    // Main sequence for the time a saccade still needs (fovea::gaze::LandingParams' fit).
    double duration_slope_ms = 2.6;
    double duration_intercept_ms = 17.0;
    int64_t pursuit_window_ns = 20'000'000;  // angular velocity over this much history
    int64_t clock_jump_ns = 50'000'000;      // a sample this far before the newest: new timeline
};

enum class GazeStatus {
    kTracked,    // direction is valid
    kUntracked,  // the ring says the eyes are not tracked (blink, lost) at that time
    kStale,      // nothing new from the tracker for longer than stale_ns
    kNoData,     // nothing received yet
    kTooOld,     // asked for a time before the oldest sample kept
};
const char* status_name(GazeStatus s);

enum class GazeMethod { kNone, kInterpolated, kNearest, kHeld, kLanding, kPursuit };
const char* method_name(GazeMethod m);

struct GazeEstimate {
    GazeStatus status = GazeStatus::kNoData;
    GazeMethod method = GazeMethod::kNone;
    Vec3 direction{0, 0, -1};
    int64_t t_expressed_ns = 0;  // the time the direction holds for (the query, or clamped)
    int64_t t_newest_ns = 0;     // the newest sample known
    bool tracked() const { return status == GazeStatus::kTracked; }
};

class GazeTimeline {
public:
    explicit GazeTimeline(TimelineParams params = {}, std::size_t capacity = 512);

    // Samples arrive in capture order. A small step back (clock-mapping jitter) is nudged to
    // just after the newest; a jump back of more than clock_jump_ns restarts the timeline.
    void push(const GazeSample& s);
    void clear();

    // The gaze at time t_ns, judged at host time now_ns (for staleness).
    GazeEstimate at(int64_t t_ns, int64_t now_ns) const;

    std::size_t size() const { return samples_.size(); }
    int64_t newest_ns() const { return samples_.empty() ? 0 : samples_.back().t_ns; }
    uint64_t clock_jumps() const { return clock_jumps_; }
    const TimelineParams& params() const { return params_; }

private:
    GazeEstimate beyond_newest(int64_t t_ns, int64_t now_ns) const;
    Vec3 landing_at(const GazeSample& s, int64_t t_ns) const;
    Vec3 pursuit_at(int64_t t_ns) const;

    TimelineParams params_;
    std::size_t capacity_;
    std::deque<GazeSample> samples_;
    uint64_t clock_jumps_ = 0;
};

}  // namespace fovea::openxr
