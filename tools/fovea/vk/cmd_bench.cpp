// `fovea bench [--quick] [--json]`: every foveation method and a sweep of their settings on the
// demo scene's camera path (display rate) and a gaze trace window with a saccade, against the
// full-rate reference of the same frames: ms/frame (median, p95), shaded fraction, mean LDR-FLIP
// (at the display's ppd and at 67 ppd, per eccentricity band, on the device), PSNR/SSIM pooled
// over frames per band, ATD and temporal FLIP (settled and after a camera cut), skipped tiles, and
// the saccade recovery of cps + TAA measured on the GPU. Writes a table, a CSV with a
// reproducibility header, PNGs of time against FLIP and against PSNR with their Pareto fronts
// and, with --summary, the Markdown the README embeds (tools/bench_summary.sh). Figures from CPU
// models are kept apart under "model". --json prints exactly one JSON object on stdout;
// everything else goes to stderr then. --scene FILE runs the same sweep on a glTF scene through
// the viewer's host code, its integration paths as the methods.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench_output.hpp"
#include "bench_recovery.hpp"
#include "bench_scene.hpp"
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
    bool validation = false;
    bool recovery = true;
    bool temporal = true;
    int frames = 0;                    // 0: 2 with --quick, 8 otherwise
    std::vector<std::string> methods;  // empty: every registered method
    std::vector<std::string> method_options;
    std::string csv = "fovea_bench.csv";
    std::string png = "fovea_bench.png";
    std::string summary;     // Markdown summary path; none when empty
    std::string resolution;  // hidden, for tests: "WxH" instead of the presets
    std::string scene;       // glTF scene file (TOML); empty: the demo scene
    std::string data_dir;    // replaces the scene file's data_dir
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
    so.temporal = o.temporal;
    so.methods = o.methods;
    so.extra_options = o.method_options;
    if (!o.resolution.empty() &&
        (std::sscanf(o.resolution.c_str(), "%ux%u", &so.width, &so.height) != 2 || so.width == 0 ||
         so.height == 0)) {
        std::fprintf(stderr, "fovea bench: --resolution wants WxH, got %s\n", o.resolution.c_str());
        return 1;
    }
    const int frames = o.frames > 0 ? o.frames : (o.quick ? 2 : 8);

    std::unique_ptr<bench::SceneBench> scene;
    std::optional<vk::Device> headless;
    if (!o.scene.empty()) {
        auto opened = bench::SceneBench::open(o.scene, o.data_dir, true, o.validation);
        if (!opened) {
            std::fprintf(stderr, "fovea bench: %s\n", opened.error().message.c_str());
            return 1;
        }
        scene = std::move(*opened);
        for (const auto& w : scene->warnings())
            std::fprintf(stderr, "fovea bench: warning: %s\n", w.c_str());
        so.scene_display = scene->display(so.width, so.height);
        if (so.methods.empty()) so.methods = bench::SceneBench::variants();
    } else {
        vk::DeviceOptions dopt;
        dopt.validation = o.validation;
        dopt.log = [](vk::LogLevel l, const std::string& m) {
            if (l >= vk::LogLevel::kWarning) std::fprintf(stderr, "vk: %s\n", m.c_str());
        };
        auto made = vk::Device::create_headless(dopt);
        if (!made) {
            std::fprintf(stderr, "fovea bench: %s\n", made.error().message.c_str());
            return 1;
        }
        headless.emplace(std::move(*made));
    }
    const vk::Device* device = scene ? &scene->device() : &*headless;
    FILE* table = o.json ? stderr : stdout;
    std::vector<bench::Config> configs = bench::sweep_configs(so);
    if (scene)
        for (auto& c : configs) c.methods = bench::SceneBench::with_references(c.methods);
    const std::string where =
        scene ? "the scene's camera path (" + scene->description() + ")" : "the demo camera path";
    const std::vector<std::string> header = {
        "date " + utc_now(),
        "device " + device->name() + "; driver " + driver_description(*device),
        "command " + o.command_line,
        "frames " + std::to_string(frames) + " per variant at 1/60 s along " + where +
            " (+1 warm-up; the temporal runs 16), fixed seeds: gaze trace 7 (window from its "
            "first saccade after 1 s), Halton(2,3) jitter" +
            (scene ? "" : ", scene in code"),
        std::to_string(configs.size()) +
            " configurations; errors against the full-rate "
            "reference with the same post chain; ms = wall time of the whole frame",
    };
    std::fprintf(table, "fovea bench: %s, %s\n", device->name().c_str(),
                 o.quick ? "quick sweep" : "full sweep");

    ProgressBar bar(!o.quick);
    bench::FrameRunner runner;
    if (scene) runner = [&](const demo::RunOptions& ro) { return scene->run(ro); };
    auto rows = bench::run_sweep(
        *device, configs, frames,
        [&](int done, int total, const std::string& what) { bar.update(done, total, what); },
        runner);
    if (!rows) {
        std::fprintf(stderr, "fovea bench: %s\n", rows.error().message.c_str());
        return 1;
    }
    bench::print_table(table, *rows);
    nlohmann::json j = bench::to_json(*rows, frames);
    j["header"] = header;
    if (o.recovery && !scene && j["methods"].contains("cps")) {
        bench::RecoveryOptions ro;
        ro.display = configs.front().display;  // the sweep's desktop (small in tests)
        if (o.quick && o.resolution.empty())
            ro.display = vk::EyeDisplay::from_fov(ro.display.width_px / 2, ro.display.height_px / 2,
                                                  ro.display.fov_h_deg, ro.display.fov_v_deg);
        auto rec = bench::measure_saccade_recovery(*device, ro);
        if (!rec) {
            std::fprintf(stderr, "fovea bench: saccade recovery: %s\n",
                         rec.error().message.c_str());
            return 1;
        }
        auto& cps = j["methods"]["cps"];
        cps["saccade_recovery_frames"] = rec->frames;
        cps["saccade_recovery_frames_no_term"] = rec->frames_no_term;
        cps["saccade_recovery"] = {
            {"source", "measured: cps + TAA on the GPU, still camera, demo scene"},
            {"display",
             std::to_string(ro.display.width_px) + "x" + std::to_string(ro.display.height_px)},
            {"jump_deg", ro.jump_deg},
            {"tolerance", ro.tolerance},
            {"max_frames", ro.max_frames},
            {"frames", rec->frames},
            {"frames_no_term", rec->frames_no_term},
            {"first_error", rec->first_error},
            {"first_error_no_term", rec->first_error_no_term}};
        std::fprintf(table,
                     "saccade recovery (measured, cps + TAA, %ux%u, %.0f deg jump): %d frames, "
                     "%d without the saccade term\n",
                     ro.display.width_px, ro.display.height_px, ro.jump_deg, rec->frames,
                     rec->frames_no_term);
    }
    // The reference-model experiments (post/bench_metrics.hpp) emulate cps on an analytic scene:
    // models, kept apart from the measured figures.
    if (o.model) {
        const vk::post::ModelPostFigures pf = vk::post::model_post_figures();
        j["model"] = {
            {"source",
             "CPU reference models (sdk/src/vk/post/stability_model.hpp, saccade_model.hpp): "
             "coarse pixel shading emulated on an analytic scene, not the GPU path"},
            {"cps",
             {{"atd", pf.atd},
              {"atd_no_taa", pf.atd_no_taa},
              {"atd_full_taa", pf.atd_full_taa},
              {"saccade_recovery_frames", pf.saccade_recovery_frames},
              {"saccade_recovery_frames_no_term", pf.saccade_recovery_frames_no_term}}}};
        std::fprintf(table,
                     "MODEL, not measured (CPU reference model of cps on an analytic scene): ATD "
                     "cps %.5f, cps + TAA %.5f, full + TAA %.5f; saccade recovery %d frames (%d "
                     "without the saccade term)\n",
                     pf.atd_no_taa, pf.atd, pf.atd_full_taa, pf.saccade_recovery_frames,
                     pf.saccade_recovery_frames_no_term);
    }
    std::fprintf(table, "Pareto front (ms/frame against mean FLIP):");
    for (const auto& label : j["pareto_front"])
        std::fprintf(table, " | %s", label.get<std::string>().c_str());
    std::fprintf(table, "\nPareto front (ms/frame against pooled PSNR):");
    for (const auto& label : j["pareto_front_psnr"])
        std::fprintf(table, " | %s", label.get<std::string>().c_str());
    std::fprintf(table, "\n");
    if (!bench::write_csv(o.csv, *rows, header))
        std::fprintf(stderr, "fovea bench: cannot write %s\n", o.csv.c_str());
    const std::string png_psnr = o.png.empty() ? "" : bench::psnr_plot_path(o.png);
    if (!o.png.empty() && !bench::write_plots(o.png, png_psnr, *rows))
        std::fprintf(stderr, "fovea bench: cannot write %s or %s\n", o.png.c_str(),
                     png_psnr.c_str());
    if (!o.summary.empty()) {
        const auto name = [](const std::string& p) { return p.substr(p.find_last_of('/') + 1); };
        if (!bench::write_summary(o.summary, *rows, header, j, name(o.png), name(png_psnr)))
            std::fprintf(stderr, "fovea bench: cannot write %s\n", o.summary.c_str());
    }
    std::fprintf(table, "CSV: %s, plots: %s %s%s%s\n", o.csv.c_str(), o.png.c_str(),
                 png_psnr.c_str(), o.summary.empty() ? "" : ", summary: ", o.summary.c_str());
    if (o.json) std::printf("%s\n", j.dump().c_str());
    if (const uint64_t n = scene ? scene->validation_errors() : device->validation_errors();
        n > 0) {
        std::fprintf(stderr, "fovea bench: %llu Vulkan validation errors\n",
                     static_cast<unsigned long long>(n));
        return 1;
    }
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
    app.add_flag("!--no-model", o->model, "Skip the CPU model figures under \"model\" (~10 s)");
    app.add_flag("!--no-recovery", o->recovery,
                 "Skip the saccade recovery measured on the GPU (cps + TAA)");
    app.add_flag("!--no-temporal", o->temporal,
                 "Skip the settled / camera-cut temporal runs (16 frames each)");
    app.add_flag("--validation", o->validation,
                 "Vulkan validation layers on; any validation error fails the run");
    app.add_option("--csv", o->csv, "CSV output path");
    app.add_option("--png", o->png,
                   "Plot of time against mean FLIP; the PSNR plot goes to NAME_psnr.png "
                   "(empty: none)");
    app.add_option("--summary", o->summary, "Markdown summary path (docs/bench/summary.md)");
    app.add_option("--scene", o->scene,
                   "glTF scene file (TOML, sdk/examples/gltf_viewer) instead of the demo scene: "
                   "its integration paths against its forward frame at full rate");
    app.add_option("--data-dir", o->data_dir, "Directory the scene's model files are relative to");
    app.add_option("--resolution", o->resolution, "WxH display instead of the presets")
        ->group("");  // hidden: tests run a tiny frame
    app.callback([o, &app] {
        o->command_line = "fovea bench";
        for (const auto* opt : app.get_options())
            if (opt->count() > 0 && !opt->get_lnames().empty())
                o->command_line +=
                    " --" + opt->get_lnames().front() +
                    (opt->get_expected_min() > 0 ? " " + opt->as<std::string>() : "");
        if (const int rc = run_bench(*o); rc != 0) throw CLI::RuntimeError(rc);
    });
}

const Command kBench{"bench",
                     "Benchmark every foveation method and its settings against the "
                     "full-rate reference: time against error",
                     &setup};

}  // namespace
}  // namespace fovea::cli
