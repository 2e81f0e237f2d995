// `fovea bench [--quick] [--json]`: every foveation method on the demo scene's camera path and
// gaze trace against the full-rate reference of the same frames, at 1920x1080: median time per
// frame, shaded fraction, foveal PSNR and per-band PSNR/SSIM. Ratios are within one run.
// --json prints exactly one JSON object on stdout; the table goes to stderr then. Writes a CSV.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "command.hpp"
#include "fovea/demo/demo.hpp"
#include "fovea/vk/foveator.hpp"
#include "post/bench_metrics.hpp"

namespace fovea::cli {
namespace {

struct BenchOptions {
    bool quick = false;
    bool json = false;
    int frames = 0;  // 0: 3 with --quick, 16 otherwise
    std::vector<std::string> methods;  // empty: every registered method
    std::string csv = "fovea_bench.csv";
};

nlohmann::json number_or_null(double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

int run_bench(const BenchOptions& o) {
    vk::DeviceOptions dopt;
    dopt.log = [](vk::LogLevel l, const std::string& m) {
        if (l >= vk::LogLevel::kWarning) std::fprintf(stderr, "vk: %s\n", m.c_str());
    };
    auto device = vk::Device::create_headless(dopt);
    if (!device) {
        std::fprintf(stderr, "fovea bench: %s\n", device.error().message.c_str());
        return 1;
    }
    demo::RunOptions ro;
    ro.display = vk::EyeDisplay::desktop_1080p();
    ro.methods = o.methods.empty() ? vk::Foveator::methods() : o.methods;
    ro.frames = o.frames > 0 ? o.frames : (o.quick ? 3 : 16);
    ro.frame_dt_s = o.quick ? 0.4 : 0.1;
    FILE* table = o.json ? stderr : stdout;
    ro.progress = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
    auto results = demo::run(*device, ro);
    if (!results) {
        std::fprintf(stderr, "fovea bench: %s\n", results.error().message.c_str());
        return 1;
    }
    const double full_ms = (*results)[0].ms_median;
    nlohmann::json j;
    j["resolution"] = {ro.display.width_px, ro.display.height_px};
    j["frames"] = ro.frames;
    j["methods"] = nlohmann::json::object();
    std::ofstream csv(o.csv);
    csv << "method,ms_per_frame,ratio_to_full,shaded_fraction,method_gpu_ms,psnr_fovea_db";
    for (int b = 0; b < vk::kBandCount; ++b) csv << ",psnr_" << vk::band_name(b);
    for (int b = 0; b < vk::kBandCount; ++b) csv << ",ssim_" << vk::band_name(b);
    csv << "\n";
    std::fprintf(table, "device %s, %ux%u, %d frames (medians; PSNR capped at 100 dB)\n",
                 device->name().c_str(), ro.display.width_px, ro.display.height_px, ro.frames);
    std::fprintf(table, "%-10s %10s %7s %8s %9s  %s\n", "method", "ms/frame", "ratio", "shaded",
                 "fovea dB", "PSNR dB by band 0-5/5-10/10-20/20-30/>30 deg");
    for (const auto& r : *results) {
        if (!r.error.empty()) {
            std::fprintf(stderr, "fovea bench: method %s skipped: %s\n", r.name.c_str(),
                         r.error.c_str());
            continue;
        }
        const auto& e = r.error_figures;
        nlohmann::json m;
        m["ms_per_frame"] = r.ms_median;
        m["shaded_fraction"] = r.shaded_fraction;
        m["psnr_fovea_db"] = number_or_null(e.psnr_fovea_db);
        m["psnr_bands_db"] = nlohmann::json::array();
        m["ssim_bands"] = nlohmann::json::array();
        for (int b = 0; b < vk::kBandCount; ++b) {
            m["psnr_bands_db"].push_back(number_or_null(e.psnr_bands_db[b]));
            m["ssim_bands"].push_back(number_or_null(e.ssim_bands[b]));
        }
        j["methods"][r.name] = m;
        std::fprintf(table, "%-10s %10.1f %7.3f %7.1f%% %9.2f ", r.name.c_str(), r.ms_median,
                     r.ms_median / full_ms, 100.0 * r.shaded_fraction, e.psnr_fovea_db);
        for (double p : e.psnr_bands_db) std::fprintf(table, " %6.2f", p);
        std::fprintf(table, "\n");
        csv << r.name << "," << r.ms_median << "," << r.ms_median / full_ms << ","
            << r.shaded_fraction << "," << r.method_gpu_ms << "," << e.psnr_fovea_db;
        for (double p : e.psnr_bands_db) csv << "," << p;
        for (double s : e.ssim_bands) csv << "," << s;
        csv << "\n";
    }
    // Issue 7 (TAA + enhancement), added by the TAA engineer: stability and saccade figures from
    // the reference-model experiments (post/bench_metrics.hpp); taa_enhance_ms measured here as
    // the cps frame time with post chain {"taa", "contrast"} minus without.
    if (j["methods"].contains("cps")) {
        const vk::post::ModelPostFigures pf = vk::post::model_post_figures();
        auto& cps = j["methods"]["cps"];
        cps["atd"] = pf.atd;
        cps["atd_no_taa"] = pf.atd_no_taa;
        cps["atd_full_taa"] = pf.atd_full_taa;
        cps["atd_source"] = "model";
        cps["saccade_recovery_frames"] = pf.saccade_recovery_frames;
        cps["saccade_recovery_frames_no_term"] = pf.saccade_recovery_frames_no_term;
        demo::RunOptions po = ro;
        po.methods = {"cps"};
        po.post_chain = {"taa", "contrast"};
        auto post = demo::run(*device, po);
        if (post && post->size() > 1 && (*post)[1].error.empty()) {
            cps["taa_enhance_ms"] = (*post)[1].ms_median - cps["ms_per_frame"].get<double>();
            if ((*results)[0].method_gpu_ms > 0.0)
                cps["taa_enhance_fraction_of_full"] =
                    cps["taa_enhance_ms"].get<double>() / (*results)[0].method_gpu_ms;
        }
        std::fprintf(table, "cps: atd %.5f (no TAA %.5f), saccade recovery %d frames (%d without "
                     "the term), taa+contrast %.1f ms\n", pf.atd, pf.atd_no_taa,
                     pf.saccade_recovery_frames, pf.saccade_recovery_frames_no_term,
                     cps.value("taa_enhance_ms", 0.0));
    }
    std::fprintf(table, "CSV: %s\n", o.csv.c_str());
    if (o.json) std::printf("%s\n", j.dump().c_str());
    return 0;
}

void setup(CLI::App& app) {
    auto o = std::make_shared<BenchOptions>();
    app.add_flag("--quick", o->quick, "3 frames (under 2 minutes on lavapipe, 2 cores)");
    app.add_flag("--json", o->json, "Print one JSON object on stdout (table to stderr)");
    app.add_option("--frames", o->frames, "Frames per method (default 3 quick, 16 full)")
        ->check(CLI::Range(1, 10000));
    app.add_option("--methods", o->methods, "Methods to run (default: all registered)");
    app.add_option("--csv", o->csv, "CSV output path");
    app.callback([o] {
        if (const int rc = run_bench(*o); rc != 0) throw CLI::RuntimeError(rc);
    });
}

const Command kBench{"bench", "Benchmark every foveation method against the full-rate reference",
                     &setup};

}  // namespace
}  // namespace fovea::cli
