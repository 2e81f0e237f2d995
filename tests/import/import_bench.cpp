// Importer throughput on every real recording of ../shared/data: each file read whole through
// fovea::import from the page cache, `--rounds` times interleaved across files; medians of CPU
// time (the machine is shared: wall time is printed beside it). "read" is one pass with the
// rate given; "open+read" is what open() does (a first pass over up to 2000 samples measures
// the rate). Prints a table and writes --csv FILE.
//   import_bench [--rounds 5] [--csv import_bench.csv] [--data DIR]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <string>
#include <vector>

#include "fovea/import/reader.hpp"

namespace fs = std::filesystem;
using namespace fovea::import;

namespace {

struct Run {
    double cpu_s = 0, wall_s = 0;
    uint64_t bytes = 0, items = 0;
};

Run read_once(const std::string& path, double rate_hz) {
    Options o;
    o.rate_hz = rate_hz;
    const std::clock_t c0 = std::clock();
    const auto w0 = std::chrono::steady_clock::now();
    auto r = open(path, o);
    Run run;
    if (!r) return run;
    for (auto it = (*r)->next(); it != Item::kEnd; it = (*r)->next()) ++run.items;
    run.cpu_s = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    run.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
    run.bytes = (*r)->stats().bytes;
    return run;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
    int rounds = 5;
    std::string csv = "import_bench.csv";
    fs::path data = FOVEA_SHARED_DATA_DIR;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--rounds")) rounds = std::max(1, std::atoi(argv[i + 1]));
        if (!std::strcmp(argv[i], "--csv")) csv = argv[i + 1];
        if (!std::strcmp(argv[i], "--data")) data = argv[i + 1];
    }
    struct Input {
        std::string path;
        Format format{};
        double rate = 0;
        std::vector<Run> read, open_read;
    };
    std::vector<Input> inputs;
    const fs::path rec = data / "recordings";
    if (!fs::exists(rec)) {
        std::printf("no %s: nothing to measure\n", rec.c_str());
        return 0;
    }
    std::vector<fs::path> paths;
    for (const auto& e : fs::recursive_directory_iterator(rec))
        if (e.is_regular_file()) paths.push_back(e.path());
    paths.push_back(rec / "pupil/vedb_pupil_recording_interface/test_recording");
    paths.push_back(data / "labelled/gazecom/GGM_holsten_gate.input.arff");
    for (const auto& e : fs::directory_iterator(data / "lund2013"))
        if (e.path().filename().string().starts_with("img__TH34")) paths.push_back(e.path());
    std::sort(paths.begin(), paths.end());
    for (const auto& p : paths) {
        const std::string s = p.string();
        if (p.extension() == ".npy" || p.extension() == ".edf") continue;
        if (s.find("test_recording/") != std::string::npos) continue;  // read as the folder
        auto r = open(s);
        if (!r) continue;  // licence texts, info.player.json, ...
        Input in;
        in.path = s;
        in.format = (*r)->info().format;
        in.rate = (*r)->info().measured_rate_hz;
        inputs.push_back(std::move(in));
    }
    for (int k = 0; k < rounds; ++k)
        for (auto& in : inputs) {
            in.read.push_back(read_once(in.path, in.rate > 0 ? in.rate : 1.0));
            in.open_read.push_back(read_once(in.path, 0.0));
        }

    std::FILE* out = std::fopen(csv.c_str(), "w");
    if (out)
        std::fprintf(out,
                     "file,format,bytes,items,read_cpu_mb_s,open_read_cpu_mb_s,"
                     "read_wall_mb_s,open_read_wall_mb_s\n");
    std::printf("%-44s %-12s %9s %8s %10s %10s %10s\n", "file", "format", "bytes", "items",
                "read MB/s", "open+read", "wall MB/s");
    for (const auto& in : inputs) {
        std::vector<double> rc, oc, rw, ow;
        for (const auto& r : in.read) {
            rc.push_back(r.bytes / std::max(r.cpu_s, 1e-6) / 1e6);
            rw.push_back(r.bytes / std::max(r.wall_s, 1e-6) / 1e6);
        }
        for (const auto& r : in.open_read) {
            oc.push_back(r.bytes / std::max(r.cpu_s, 1e-6) / 1e6);
            ow.push_back(r.bytes / std::max(r.wall_s, 1e-6) / 1e6);
        }
        const std::string name = fs::relative(in.path, data).string();
        const Run& r0 = in.read.front();
        std::printf("%-44s %-12s %9llu %8llu %10.1f %10.1f %10.1f\n",
                    name.substr(name.size() > 44 ? name.size() - 44 : 0).c_str(),
                    format_name(in.format), static_cast<unsigned long long>(r0.bytes),
                    static_cast<unsigned long long>(r0.items), median(rc), median(oc), median(rw));
        if (out)
            std::fprintf(out, "%s,%s,%llu,%llu,%.2f,%.2f,%.2f,%.2f\n", name.c_str(),
                         format_name(in.format), static_cast<unsigned long long>(r0.bytes),
                         static_cast<unsigned long long>(r0.items), median(rc), median(oc),
                         median(rw), median(ow));
    }
    if (out) std::fclose(out);
    std::printf("medians of %d rounds, MB/s of CPU time unless marked wall; CSV: %s\n", rounds,
                csv.c_str());
    return 0;
}
