#include "fovea/record/report.hpp"

#include <filesystem>
#include <fstream>

#include "report_parts.hpp"

namespace fovea::record {

Result<ReportSummary> make_report(const xdf::File& file, const std::string& source,
                                  const std::string& out_dir) {
    auto decoded = decode_recording(file);
    if (!decoded) return decoded.error();
    const report::Analysis a = report::analyse(std::move(decoded).value());
    std::error_code ec;
    std::filesystem::create_directories(out_dir, ec);
    if (ec) return make_error("cannot create " + out_dir + ": " + ec.message());
    auto figures = report::draw_figures(a, out_dir);
    if (!figures) return figures.error();
    ReportSummary sum = a.summary;
    for (const auto& f : *figures)
        sum.pngs.push_back((std::filesystem::path(out_dir) / f.file).string());
    sum.html_path = (std::filesystem::path(out_dir) / "report.html").string();
    std::ofstream out(sum.html_path);
    out << report::html_page(a, source, *figures, out_dir);
    if (!out) return make_error("cannot write " + sum.html_path);
    return sum;
}

}  // namespace fovea::record
