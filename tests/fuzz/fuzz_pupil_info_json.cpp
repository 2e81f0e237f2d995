// libFuzzer target: a Pupil recording's info.player.json as the importer reads it for the
// recording software's name and version. Invariants: no crash, no escaped exception, and an
// answer that is never empty.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "pldata.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string s = fovea::import::detail::pupil_recording_software(
        std::string_view(reinterpret_cast<const char*>(data), size));
    if (s.empty()) std::abort();
    return 0;
}
