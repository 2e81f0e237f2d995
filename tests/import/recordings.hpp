// Every recording under ../shared/data/recordings with what it holds, counted here with plain
// string handling and an independent .npy reader — never through fovea::import — so that tests
// can check the importers against it. Files that are not recordings are listed with the reason.
#pragma once

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "fovea/import/reader.hpp"

namespace fovea::import::test {

namespace fs = std::filesystem;

inline const fs::path kData = FOVEA_SHARED_DATA_DIR;

struct Count {
    uint64_t rows = 0;
    double first = NAN, last = NAN;  // min and max stamp, seconds after `scale`
    void add(double t) {
        if (rows++ == 0) first = last = t;
        first = std::min(first, t);
        last = std::max(last, t);
    }
};

inline std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// A .npy's float64s: header length, then 8 bytes each.
inline Count npy_count(const fs::path& p) {
    const std::string d = slurp(p);
    Count c;
    if (d.size() < 10) return c;
    const std::size_t hl = static_cast<uint8_t>(d[8]) | static_cast<uint8_t>(d[9]) << 8;
    for (std::size_t off = 10 + hl; off + 8 <= d.size(); off += 8) {
        double v;
        std::memcpy(&v, d.data() + off, 8);
        c.add(v);
    }
    return c;
}

// Rows after the column line (the first line, or the first starting with `header`) whose first
// character is one of `starts`; field `time_field` is the stamp. `complete_only` leaves out a
// last line without a line end.
inline Count csv_count(const fs::path& p, char sep, int time_field, bool complete_only,
                       const std::string& header = "", const std::string& starts = "0123456789") {
    const std::string d = slurp(p);
    Count c;
    std::size_t pos = header.empty() ? 0 : d.find("\n" + header) + 1;
    pos = d.find('\n', pos) + 1;
    while (pos < d.size()) {
        std::size_t end = d.find('\n', pos);
        if (end == std::string::npos) {
            if (complete_only) break;
            end = d.size();
        }
        const std::string line = d.substr(pos, end - pos);
        pos = end + 1;
        if (line.empty() || starts.find(line[0]) == std::string::npos) continue;
        std::stringstream ss(line);
        std::string f;
        for (int i = 0; i <= time_field; ++i) std::getline(ss, f, sep);
        c.add(std::strtod(f.c_str(), nullptr));
    }
    return c;
}

// EyeLink: sample lines start with a digit inside START..END (ms); E* lines are events.
inline Count asc_count(const fs::path& p, Item kind) {
    std::ifstream in(p);
    std::string line;
    Count c;
    bool block = false;
    while (std::getline(in, line)) {
        if (line.rfind("START", 0) == 0) block = true;
        if (line.rfind("END", 0) == 0) block = false;
        if (kind == Item::kSample && block && !line.empty() &&
            std::isdigit(static_cast<unsigned char>(line[0])))
            c.add(std::strtod(line.c_str(), nullptr));
        if (kind == Item::kEvent && (line.rfind("EFIX", 0) == 0 || line.rfind("ESACC", 0) == 0 ||
                                     line.rfind("EBLINK", 0) == 0)) {
            std::stringstream ss(line);
            std::string word, eye, start;
            ss >> word >> eye >> start;
            c.add(std::strtod(start.c_str(), nullptr));
        }
        if (kind == Item::kMarker && (line.rfind("MSG", 0) == 0 || line.rfind("INPUT", 0) == 0))
            ++c.rows;  // MSG offsets move the stamp: count only
    }
    if (kind == Item::kMarker) c.first = c.last = NAN;
    return c;
}

// ARFF: rows after @DATA that are not comments; the first field is µs.
inline Count arff_count(const fs::path& p) {
    std::ifstream in(p);
    std::string line;
    Count c;
    bool data = false;
    while (std::getline(in, line)) {
        if (line.rfind("@DATA", 0) == 0 || line.rfind("@data", 0) == 0) {
            data = true;
        } else if (data && !line.empty() && line[0] != '%') {
            c.add(std::strtod(line.c_str(), nullptr));
        }
    }
    return c;
}

struct Expect {
    Item kind;  // which items `count` counts
    Count count;
    double scale = 1.0;  // count's stamps * scale = seconds
};

struct Unit {
    fs::path path;  // a file, or a Pupil recording folder
    std::vector<Expect> expect;
};

struct Recordings {
    std::vector<Unit> units;
    std::map<fs::path, std::string> not_recordings;  // file -> why it is not imported itself
};

inline Recordings recordings() {
    Recordings r;
    const fs::path rec = kData / "recordings";
    const fs::path el = rec / "eyelink", pu = rec / "pupil",
                   vedb = pu / "vedb_pupil_recording_interface", to = rec / "tobii/EMDAT";
    for (const char* f :
         {"mne-testing-data/test_eyelink.asc", "mne-testing-data/test_eyelink_HREF.asc",
          "eyelinkparser/data1.asc", "sp_tool/eyelink_data_example.asc"})
        r.units.push_back({el / f,
                           {{Item::kSample, asc_count(el / f, Item::kSample), 1e-3},
                            {Item::kEvent, asc_count(el / f, Item::kEvent), 1e-3},
                            {Item::kMarker, asc_count(el / f, Item::kMarker)}}});
    r.units.push_back({el / "sp_tool/arff_data_example.arff",
                       {{Item::kSample, arff_count(el / "sp_tool/arff_data_example.arff"), 1e-6}}});
    const fs::path bino = vedb / "tests_test_data/binocular_only_gaze.pldata";
    const Count bino_n = npy_count(vedb / "tests_test_data/binocular_only_gaze_timestamps.npy");
    r.units.push_back({bino, {{Item::kSample, bino_n}}});
    r.units.push_back(
        {vedb / "test_recording",
         {{Item::kSample, npy_count(vedb / "test_recording/pupil_timestamps.npy")},
          {Item::kMarker, npy_count(vedb / "test_recording/notify_timestamps.npy")}}});
    for (const char* f :
         {"pupil-tutorials/gaze_positions.csv", "pupil-tutorials/10_merge/gaze_positions.csv",
          "pupil-helpers_lsl-recording.csv"})
        r.units.push_back({pu / f, {{Item::kSample, csv_count(pu / f, ',', 0, false)}}});
    for (const char* f :
         {"pupil-tutorials/10_merge/blinks.csv", "pupil-tutorials/10_merge/fixations.csv"})
        r.units.push_back({pu / f, {{Item::kEvent, csv_count(pu / f, ',', 1, false)}}});
    r.units.push_back(
        {to / "Tobii4C_4Ctest.csv",
         {{Item::kSample, csv_count(to / "Tobii4C_4Ctest.csv", ';', 17, true), 1e-6}}});
    r.units.push_back(
        {to / "Tobii4C_P123456_Data_Export.tsv",
         {{Item::kSample, csv_count(to / "Tobii4C_P123456_Data_Export.tsv", '\t', 18, true),
           1e-6}}});
    r.units.push_back(
        {to / "Tobii4C_4Ctest_fixation.csv",
         {{Item::kEvent, csv_count(to / "Tobii4C_4Ctest_fixation.csv", ',', 3, true, "", "fs"),
           1e-6}}});
    r.units.push_back(
        {to / "TobiiStudio_P61-Event-Data.tsv",
         {{Item::kMarker,
           csv_count(to / "TobiiStudio_P61-Event-Data.tsv", '\t', 0, true, "Timestamp\t"), 1e-3}}});
    r.units.push_back(
        {to / "TobiiStudio_P62-Fixation-Data.tsv",
         {{Item::kEvent,
           csv_count(to / "TobiiStudio_P62-Fixation-Data.tsv", '\t', 1, true, "FixationIndex\t"),
           1e-3}}});
    r.not_recordings = {
        {el / "sp_tool/eyelink_data_example.edf",
         "binary EDF (SR Research's own format): read its edf2asc output, "
         "eyelink_data_example.asc"},
        {bino.parent_path() / "binocular_only_gaze_timestamps.npy",
         "time stamps of the .pldata beside it"},
    };
    for (const char* f :
         {"eye0_timestamps.npy", "eye1_timestamps.npy", "gaze_timestamps.npy", "info.player.json",
          "notify.pldata", "notify_timestamps.npy", "pupil.pldata", "pupil_timestamps.npy",
          "user_info.csv", "world.intrinsics", "world_timestamps.npy"})
        r.not_recordings[vedb / "test_recording" / f] = "part of the test_recording folder";
    for (const auto& e : fs::recursive_directory_iterator(rec))
        if (e.is_regular_file() &&
            (e.path().filename() == "LICENSE" || e.path().filename() == "LICENSE.md" ||
             e.path().filename() == "copyright"))
            r.not_recordings[e.path()] = "licence text";
    return r;
}

}  // namespace fovea::import::test
