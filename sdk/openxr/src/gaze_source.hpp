// fovead's gaze ring as seen by one OpenXR session: attaches when the daemon appears, re-attaches
// when it restarts, keeps the recent samples as a GazeTimeline and answers "where was / will the
// gaze be at time t". Thread-safe: any thread may call at(); a short internal lock serialises
// callers. Never blocks: ring reads are non-blocking, attach attempts are rate-limited.
#pragma once

#include <cstdint>
#include <mutex>
#include <string>

#include "fovea/client.h"
#include "gaze_geometry.hpp"
#include "gaze_timeline.hpp"

namespace fovea::openxr {

struct GazeSourceOptions {
    std::string instance = "default";  // fovead --instance
    TimelineParams timeline;
    int64_t retry_ns = 250'000'000;  // between attach attempts while fovead is absent
};

// Map one ring record to a timeline sample.
GazeSample to_sample(const fovea_gaze_record& r, const GazeGeometry& geometry);

class GazeSource {
public:
    explicit GazeSource(GazeSourceOptions options);
    ~GazeSource();
    GazeSource(const GazeSource&) = delete;
    GazeSource& operator=(const GazeSource&) = delete;

    // The gaze at t_ns (host CLOCK_MONOTONIC), after reading whatever fovead published since the
    // last call.
    GazeEstimate at(int64_t t_ns);

    struct Counters {
        uint64_t records = 0;   // ring records taken into the timeline
        uint64_t dropped = 0;   // records the ring overwrote before we read them
        uint64_t attaches = 0;  // successful attaches (first one included)
        uint64_t restarts = 0;  // writer generations replaced while attached
    };
    Counters counters() const;

private:
    void poll(int64_t now_ns);  // with mu_ held
    void try_attach(int64_t now_ns);
    void reset_to(fovea_client* c);
    void note_state(const GazeEstimate& e);

    const GazeSourceOptions options_;
    mutable std::mutex mu_;
    fovea_client* client_ = nullptr;
    uint64_t cursor_ = 0;
    GazeGeometry geometry_;
    GazeTimeline timeline_;
    int64_t next_attach_ns_ = 0;
    Counters counters_;
    // What the last log line said, so each change is logged once.
    bool said_absent_ = false, said_stale_ = false;
};

int64_t monotonic_now_ns();

}  // namespace fovea::openxr
