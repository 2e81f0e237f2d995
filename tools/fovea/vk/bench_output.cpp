#include "bench_output.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>

#include "bench_analysis.hpp"
#include "fovea/record/plot.hpp"

namespace fovea::bench {
namespace {

nlohmann::json number_or_null(double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

const std::string& primary_display(const std::vector<Row>& rows) {
    static const std::string none;
    return rows.empty() ? none : rows.front().display_name;
}

const Row* find_row(const std::vector<Row>& rows, const std::string& method, const std::string& tag,
                    const std::string& display) {
    for (const auto& r : rows)
        if (r.method == method && r.tag == tag && r.display_name == display && r.error.empty())
            return &r;
    return nullptr;
}

nlohmann::json row_json(const Row& r, const std::string& primary) {
    nlohmann::json m;
    m["label"] = variant_label(r, primary);
    m["method"] = r.method;
    m["tag"] = r.tag;
    m["display"] = r.display_name;
    m["resolution"] = {r.width, r.height};
    m["settings"] = r.settings;
    m["frames"] = r.frames;
    m["ms_per_frame"] = r.ms_median;
    m["ms_p95"] = r.ms_p95;
    m["method_gpu_ms"] = r.method_gpu_ms;
    m["shaded_fraction"] = r.shaded_fraction;
    m["psnr_fovea_db"] = number_or_null(r.psnr_fovea_db);
    m["psnr_bands_db"] = nlohmann::json::array();
    m["ssim_bands"] = nlohmann::json::array();
    for (int b = 0; b < vk::kBandCount; ++b) {
        m["psnr_bands_db"].push_back(number_or_null(r.psnr_bands_db[b]));
        m["ssim_bands"].push_back(number_or_null(r.ssim_bands[b]));
    }
    m["psnr_bands_mean_db"] = number_or_null(r.psnr_bands_mean_db);
    m["atd"] = number_or_null(r.atd);
    m["atd_8bit"] = number_or_null(r.atd_8bit);
    m["atd_settled"] = number_or_null(r.atd_settled);
    m["skipped_tiles"] = r.skipped_tiles;
    m["reused_tiles"] = r.reused_tiles;
    return m;
}

std::string fixed(double v, int digits) {
    if (!std::isfinite(v)) return "n/a";
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%.*f", digits, v);
    return buf;
}

}  // namespace

std::string variant_label(const Row& row, const std::string& primary) {
    std::string s = row.method + " " + row.tag;
    if (row.display_name != primary) s += " @" + row.display_name.substr(0, row.display_name.find(' '));
    return s;
}

std::vector<size_t> pareto_rows(const std::vector<Row>& rows) {
    std::vector<size_t> index;
    std::vector<CostQuality> points;
    for (size_t i = 0; i < rows.size(); ++i) {
        const Row& r = rows[i];
        if (r.method == "full" || !r.error.empty() || r.display_name != primary_display(rows)) continue;
        index.push_back(i);
        points.push_back({r.ms_median, r.psnr_bands_mean_db});
    }
    std::vector<size_t> front;
    for (size_t p : pareto_front(points)) front.push_back(index[p]);
    return front;
}

nlohmann::json to_json(const std::vector<Row>& rows, int frames) {
    const std::string& primary = primary_display(rows);
    nlohmann::json j;
    const Row* any = rows.empty() ? nullptr : &rows.front();
    j["resolution"] = {any ? any->width : 0u, any ? any->height : 0u};
    j["frames"] = frames;
    j["frame_dt_s"] = 1.0 / 60.0;
    j["methods"] = nlohmann::json::object();
    const Row* full_taa = find_row(rows, "full", "taa", primary);
    for (const auto& r : rows) {
        if (r.tag != "default" || r.display_name != primary) continue;
        if (!r.error.empty()) {
            j["errors"][r.method] = r.error;
            continue;
        }
        nlohmann::json m = row_json(r, primary);
        m.erase("label");
        m.erase("tag");
        m.erase("display");
        m["atd_no_taa"] = number_or_null(r.atd);
        const Row* taa = find_row(rows, r.method, "taa", primary);
        m["atd"] = taa ? number_or_null(taa->atd) : nlohmann::json(nullptr);
        m["atd_full_taa"] = full_taa ? number_or_null(full_taa->atd) : nlohmann::json(nullptr);
        if (taa) m["taa_ms"] = taa->ms_median - r.ms_median;
        if (const Row* te = find_row(rows, r.method, "taa+contrast", primary))
            m["taa_enhance_ms"] = te->ms_median - r.ms_median;
        j["methods"][r.method] = m;
    }
    j["variants"] = nlohmann::json::array();
    for (const auto& r : rows)
        if (r.error.empty()) j["variants"].push_back(row_json(r, primary));
    j["pareto_front"] = nlohmann::json::array();
    for (size_t i : pareto_rows(rows)) j["pareto_front"].push_back(variant_label(rows[i], primary));
    return j;
}

void print_table(std::FILE* out, const std::vector<Row>& rows) {
    const std::string& primary = primary_display(rows);
    std::fprintf(out, "%-26s %8s %8s %7s %8s %8s %8s %8s %8s  %s\n", "variant", "ms med", "ms p95",
                 "shaded", "fovea dB", "band dB", "ATD", "skipped", "reused", "PSNR dB by band (0-5/5-10/10-20/20-30/>30 deg)");
    for (const auto& r : rows) {
        if (!r.error.empty()) {
            std::fprintf(out, "%-26s failed: %s\n", variant_label(r, primary).c_str(), r.error.c_str());
            continue;
        }
        std::fprintf(out, "%-26s %8.1f %8.1f %6.1f%% %8.2f %8.2f %8.5f %8.1f %8.1f ",
                     variant_label(r, primary).c_str(), r.ms_median, r.ms_p95,
                     100.0 * r.shaded_fraction, r.psnr_fovea_db, r.psnr_bands_mean_db, r.atd,
                     r.skipped_tiles, r.reused_tiles);
        for (double p : r.psnr_bands_db) std::fprintf(out, " %6s", fixed(p, 2).c_str());
        std::fprintf(out, "\n");
    }
}

bool write_csv(const std::string& path, const std::vector<Row>& rows,
               const std::vector<std::string>& header_lines) {
    std::ofstream csv(path);
    for (const auto& l : header_lines) csv << "# " << l << "\n";
    csv << "method,tag,display,width,height,settings,frames,ms_median,ms_p95,method_gpu_ms,"
           "shaded_fraction,psnr_fovea_db,psnr_bands_mean_db";
    for (int b = 0; b < vk::kBandCount; ++b) csv << ",psnr_" << vk::band_name(b);
    for (int b = 0; b < vk::kBandCount; ++b) csv << ",ssim_" << vk::band_name(b);
    csv << ",atd,skipped_tiles,reused_tiles,pareto\n";
    const std::vector<size_t> front = pareto_rows(rows);
    for (size_t i = 0; i < rows.size(); ++i) {
        const Row& r = rows[i];
        if (!r.error.empty()) continue;
        csv << r.method << "," << r.tag << "," << r.display_name << "," << r.width << "," << r.height
            << ",\"" << r.settings << "\"," << r.frames << "," << r.ms_median << "," << r.ms_p95
            << "," << r.method_gpu_ms << "," << r.shaded_fraction << "," << r.psnr_fovea_db << ","
            << r.psnr_bands_mean_db;
        for (double p : r.psnr_bands_db) csv << "," << p;
        for (double s : r.ssim_bands) csv << "," << s;
        csv << "," << r.atd << "," << r.skipped_tiles << "," << r.reused_tiles << ","
            << (std::count(front.begin(), front.end(), i) ? 1 : 0) << "\n";
    }
    return bool(csv);
}

bool write_plot(const std::string& path, const std::vector<Row>& rows) {
    const std::string& primary = primary_display(rows);
    static const record::Rgb kColours[] = {{31, 119, 180}, {255, 127, 14}, {44, 160, 44},
                                           {214, 39, 40},  {148, 103, 189}, {140, 86, 75}};
    double x_hi = 0, y_lo = 1e9, y_hi = -1e9;
    const Row* full = find_row(rows, "full", "default", primary);
    std::map<std::string, std::pair<std::vector<double>, std::vector<double>>> by_method;
    for (const auto& r : rows) {
        if (r.method == "full" || !r.error.empty() || r.display_name != primary ||
            !std::isfinite(r.psnr_bands_mean_db))
            continue;
        by_method[r.method].first.push_back(r.ms_median);
        by_method[r.method].second.push_back(r.psnr_bands_mean_db);
        x_hi = std::max(x_hi, r.ms_median);
        y_lo = std::min(y_lo, r.psnr_bands_mean_db);
        y_hi = std::max(y_hi, r.psnr_bands_mean_db);
    }
    if (full) x_hi = std::max(x_hi, full->ms_median);
    if (by_method.empty()) y_lo = 0, y_hi = 1;
    record::Plot plot(900, 560, "time against error, " + primary,
                      "ms per frame (median)", "mean PSNR over eccentricity bands, dB");
    plot.set_x(0.0, x_hi * 1.08);
    plot.set_y(std::floor(y_lo - 1.0), std::ceil(y_hi + 1.0));
    const std::vector<size_t> front = pareto_rows(rows);
    std::vector<double> fx, fy;
    for (size_t i : front) {
        fx.push_back(rows[i].ms_median);
        fy.push_back(rows[i].psnr_bands_mean_db);
    }
    plot.line(fx, fy, {120, 120, 120}, 2);
    plot.points(fx, fy, {0, 0, 0}, 7);  // a black ring under the front's points
    size_t c = 0;
    for (const auto& [method, pts] : by_method) {
        const record::Rgb colour = kColours[c++ % std::size(kColours)];
        plot.points(pts.first, pts.second, colour, 4);
        plot.legend(method, colour);
    }
    plot.legend("Pareto front (ringed)", {120, 120, 120});
    if (full) plot.vline(full->ms_median, {200, 0, 0}, "full rate");
    return bool(plot.finish().save_png(path));
}

bool write_summary(const std::string& path, const std::vector<Row>& rows,
                   const std::vector<std::string>& header_lines, const std::string& png_name) {
    const std::string& primary = primary_display(rows);
    std::ofstream md(path);
    md << "Generated by `tools/bench_summary.sh` (`fovea bench`); do not edit by hand.\n\n";
    for (const auto& l : header_lines) md << "- " << l << "\n";
    md << "\nTimes are wall-clock per frame (rasterized G-buffer + method + post, submit to "
          "done) on lavapipe; errors are against the full-rate reference with the same post chain "
          "on the same frames; ATD is Patney's average temporal difference of consecutive "
          "tone-mapped frames (before 8-bit rounding) after back-projecting the previous one with "
          "the G-buffer motion and the frame's jitter.\n\n";
    md << "| variant | display | settings | ms median | ms p95 | shaded | fovea PSNR dB | "
          "band PSNR dB (mean) | SSIM >30deg | ATD | skipped / reused tiles |\n";
    md << "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& r : rows) {
        if (!r.error.empty()) continue;
        md << "| " << variant_label(r, primary) << " | " << r.display_name << " | " << r.settings
           << " | " << fixed(r.ms_median, 1) << " | " << fixed(r.ms_p95, 1) << " | "
           << fixed(100.0 * r.shaded_fraction, 1) << "% | " << fixed(r.psnr_fovea_db, 2) << " | "
           << fixed(r.psnr_bands_mean_db, 2) << " | " << fixed(r.ssim_bands[vk::kBandCount - 1], 3)
           << " | " << fixed(r.atd, 5) << " | " << fixed(r.skipped_tiles, 0) << " / "
           << fixed(r.reused_tiles, 0) << " |\n";
    }
    md << "\n**Pareto front** (" << primary
       << ", ms/frame against mean band PSNR; no cheaper variant is as accurate):\n\n";
    for (size_t i : pareto_rows(rows))
        md << "1. " << variant_label(rows[i], primary) << ": " << fixed(rows[i].ms_median, 1)
           << " ms, " << fixed(rows[i].psnr_bands_mean_db, 2) << " dB, shaded "
           << fixed(100.0 * rows[i].shaded_fraction, 1) << "%\n";
    if (const Row* full = find_row(rows, "full", "default", primary))
        md << "\nFull rate for comparison: " << fixed(full->ms_median, 1) << " ms.\n";
    md << "\n![time against error](" << png_name << ")\n";
    return bool(md);
}

}  // namespace fovea::bench
