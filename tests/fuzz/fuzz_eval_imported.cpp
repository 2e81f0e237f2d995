// libFuzzer target: fovea::eval's datasets read through fovea::import (imported.cpp), which
// turn an EyeLink ASC file's parser events, or an ARFF file's label columns, into per-coder
// labels. Input naming an ARFF data section is read as ARFF, anything else as ASC. Invariants: no
// crash, and every coder's labels are aligned with the samples (Recording's contract), each a known
// event.
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "fovea/eval/dataset.hpp"

namespace {

namespace fs = std::filesystem;

void check(const fovea::eval::Recording& r) {
    for (const auto& [coder, labels] : r.coders) {
        if (labels.size() != r.samples.size()) std::abort();
        for (const auto e : labels)
            if (static_cast<unsigned>(e) > static_cast<unsigned>(fovea::gaze::Event::kBlink))
                std::abort();
    }
}

// The loaders read files: one folder per process, removed when libFuzzer exits normally (a
// crash leaves it beside the crash artefact).
struct ScratchDir {
    fs::path path = fs::temp_directory_path() / ("fuzz_eval_imported." + std::to_string(getpid()));
    ScratchDir() { fs::create_directories(path); }
    ~ScratchDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const ScratchDir scratch;
    const fs::path& dir = scratch.path;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    const bool asc = text.find("@DATA") == text.npos && text.find("@data") == text.npos;
    const fs::path file = dir / (asc ? "input.asc" : "input.arff");
    fs::remove(dir / (asc ? "input.arff" : "input.asc"));
    {
        std::ofstream out(file, std::ios::binary | std::ios::trunc);
        out.write(text.data(), static_cast<std::streamsize>(text.size()));
    }
    if (asc) {
        std::vector<std::string> notes;
        auto r = fovea::eval::load_asc(file.string(), &notes);
        if (r) check(*r);
    } else {
        auto d = fovea::eval::load_arff(dir.string());
        if (d)
            for (const auto& r : d->recordings) check(r);
    }
    return 0;
}
