// A message from Pupil Capture's bus as bytes: [topic, msgpack datum, raw frames...] (raw frames,
// eye images, are not used) decoded into a chain sample. The socket code in pupil_driver.cpp
// only receives the frames; this is what it does with them. Pure functions; any thread.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "fovea/gaze/sample.hpp"

namespace fovea::drivers::pupil {

struct BusMessage {
    enum class Kind {
        kSample,     // a gaze or pupil datum: `sample`, `pupil_time_s`
        kOther,      // blinks, notifications, ...: not samples, not an error
        kMalformed,  // `why` says what was wrong (for the log, with the topic)
    };
    Kind kind = Kind::kMalformed;
    gaze::RawSample sample;   // device_ticks = ns of Pupil time
    double pupil_time_s = 0;  // finite for kSample
    std::string why;
};

// `frames` as received: the topic frame first, then the datum frame (any more are ignored).
BusMessage decode_bus_message(const std::vector<std::string>& frames, double min_confidence);

// Pupil time to host CLOCK_MONOTONIC ns by the measured offset (Pupil - host); 0 when the result
// is not a positive 64-bit ns count.
uint64_t host_ticks(double pupil_time_s, double offset_s);

}  // namespace fovea::drivers::pupil
