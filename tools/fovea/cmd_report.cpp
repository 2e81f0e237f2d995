// fovea report FILE.xdf --out DIR: self-contained HTML page with PNG plots.
#include <cstdio>
#include <stdexcept>
#include <string>

#include "command.hpp"
#include "fovea/record/report.hpp"
#include "fovea/record/xdf.hpp"

namespace fovea::cli {
namespace {

void setup_report(CLI::App& app) {
    static std::string file, dir;
    app.add_option("file", file, "Recording (.xdf)")->required();
    app.add_option("--out,-o", dir, "Output directory (report.html + PNGs)")->required();
    app.callback([] {
        auto f = record::xdf::read_file(file);
        if (!f) throw std::runtime_error(f.error().message);
        if (f->truncated) {
            std::fprintf(stderr, "fovea report: %s is truncated (%s); reporting what is readable\n",
                         file.c_str(), f->truncation_reason.c_str());
        }
        auto r = record::make_report(*f, file, dir);
        if (!r) throw std::runtime_error(r.error().message);
        std::printf("%s (%zu plots; %.1f s, %llu samples, %llu saccades, %llu lost)\n",
                    r->html_path.c_str(), r->pngs.size(), r->duration_s,
                    static_cast<unsigned long long>(r->raw_samples),
                    static_cast<unsigned long long>(r->saccades),
                    static_cast<unsigned long long>(r->missing_samples));
    });
}

const Command kReport{"report", "HTML report with latency, gaze, main-sequence and drop plots",
                      &setup_report};

}  // namespace
}  // namespace fovea::cli
