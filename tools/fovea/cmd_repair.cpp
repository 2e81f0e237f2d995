// fovea repair FILE.xdf: close a recording a crashed or killed daemon left open.
#include <cstdio>
#include <stdexcept>
#include <string>

#include "command.hpp"
#include "fovea/record/xdf.hpp"

namespace fovea::cli {
namespace {

void setup_repair(CLI::App& app) {
    static std::string file;
    app.add_option("file", file, "Recording (.xdf) to close in place")->required();
    app.callback([] {
        auto r = record::xdf::repair(file);
        if (!r) throw std::runtime_error(r.error().message);
        if (r->already_closed) {
            std::printf("%s: already complete (%llu samples), nothing to do\n", file.c_str(),
                        static_cast<unsigned long long>(r->samples_kept));
            return;
        }
        std::printf(
            "%s: kept %llu samples, dropped %llu bytes of an incomplete last chunk, "
            "added %d stream footer(s)\n",
            file.c_str(), static_cast<unsigned long long>(r->samples_kept),
            static_cast<unsigned long long>(r->bytes_dropped), r->footers_added);
    });
}

const Command kRepair{"repair", "Close a truncated XDF recording (after a crash or kill -9)",
                      &setup_repair};

}  // namespace
}  // namespace fovea::cli
