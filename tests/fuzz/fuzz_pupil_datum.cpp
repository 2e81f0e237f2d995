// libFuzzer target: one Pupil datum as the live `pupil` driver receives it from Pupil Capture's
// bus (decode_pupil_datum + pupil_sample). Invariants: no crash; a valid eye has finite
// coordinates; eye ids stay 0/1.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "fovea/import/pupil_datum.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    auto d = fovea::import::decode_pupil_datum(
        std::string_view(reinterpret_cast<const char*>(data), size));
    if (!d) return 0;
    if (d->eye_id < -1 || d->eye_id > 1) std::abort();
    fovea::gaze::RawSample s;
    if (fovea::import::pupil_sample(*d, 0.6, s))
        for (const auto* e : {&s.left, &s.right})
            if (e->valid && !(std::isfinite(e->x) && std::isfinite(e->y))) std::abort();
    return 0;
}
