// fovea export FILE.xdf --csv DIR: one CSV per stream of a recording.
#include <cstdio>
#include <stdexcept>
#include <string>

#include "command.hpp"
#include "fovea/record/offline.hpp"
#include "fovea/record/xdf.hpp"

namespace fovea::cli {
namespace {

void setup_export(CLI::App& app) {
    static std::string file, dir;
    app.add_option("file", file, "Recording (.xdf)")->required();
    app.add_option("--csv", dir, "Directory for the CSV files (one per stream)")->required();
    app.callback([] {
        auto f = record::xdf::read_file(file);
        if (!f) throw std::runtime_error(f.error().message);
        if (f->truncated) {
            std::fprintf(stderr,
                         "fovea export: %s ends in an incomplete chunk (%s); exporting the "
                         "%llu readable bytes (run `fovea repair` to close it)\n",
                         file.c_str(), f->truncation_reason.c_str(),
                         static_cast<unsigned long long>(f->valid_bytes));
        }
        auto out = record::export_csv(*f, dir);
        if (!out) throw std::runtime_error(out.error().message);
        for (const auto& c : *out) {
            std::printf("%-16s %8llu rows  %s\n", c.stream.c_str(),
                        static_cast<unsigned long long>(c.rows), c.path.c_str());
        }
    });
}

const Command kExport{"export", "Export a recording's streams to CSV", &setup_export};

}  // namespace
}  // namespace fovea::cli
