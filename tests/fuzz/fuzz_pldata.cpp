// libFuzzer target: fovea::import's reader for Pupil .pldata streams (invariants in
// import_fuzz.hpp).
#include "fuzz/import_fuzz.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    fovea::fuzz::check_import(data, size, fovea::import::Format::kPupilFolder);
    return 0;
}
