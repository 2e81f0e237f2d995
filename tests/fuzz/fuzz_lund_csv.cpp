// libFuzzer target: fovea::import's reader for the lund2013 labelled CSV (invariants in
// import_fuzz.hpp).
#include "fuzz/import_fuzz.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    fovea::fuzz::check_import(data, size, fovea::import::Format::kLund2013);
    return 0;
}
