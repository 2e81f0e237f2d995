// Text forms of ring records shared by `watch`, `record` and friends.
#pragma once

#include <cstdio>
#include <string>

#include "fovea/ring.h"

namespace fovea::cli {

const char* event_name(uint32_t event);

// The CSV that `fovea record --out FILE.csv` writes (and the replay driver reads by column name).
void write_csv_header(std::FILE* f, const std::string& comment);
void write_csv_row(std::FILE* f, const fovea_gaze_record& r);

// One human-readable line per sample for `fovea watch`.
std::string watch_line(const fovea_gaze_record& r, int64_t now_ns);

int64_t monotonic_ns();

}  // namespace fovea::cli
