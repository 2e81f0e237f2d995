// The records of a Pupil .pldata file exactly as stored, [topic, msgpack datum bytes], for tools
// that forward Pupil's own bytes (`fovea simulate pupil`). Streams in constant memory; a
// malformed record is skipped to the next record start (resyncs()). One thread.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "fovea/result.hpp"

namespace fovea::import {

namespace detail {
class PldataStream;
}

class PldataFile {
public:
    static Result<std::unique_ptr<PldataFile>> open(const std::string& path);
    ~PldataFile();
    PldataFile(const PldataFile&) = delete;
    PldataFile& operator=(const PldataFile&) = delete;

    // False at the end. The views stay valid until the next call.
    bool next(std::string_view& topic, std::string_view& datum);
    uint64_t records() const;
    uint64_t resyncs() const;
    bool truncated() const;

private:
    PldataFile() = default;
    std::unique_ptr<detail::PldataStream> stream_;
};

}  // namespace fovea::import
