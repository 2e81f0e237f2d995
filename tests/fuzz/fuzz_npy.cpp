// libFuzzer target: a Pupil recording's <name>_timestamps.npy as the importer reads it
// (NpyDoubles over bytes in memory). Invariants: no crash; what opens yields at most the length
// its header gives, and exactly the little-endian float64s that follow the header, as many as
// the bytes hold.
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string_view>

#include "pldata.hpp"

namespace detail = fovea::import::detail;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    auto npy = detail::NpyDoubles::open(detail::ByteSource::memory(bytes), "fuzz.npy");
    if (!npy) {
        if (npy.error().message.empty()) std::abort();
        return 0;
    }
    // Version 1 has a 2-byte header length after the 8-byte magic and version, 2+ a 4-byte one.
    const bool v2 = data[6] >= 2;
    std::size_t header_len = data[8] | std::size_t{data[9]} << 8;
    if (v2) header_len |= std::size_t{data[10]} << 16 | std::size_t{data[11]} << 24;
    const std::size_t body = (v2 ? 12 : 10) + header_len;
    if (body > size) std::abort();
    const uint64_t expect = std::min<uint64_t>((*npy)->size(), (size - body) / 8);
    uint64_t n = 0;
    double v = 0;
    while ((*npy)->next(v)) {
        if (n >= expect) std::abort();
        uint64_t bits = 0;
        for (int i = 7; i >= 0; --i)
            bits = bits << 8 | data[body + n * 8 + static_cast<unsigned>(i)];
        uint64_t got = 0;
        std::memcpy(&got, &v, 8);
        if (got != bits) std::abort();
        ++n;
    }
    if (n != expect) std::abort();
    return 0;
}
