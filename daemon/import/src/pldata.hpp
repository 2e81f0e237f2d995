// Pupil's storage: a .pldata file is a plain run of msgpack 2-arrays [topic, bin(datum)]; its
// <name>_timestamps.npy holds one little-endian float64 per record. Both read block-wise.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "fovea/msgpack_read.hpp"
#include "fovea/result.hpp"
#include "text.hpp"

namespace fovea::import::detail {

// The records of one .pldata file. A malformed record is skipped by hunting for the next
// record start (counted in resyncs()); a record cut off at the end sets truncated().
class PldataStream {
public:
    explicit PldataStream(std::unique_ptr<ByteSource> source);
    // False at the end. The views stay valid until the next call.
    bool next(std::string_view& topic, std::string_view& payload);
    uint64_t records() const { return records_; }
    uint64_t bytes() const { return buf_.consumed(); }
    uint64_t resyncs() const { return resyncs_; }
    bool truncated() const { return truncated_; }
    // What went wrong at the last resync or truncation, with the byte offset.
    const std::string& last_problem() const { return problem_; }
    const std::string& error() const { return buf_.error(); }

private:
    void resync(const std::string& why);
    BlockBuffer buf_;
    uint64_t records_ = 0, resyncs_ = 0;
    bool truncated_ = false;
    msgpack::object_handle record_;
    std::string problem_;
};

// A 1-D little-endian float64 .npy array, read one value at a time.
class NpyDoubles {
public:
    static Result<std::unique_ptr<NpyDoubles>> open(const std::string& path);
    // Bytes from anywhere; `path` names them in errors.
    static Result<std::unique_ptr<NpyDoubles>> open(std::unique_ptr<ByteSource> source,
                                                    const std::string& path);
    bool next(double& out);
    uint64_t size() const { return size_; }

private:
    std::unique_ptr<ByteSource> source_;
    uint64_t size_ = 0, read_ = 0;
};

// "<recording_software_name> <recording_software_version>" from an info.player.json's text
// (Pupil Capture 1.16+ writes it), or what was wrong with it. Never throws.
std::string pupil_recording_software(std::string_view info_player_json);

}  // namespace fovea::import::detail
