// A stored calibration (<state>/calibrations/<user>.json, loaded at start and by
// calibrate.apply): any text loads or is refused with an error — never a crash — and what
// loads writes back to JSON that loads to the same calibration.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "fovea/gaze/calibration.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    const fovea::gaze::DisplayGeometry display;
    auto c = fovea::gaze::Calibration::from_json(text, display);
    if (!c) return 0;
    const std::string written = c->to_json();
    auto back = fovea::gaze::Calibration::from_json(written, display);
    if (!back || back->to_json() != written || back->fitted() != c->fitted()) std::abort();
    return 0;
}
