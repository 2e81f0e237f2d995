// The single writer of a ring (used by fovead). Creates "/fovea.<instance>.<stream>", replacing
// any object a crashed writer left behind, so readers of the old one see a new generation.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <string>

#include "fovea/result.hpp"
#include "fovea/ring.h"
#include "seqlock.hpp"

namespace fovea::ring {

struct WriterOptions {
    std::string instance = "default";
    fovea_stream_kind kind = FOVEA_STREAM_GAZE;
    uint32_t slot_count = FOVEA_RING_DEFAULT_SLOTS;  // rounded up to a power of two
    uint32_t nominal_rate_hz = 0;
    std::string device_name;
    fovea_eye_geometry eyes{};  // the HMD profile's eye views; zero for a monitor
    mode_t mode = 0640;         // readers only read (DESIGN.md §4)
};

class RingWriter {
public:
    // Called once per daemon start, from the service thread.
    static Result<RingWriter> create(const WriterOptions& options);

    RingWriter() = default;
    RingWriter(RingWriter&& other) noexcept;
    RingWriter& operator=(RingWriter&& other) noexcept;
    RingWriter(const RingWriter&) = delete;
    RingWriter& operator=(const RingWriter&) = delete;
    ~RingWriter();

    // Publish one record (fovea_gaze_record or fovea_head_record, per the stream kind). Fills
    // index, t_publish_ns (if zero) and checksum. Wait-free; one FUTEX_WAKE syscall.
    // Called from the one writer thread only. Returns the record's index.
    uint64_t publish(fovea_gaze_record& record);
    uint64_t publish(fovea_head_record& record);

    // Change the rate readers see in fovea_client_info: a tracker whose rate is measured from
    // its first samples. Service thread; readers may be attached.
    void set_nominal_rate_hz(uint32_t hz);

    // True if any client has the ring open (clients hold a shared flock on it).
    bool readers_attached() const;

    // Mark the ring closed and unlink it; mapped readers keep their view.
    void close();

    uint64_t head() const { return view_.header ? view_.header->head : 0; }
    uint64_t generation() const { return view_.header ? view_.header->generation : 0; }
    const std::string& name() const { return name_; }
    bool is_open() const { return view_.header != nullptr; }

private:
    uint64_t publish_words(void* record, uint64_t* index_field, int64_t* publish_field,
                           uint64_t* checksum_field);

    RingView view_;
    std::size_t bytes_ = 0;
    int fd_ = -1;
    std::string name_;
};

}  // namespace fovea::ring
