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

template <size_t N>
nlohmann::json array_json(const std::array<double, N>& a) {
    nlohmann::json j = nlohmann::json::array();
    for (double v : a) j.push_back(number_or_null(v));
    return j;
}

bool is_temporal(const Row& r) { return r.tag.rfind("temporal", 0) == 0; }

const std::string& primary_display(const std::vector<Row>& rows) {
    static const std::string none;
    return rows.empty() ? none : rows.front().display_name;
}

const Row* find_row(const std::vector<Row>& rows, const std::string& method, const std::string& tag,
                    const std::string& display = {}) {
    for (const auto& r : rows)
        if (r.method == method && r.tag == tag && (display.empty() || r.display_name == display) &&
            r.error.empty())
            return &r;
    return nullptr;
}

double front_error(const Row& r, FrontMetric m) {
    return m == FrontMetric::kFlip ? r.flip_mean : -r.psnr_db;
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
    m["gbuffer_gpu_ms"] = r.gbuffer_gpu_ms > 0 ? nlohmann::json(r.gbuffer_gpu_ms) : nullptr;
    m["shaded_fraction"] = r.shaded_fraction;
    m["flip_mean"] = number_or_null(r.flip_mean);
    m["flip_bands"] = array_json(r.flip_bands);
    m["flip_mean_67ppd"] = number_or_null(r.flip_mean_67ppd);
    m["flip_bands_67ppd"] = array_json(r.flip_bands_67ppd);
    m["band_ppd"] = array_json(r.band_ppd);
    m["flip_gpu_ms"] = r.flip_gpu_ms;
    m["psnr_db"] = number_or_null(r.psnr_db);  // null: identical to the reference (+inf)
    m["psnr_fovea_db"] = number_or_null(r.psnr_fovea_db);
    m["psnr_bands_pooled"] = array_json(r.psnr_bands_pooled);
    m["ssim_bands"] = array_json(r.ssim_bands);
    m["atd"] = number_or_null(r.atd);
    m["atd_8bit"] = number_or_null(r.atd_8bit);
    m["atd_settled"] = number_or_null(r.atd_settled);
    m["atd_cut"] = number_or_null(r.atd_cut);
    m["tflip"] = number_or_null(r.tflip);
    m["tflip_settled"] = number_or_null(r.tflip_settled);
    m["tflip_cut"] = number_or_null(r.tflip_cut);
    m["skipped_tiles"] = r.skipped_tiles;
    m["reused_tiles"] = r.reused_tiles;
    return m;
}

nlohmann::json temporal_json(const Row& r) {
    return {{"atd_settled", number_or_null(r.atd_settled)},
            {"atd_cut", number_or_null(r.atd_cut)},
            {"tflip_settled", number_or_null(r.tflip_settled)},
            {"tflip_cut", number_or_null(r.tflip_cut)}};
}

std::string fixed(double v, int digits) {
    if (std::isinf(v) && v > 0) return "inf";
    if (!std::isfinite(v)) return "n/a";
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%.*f", digits, v);
    return buf;
}

std::string json_fixed(const nlohmann::json& v, int digits) {
    return v.is_number() ? fixed(v.get<double>(), digits) : "n/a";
}

}  // namespace

std::string variant_label(const Row& row, const std::string& primary) {
    std::string s = row.method + " " + row.tag;
    if (row.display_name != primary)
        s += " @" + row.display_name.substr(0, row.display_name.find(' '));
    return s;
}

std::vector<size_t> pareto_rows(const std::vector<Row>& rows, FrontMetric metric) {
    std::vector<size_t> index;
    std::vector<CostError> points;
    for (size_t i = 0; i < rows.size(); ++i) {
        const Row& r = rows[i];
        // references ("full", the glTF scene's "full-forward") are not variants
        if (r.method.rfind("full", 0) == 0 || !r.error.empty() ||
            r.display_name != primary_display(rows) || is_temporal(r))
            continue;
        index.push_back(i);
        points.push_back({r.ms_median, front_error(r, metric)});
    }
    std::vector<size_t> front;
    for (size_t p : pareto_front(points)) front.push_back(index[p]);
    return front;
}

std::string psnr_plot_path(const std::string& flip_png) {
    const size_t dot = flip_png.rfind(".png");
    return dot == std::string::npos ? flip_png + "_psnr"
                                    : flip_png.substr(0, dot) + "_psnr" + flip_png.substr(dot);
}

nlohmann::json to_json(const std::vector<Row>& rows, int frames) {
    const std::string& primary = primary_display(rows);
    nlohmann::json j;
    const Row* any = rows.empty() ? nullptr : &rows.front();
    j["resolution"] = {any ? any->width : 0u, any ? any->height : 0u};
    j["frames"] = frames;
    j["frame_dt_s"] = 1.0 / 60.0;
    j["band_edges_deg"] = {0, 5, 10, 20, 30};
    j["flip"] = {{"metric",
                  "LDR-FLIP (Andersson et al. 2020), GPU, verified against NVIDIA's "
                  "vectors"},
                 {"flip_mean", "ppd from the display geometry, per pixel and axis"},
                 {"flip_mean_67ppd", "67.02 ppd, the FLIP tool's default"}};
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
        const Row* t0 = find_row(rows, r.method, "temporal");
        const Row* t1 = find_row(rows, r.method, "temporal taa");
        if (t0 && t1) {
            m["temporal"] = {
                {"display", t0->display_name},
                {"frames", t0->frames},
                {"settled_from_frame", kSettledFrom},
                {"no_taa", temporal_json(*t0)},
                {"taa", temporal_json(*t1)},
                {"atd_settled_taa_ratio", number_or_null(t1->atd_settled / t0->atd_settled)},
                {"tflip_settled_taa_ratio", number_or_null(t1->tflip_settled / t0->tflip_settled)}};
        }
        j["methods"][r.method] = m;
    }
    j["variants"] = nlohmann::json::array();
    for (const auto& r : rows)
        if (r.error.empty()) j["variants"].push_back(row_json(r, primary));
    j["pareto_front"] = nlohmann::json::array();
    for (size_t i : pareto_rows(rows, FrontMetric::kFlip))
        j["pareto_front"].push_back(variant_label(rows[i], primary));
    j["pareto_front_psnr"] = nlohmann::json::array();
    for (size_t i : pareto_rows(rows, FrontMetric::kPsnr))
        j["pareto_front_psnr"].push_back(variant_label(rows[i], primary));
    return j;
}

namespace {

// What a foveated method could cost at best on this host and device: its G-buffer plus its
// shaded fraction of the full-rate method's time, no overhead of its own, against the full-rate
// frame of the same configuration. Rows without post passes and with a timed G-buffer only.
void print_cost_floors(std::FILE* out, const std::vector<Row>& rows) {
    bool header = false;
    for (const auto& r : rows) {
        if (!r.error.empty() || r.method.rfind("full", 0) == 0 || r.tag != "default" ||
            !(r.gbuffer_gpu_ms > 0))
            continue;
        const Row* full = find_row(rows, "full", r.tag, r.display_name);
        if (!full || !(full->ms_median > 0)) continue;
        if (!header) {
            std::fprintf(out,
                         "cost against full rate, and the floor at zero method overhead (G-buffer "
                         "+ shaded fraction x full-rate method):\n");
            header = true;
        }
        const double floor_ms = r.gbuffer_gpu_ms + r.shaded_fraction * full->method_gpu_ms;
        std::fprintf(out, "  %-10s %-18s %.3fx  floor %.3fx = (%.1f + %.1f%% x %.1f) / %.1f ms\n",
                     r.method.c_str(), r.display_name.c_str(), r.ms_median / full->ms_median,
                     floor_ms / full->ms_median, r.gbuffer_gpu_ms, 100.0 * r.shaded_fraction,
                     full->method_gpu_ms, full->ms_median);
    }
}

}  // namespace

void print_table(std::FILE* out, const std::vector<Row>& rows) {
    const std::string& primary = primary_display(rows);
    std::fprintf(out, "%-28s %7s %7s %6s %7s %7s %7s %7s %8s %7s %6s  %s\n", "variant", "ms med",
                 "ms p95", "shaded", "FLIP", "FLIP67", "PSNR", "fov dB", "ATD", "tFLIP", "skip",
                 "FLIP by band (0-5/5-10/10-20/20-30/>30 deg)");
    for (const auto& r : rows) {
        if (!r.error.empty()) {
            std::fprintf(out, "%-28s failed: %s\n", variant_label(r, primary).c_str(),
                         r.error.c_str());
            continue;
        }
        std::fprintf(out, "%-28s %7.1f %7.1f %5.1f%% %7.4f %7.4f %7s %7s %8.5f %7.4f %6.0f ",
                     variant_label(r, primary).c_str(), r.ms_median, r.ms_p95,
                     100.0 * r.shaded_fraction, r.flip_mean, r.flip_mean_67ppd,
                     fixed(r.psnr_db, 2).c_str(), fixed(r.psnr_fovea_db, 2).c_str(), r.atd, r.tflip,
                     r.skipped_tiles);
        for (double f : r.flip_bands) std::fprintf(out, " %6s", fixed(f, 4).c_str());
        std::fprintf(out, "\n");
    }
    print_cost_floors(out, rows);
    std::fprintf(out,
                 "FLIP: mean LDR-FLIP against the full-rate reference at the ppd each pixel is "
                 "seen at (FLIP67: at 67 ppd); PSNR pooled over the frames; ATD, tFLIP: between "
                 "consecutive back-projected frames\n");
}

bool write_csv(const std::string& path, const std::vector<Row>& rows,
               const std::vector<std::string>& header_lines) {
    std::ofstream csv(path);
    for (const auto& l : header_lines) csv << "# " << l << "\n";
    csv << "method,tag,display,width,height,settings,frames,ms_median,ms_p95,method_gpu_ms,"
           "shaded_fraction,flip_mean,flip_mean_67ppd";
    const auto bands = [&](const char* prefix) {
        for (int b = 0; b < vk::kBandCount; ++b) csv << "," << prefix << vk::band_name(b);
    };
    bands("flip_");
    bands("flip67_");
    bands("ppd_");
    csv << ",psnr_db,psnr_fovea_db";
    bands("psnr_");
    bands("ssim_");
    csv << ",atd,atd_settled,atd_cut,tflip,tflip_settled,tflip_cut,flip_gpu_ms,skipped_tiles,"
           "reused_tiles,pareto_flip,pareto_psnr,gbuffer_gpu_ms\n";
    const std::vector<size_t> front = pareto_rows(rows, FrontMetric::kFlip);
    const std::vector<size_t> front_psnr = pareto_rows(rows, FrontMetric::kPsnr);
    for (size_t i = 0; i < rows.size(); ++i) {
        const Row& r = rows[i];
        if (!r.error.empty()) continue;
        csv << r.method << "," << r.tag << "," << r.display_name << "," << r.width << ","
            << r.height << ",\"" << r.settings << "\"," << r.frames << "," << r.ms_median << ","
            << r.ms_p95 << "," << r.method_gpu_ms << "," << r.shaded_fraction << "," << r.flip_mean
            << "," << r.flip_mean_67ppd;
        for (double v : r.flip_bands) csv << "," << v;
        for (double v : r.flip_bands_67ppd) csv << "," << v;
        for (double v : r.band_ppd) csv << "," << v;
        csv << "," << r.psnr_db << "," << r.psnr_fovea_db;
        for (double v : r.psnr_bands_pooled) csv << "," << v;
        for (double v : r.ssim_bands) csv << "," << v;
        csv << "," << r.atd << "," << r.atd_settled << "," << r.atd_cut << "," << r.tflip << ","
            << r.tflip_settled << "," << r.tflip_cut << "," << r.flip_gpu_ms << ","
            << r.skipped_tiles << "," << r.reused_tiles << ","
            << (std::count(front.begin(), front.end(), i) ? 1 : 0) << ","
            << (std::count(front_psnr.begin(), front_psnr.end(), i) ? 1 : 0) << ","
            << r.gbuffer_gpu_ms << "\n";
    }
    return bool(csv);
}

namespace {

bool write_plot(const std::string& path, const std::vector<Row>& rows, FrontMetric metric) {
    const std::string& primary = primary_display(rows);
    static const record::Rgb kColours[] = {{31, 119, 180}, {255, 127, 14},  {44, 160, 44},
                                           {214, 39, 40},  {148, 103, 189}, {140, 86, 75}};
    const auto value = [&](const Row& r) {
        return metric == FrontMetric::kFlip ? r.flip_mean : r.psnr_db;
    };
    double x_hi = 0, y_lo = 1e9, y_hi = -1e9;
    const Row* full = find_row(rows, "full", "default", primary);
    std::map<std::string, std::pair<std::vector<double>, std::vector<double>>> by_method;
    for (const auto& r : rows) {
        if (r.method.rfind("full", 0) == 0 || !r.error.empty() || r.display_name != primary ||
            is_temporal(r) || !std::isfinite(value(r)))
            continue;
        by_method[r.method].first.push_back(r.ms_median);
        by_method[r.method].second.push_back(value(r));
        x_hi = std::max(x_hi, r.ms_median);
        y_lo = std::min(y_lo, value(r));
        y_hi = std::max(y_hi, value(r));
    }
    if (full) x_hi = std::max(x_hi, full->ms_median);
    if (const Row* fwd = find_row(rows, "full-forward", "default", primary))
        x_hi = std::max(x_hi, fwd->ms_median);
    if (by_method.empty()) y_lo = 0, y_hi = 1;
    const bool flip = metric == FrontMetric::kFlip;
    record::Plot plot(
        900, 560, std::string(flip ? "time against mean FLIP, " : "time against PSNR, ") + primary,
        "ms per frame (median)",
        flip ? "mean LDR-FLIP at the display's ppd (lower is better)"
             : "PSNR pooled over frames, dB (higher is better)");
    plot.set_x(0.0, x_hi * 1.08);
    if (flip) {
        const double pad = 0.05 * std::max(y_hi - y_lo, 1e-3);
        plot.set_y(std::max(0.0, y_lo - pad), y_hi + pad);
    } else {
        plot.set_y(std::floor(y_lo - 1.0), std::ceil(y_hi + 1.0));
    }
    std::vector<double> fx, fy;
    for (size_t i : pareto_rows(rows, metric)) {
        fx.push_back(rows[i].ms_median);
        fy.push_back(value(rows[i]));
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
    if (const Row* fwd = find_row(rows, "full-forward", "default", primary))
        plot.vline(fwd->ms_median, {200, 120, 0}, "full rate, forward");
    return bool(plot.finish().save_png(path));
}

}  // namespace

bool write_plots(const std::string& flip_path, const std::string& psnr_path,
                 const std::vector<Row>& rows) {
    const bool a = write_plot(flip_path, rows, FrontMetric::kFlip);
    const bool b = write_plot(psnr_path, rows, FrontMetric::kPsnr);
    return a && b;
}

bool write_summary(const std::string& path, const std::vector<Row>& rows,
                   const std::vector<std::string>& header_lines, const nlohmann::json& bench,
                   const std::string& flip_png, const std::string& psnr_png) {
    const std::string& primary = primary_display(rows);
    std::ofstream md(path);
    md << "Generated by `tools/bench_summary.sh` (`fovea bench`); do not edit by hand.\n\n";
    for (const auto& l : header_lines) md << "- " << l << "\n";
    md << "\nTimes are wall-clock per frame (rasterized G-buffer + method + post, submit to "
          "done) on lavapipe. Errors are against the full-rate reference with the same post chain "
          "on the same frames, pooled over the frames: **FLIP** is the mean LDR-FLIP (Andersson "
          "et al. 2020, computed on the device and verified against NVIDIA's own vectors) at the "
          "pixels per degree each pixel is seen at on this display (FLIP67: at the FLIP tool's 67 "
          "ppd, to compare with published figures); **PSNR** comes from the squared errors of "
          "every pixel of every frame, one log, no cap. ATD is Patney's average temporal "
          "difference and tFLIP the mean FLIP between consecutive frames, the previous one "
          "back-projected with the G-buffer motion and the frame's jitter.\n\n";
    md << "| variant | display | settings | ms median | ms p95 | shaded | FLIP | FLIP67 | FLIP "
          "0-5deg | FLIP >30deg | PSNR dB | fovea PSNR dB | SSIM >30deg | ATD | tFLIP | "
          "skipped / reused tiles |\n";
    md << "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& r : rows) {
        if (!r.error.empty() || is_temporal(r)) continue;
        md << "| " << variant_label(r, primary) << " | " << r.display_name << " | " << r.settings
           << " | " << fixed(r.ms_median, 1) << " | " << fixed(r.ms_p95, 1) << " | "
           << fixed(100.0 * r.shaded_fraction, 1) << "% | " << fixed(r.flip_mean, 4) << " | "
           << fixed(r.flip_mean_67ppd, 4) << " | " << fixed(r.flip_bands[0], 4) << " | "
           << fixed(r.flip_bands[vk::kBandCount - 1], 4) << " | " << fixed(r.psnr_db, 2) << " | "
           << fixed(r.psnr_fovea_db, 2) << " | " << fixed(r.ssim_bands[vk::kBandCount - 1], 3)
           << " | " << fixed(r.atd, 5) << " | " << fixed(r.tflip, 4) << " | "
           << fixed(r.skipped_tiles, 0) << " / " << fixed(r.reused_tiles, 0) << " |\n";
    }
    const auto front = [&](FrontMetric m, const char* what) {
        md << "\n**Pareto front on " << what << "** (" << primary
           << ", ms/frame; no cheaper variant has a lower error):\n\n";
        for (size_t i : pareto_rows(rows, m))
            md << "1. " << variant_label(rows[i], primary) << ": " << fixed(rows[i].ms_median, 1)
               << " ms, FLIP " << fixed(rows[i].flip_mean, 4) << ", PSNR "
               << fixed(rows[i].psnr_db, 2) << " dB, shaded "
               << fixed(100.0 * rows[i].shaded_fraction, 1) << "%\n";
    };
    front(FrontMetric::kFlip, "mean FLIP");
    front(FrontMetric::kPsnr, "pooled PSNR");
    if (const Row* full = find_row(rows, "full", "default", primary))
        md << "\nFull rate for comparison: " << fixed(full->ms_median, 1)
           << " ms; one GPU FLIP evaluation of a frame: " << fixed(full->flip_gpu_ms, 1)
           << " ms.\n";
    md << "\n![time against mean FLIP](" << flip_png << ")\n\n![time against PSNR](" << psnr_png
       << ")\n";
    bool temporal_header = false;
    for (const auto& [name, m] : bench["methods"].items()) {
        if (!m.contains("temporal")) continue;
        const auto& t = m["temporal"];
        if (!temporal_header) {
            md << "\n**Temporal stability** (" << t["display"].get<std::string>() << ", "
               << t["frames"].get<int>() << " frames from a camera cut; cut: frame pairs 1-"
               << kSettledFrom - 1 << ", settled: from frame " << kSettledFrom
               << "; Patney 2016 reports TAA lowering ATD by an order of magnitude):\n\n"
               << "| method | ATD cut | ATD settled | ATD cut, TAA | ATD settled, TAA | TAA/no-TAA "
                  "settled ATD | tFLIP cut | tFLIP settled | tFLIP cut, TAA | tFLIP settled, TAA "
                  "|\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
            temporal_header = true;
        }
        md << "| " << name << " | " << json_fixed(t["no_taa"]["atd_cut"], 5) << " | "
           << json_fixed(t["no_taa"]["atd_settled"], 5) << " | "
           << json_fixed(t["taa"]["atd_cut"], 5) << " | " << json_fixed(t["taa"]["atd_settled"], 5)
           << " | " << json_fixed(t["atd_settled_taa_ratio"], 2) << " | "
           << json_fixed(t["no_taa"]["tflip_cut"], 4) << " | "
           << json_fixed(t["no_taa"]["tflip_settled"], 4) << " | "
           << json_fixed(t["taa"]["tflip_cut"], 4) << " | "
           << json_fixed(t["taa"]["tflip_settled"], 4) << " |\n";
    }
    if (bench["methods"].contains("cps") && bench["methods"]["cps"].contains("saccade_recovery")) {
        const auto& s = bench["methods"]["cps"]["saccade_recovery"];
        md << "\n**Saccade recovery, measured** (cps + TAA on the GPU, " << s["display"].dump()
           << ", a " << s["jump_deg"].dump()
           << " deg gaze jump on a still camera): " << s["frames"].dump()
           << " frames with the saccade-aware alpha, " << s["frames_no_term"].dump()
           << " without (first frame within " << s["tolerance"].dump()
           << " of the never-jumped run).\n";
    }
    if (bench.contains("model")) {
        const auto& m = bench["model"]["cps"];
        md << "\n**Models, not measurements** (" << bench["model"]["source"].get<std::string>()
           << "): ATD cps " << json_fixed(m["atd_no_taa"], 5) << ", cps + TAA "
           << json_fixed(m["atd"], 5) << ", full + TAA " << json_fixed(m["atd_full_taa"], 5)
           << "; saccade recovery " << m["saccade_recovery_frames"].dump() << " frames ("
           << m["saccade_recovery_frames_no_term"].dump() << " without the saccade term).\n";
    }
    return bool(md);
}

}  // namespace fovea::bench
