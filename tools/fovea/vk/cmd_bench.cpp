// `fovea bench [--quick] [--json]`: every foveation method and a sweep of their settings on the
// demo scene's camera path (display rate) and a gaze trace window with a saccade, against the
// full-rate reference of the same frames: ms/frame (median, p95), shaded fraction, foveal PSNR,
// PSNR/SSIM per eccentricity band, ATD with and without TAA, skipped tiles. Writes a table, a
// CSV with a reproducibility header, a PNG of time against error with the Pareto front and,
// with --summary, the Markdown the README embeds (tools/bench_summary.sh). --json prints exactly
// one JSON object on stdout; everything else goes to stderr then.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench_output.hpp"
#include "bench_sweep.hpp"
#include "command.hpp"
#include "fovea/vk/foveator.hpp"
#include "post/bench_metrics.hpp"

namespace fovea::cli {
namespace {

struct BenchOptions {
    bool quick = false;
    bool json = false;
    bool no_hmd = false;
    bool model = true;
    int frames = 0;  // 0: 2 with --quick, 8 otherwise
    std::vector<std::string> methods;  // empty: every registered method
    std::vector<std::string> method_options;
    std::string csv = "fovea_bench.csv";
    std::string png = "fovea_bench.png";
    std::string summary;     // Markdown summary path; none when empty
    std::string resolution;  // hidden, for tests: "WxH" instead of the presets
    std::string command_line;
};

std::string utc_now() {
    const std::time_t t = std::time(nullptr);
    char buf[32];
    std::strftime(buf, sizeof(buf), "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
    return buf;
}

// Driver name and info (Mesa and LLVM versions on lavapipe) from Vulkan 1.2's driver properties.
std::string driver_description(const vk::Device& device) {
    VkPhysicalDeviceDriverProperties driver{};
    driver.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES;
    VkPhysicalDeviceProperties2 props{};
    props.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2;
    props.pNext = &driver;
    vkGetPhysicalDeviceProperties2(device.physical(), &props);
    const uint32_t v = props.properties.apiVersion;
    return std::string(driver.driverName) + " " + driver.driverInfo + ", Vulkan " +
           std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v)) +
           "." + std::to_string(VK_API_VERSION_PATCH(v));
}

// A one-line bar on stderr for the full run: done/total frames, the running variant, time left.
class ProgressBar {
public:
    explicit ProgressBar(bool enabled) : enabled_(enabled), start_(clock::now()) {}
    void update(int done, int total, const std::string& what) {
        if (!enabled_) return;
        const double elapsed = std::chrono::duration<double>(clock::now() - start_).count();
        const double left = done > 0 ? elapsed * (total - done) / done : 0.0;
        const int width = 30, filled = total > 0 ? width * done / total : width;
        std::fprintf(stderr, "\r[%s%s] %d/%d frames, %3.0f min left, %-40.40s",
                     std::string(filled, '#').c_str(), std::string(width - filled, '.').c_str(),
                     done, total, left / 60.0, what.c_str());
        if (done == total) std::fprintf(stderr, "\n");
        std::fflush(stderr);
    }

private:
    using clock = std::chrono::steady_clock;
    bool enabled_;
    clock::time_point start_;
};

int run_bench(const BenchOptions& o) {
    bench::SweepOptions so;
    so.quick = o.quick;
    so.hmd = !o.no_hmd;
    so.methods = o.methods;
    so.extra_options = o.method_options;
    if (!o.resolution.empty() &&
        (std::sscanf(o.resolution.c_str(), "%ux%u", &so.width, &so.height) != 2 || so.width == 0 ||
         so.height == 0)) {
        std::fprintf(stderr, "fovea bench: --resolution wants WxH, got %s\n", o.resolution.c_str());
        return 1;
    }
    const int frames = o.frames > 0 ? o.frames : (o.quick ? 2 : 8);

    vk::DeviceOptions dopt;
    dopt.log = [](vk::LogLevel l, const std::string& m) {
        if (l >= vk::LogLevel::kWarning) std::fprintf(stderr, "vk: %s\n", m.c_str());
    };
    auto device = vk::Device::create_headless(dopt);
    if (!device) {
        std::fprintf(stderr, "fovea bench: %s\n", device.error().message.c_str());
        return 1;
    }
    FILE* table = o.json ? stderr : stdout;
    const std::vector<bench::Config> configs = bench::sweep_configs(so);
    const std::vector<std::string> header = {
        "date " + utc_now(),
        "device " + device->name() + "; driver " + driver_description(*device),
        "command " + o.command_line,
        "frames " + std::to_string(frames) + " per variant at 1/60 s along the demo camera path "
            "(+1 warm-up), fixed seeds: gaze trace 7 (window from its first saccade after 1 s), "
            "Halton(2,3) jitter, scene in code",
        std::to_string(configs.size()) + " configurations; errors against the full-rate "
            "reference with the same post chain; ms = wall time of the whole frame",
    };
    std::fprintf(table, "fovea bench: %s, %s\n", device->name().c_str(),
                 o.quick ? "quick sweep" : "full sweep");

    ProgressBar bar(!o.quick);
    auto rows = bench::run_sweep(*device, configs, frames,
                                 [&](int done, int total, const std::string& what) {
                                     bar.update(done, total, what);
                                 });
    if (!rows) {
        std::fprintf(stderr, "fovea bench: %s\n", rows.error().message.c_str());
        return 1;
    }
    bench::print_table(table, *rows);
    nlohmann::json j = bench::to_json(*rows, frames);
    j["header"] = header;
    // Issue 7's saccade-recovery figures come from the reference-model experiments
    // (post/bench_metrics.hpp); the model's ATDs stay as extra keys next to the measured ones.
    if (o.model && j["methods"].contains("cps")) {
        const vk::post::ModelPostFigures pf = vk::post::model_post_figures();
        auto& cps = j["methods"]["cps"];
        cps["atd_model"] = pf.atd;
        cps["atd_no_taa_model"] = pf.atd_no_taa;
        cps["atd_full_taa_model"] = pf.atd_full_taa;
        cps["saccade_recovery_frames"] = pf.saccade_recovery_frames;
        cps["saccade_recovery_frames_no_term"] = pf.saccade_recovery_frames_no_term;
        cps["saccade_recovery_source"] = "model";
    }
    std::fprintf(table, "Pareto front (ms/frame against mean band PSNR):");
    for (const auto& label : j["pareto_front"]) std::fprintf(table, " | %s", label.get<std::string>().c_str());
    std::fprintf(table, "\n");
    if (!bench::write_csv(o.csv, *rows, header))
        std::fprintf(stderr, "fovea bench: cannot write %s\n", o.csv.c_str());
    if (!o.png.empty() && !bench::write_plot(o.png, *rows))
        std::fprintf(stderr, "fovea bench: cannot write %s\n", o.png.c_str());
    if (!o.summary.empty()) {
        const std::string png_name = o.png.substr(o.png.find_last_of('/') + 1);
        if (!bench::write_summary(o.summary, *rows, header, png_name))
            std::fprintf(stderr, "fovea bench: cannot write %s\n", o.summary.c_str());
    }
    std::fprintf(table, "CSV: %s, plot: %s%s%s\n", o.csv.c_str(), o.png.c_str(),
                 o.summary.empty() ? "" : ", summary: ", o.summary.c_str());
    if (o.json) std::printf("%s\n", j.dump().c_str());
    return 0;
}

void setup(CLI::App& app) {
    auto o = std::make_shared<BenchOptions>();
    app.add_flag("--quick", o->quick,
                 "Small sweep: default settings and TAA, 1920x1080, 2 frames (under 2 minutes)");
    app.add_flag("--json", o->json, "Print one JSON object on stdout (table to stderr)");
    app.add_option("--frames", o->frames, "Frames per variant (default 2 quick, 8 full)")
        ->check(CLI::Range(2, 10000));
    app.add_option("--methods", o->methods, "Methods to run (default: all registered)");
    app.add_option("--method-option", o->method_options,
                   "key=value added to every configuration's FoveatorConfig::options");
    app.add_flag("--no-hmd", o->no_hmd, "Full sweep without the HMD-eye preset");
    app.add_flag("!--no-model", o->model, "Skip the model-based saccade recovery figures (~10 s)");
    app.add_option("--csv", o->csv, "CSV output path");
    app.add_option("--png", o->png, "Plot of time against error (empty: none)");
    app.add_option("--summary", o->summary, "Markdown summary path (docs/bench/summary.md)");
    app.add_option("--resolution", o->resolution, "WxH display instead of the presets")
        ->group("");  // hidden: tests run a tiny frame
    app.callback([o, &app] {
        o->command_line = "fovea bench";
        for (const auto* opt : app.get_options())
            if (opt->count() > 0 && !opt->get_lnames().empty())
                o->command_line += " --" + opt->get_lnames().front() +
                                   (opt->get_expected_min() > 0 ? " " + opt->as<std::string>() : "");
        if (const int rc = run_bench(*o); rc != 0) throw CLI::RuntimeError(rc);
    });
}

const Command kBench{"bench", "Benchmark every foveation method and its settings against the "
                              "full-rate reference: time against error",
                     &setup};

}  // namespace
}  // namespace fovea::cli
