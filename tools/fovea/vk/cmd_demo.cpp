// `fovea demo`: renders the demo scene headless (lavapipe or any Vulkan device) with a foveation
// method and the full-rate reference of the same frames, gaze from the running fovead (ring) or
// --trace FILE (else a scripted trace with saccades). Writes PNGs of the foveated frame, the
// reference and the rate map, prints time per frame, shaded fraction and error figures.
// With live gaze it reports its render-side latency hops to fovead (fovea_frame_latency) at the
// end and every second, so `fovea latency` shows them next to the device hops.
#include <chrono>
#include <cstdio>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

#include "command.hpp"
#include "fovea/client.hpp"
#include "fovea/demo/demo.hpp"

namespace fovea::cli {
namespace {

struct DemoOptions {
    std::string method = "cps";
    int frames = 8;
    std::string trace;
    bool hmd = false;
    std::string out = "fovea_demo_out";
    std::string scene = "demo";
    std::vector<std::string> post;
    std::vector<std::string> options;  // FoveatorConfig::options, "key=value"
    double dt = 0.1;
    bool validation = false;
};

int64_t now_ns() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return int64_t{ts.tv_sec} * 1000000000 + ts.tv_nsec;
}

// The live-gaze demo's frame events for the SDK's render hops. The demo renders blocking and
// headless, so the events it can observe are:
//   read + frame begin: the runner asks for frame i's gaze; the newest record is read and the
//                       frame starts with it (read -> frame begin is therefore < 1 us here);
//   submitted:          the foveated method's blocking render returned (vkQueueSubmit plus the
//                       fence wait: the blocking path exposes no earlier moment; the interval
//                       includes the full-rate reference rendered first for comparison);
//   presented:          the frame's PNGs are written (headless: the frame is ready to show).
// The gaze's age at frame begin, measured by the SDK, is the age the fovea is widened by.
class DemoLatency {
public:
    DemoLatency(std::shared_ptr<Client> client, std::string instance, size_t foveated_method)
        : client_(std::move(client)), instance_(std::move(instance)), method_(foveated_method) {}

    vk::GazeState frame_gaze() {
        const auto r = client_->latest();
        if (r) hops_.gaze_read(*r, now_ns());
        const int64_t t = now_ns();
        const int64_t age_ns = hops_.frame_begin(r ? &*r : nullptr, t);
        open_ = true;
        if (!r) return vk::GazeState{};
        vk::GazeState g = vk::GazeState::from_record(*r, t);
        g.age_s = static_cast<float>(static_cast<double>(age_ns) * 1e-9);
        return g;
    }
    void rendered(size_t method) {
        if (method == method_ && open_) hops_.submitted();
        submitted_ = method == method_ && open_;
    }
    void shown() {
        if (submitted_) hops_.presented();
        submitted_ = open_ = false;
        if (now_ns() - last_report_ns_ >= 1'000'000'000) report();
    }
    void report() {
        last_report_ns_ = now_ns();
        try {
            hops_.report(instance_, 1000);
        } catch (const ClientError& e) {
            if (!warned_) std::fprintf(stderr, "fovea demo: latency report: %s\n", e.what());
            warned_ = true;
        }
    }
    void print() const {
        const auto c = hops_.counters();
        std::printf("render hops (sdk, us)        count      p50      p99      max\n");
        for (int h = 0; h < FOVEA_RENDER_HOP_COUNT; ++h) {
            const auto s = hops_.hop(static_cast<fovea_render_hop>(h));
            if (s.count == 0) continue;
            std::printf("%-24s %9llu %8.1f %8.1f %8.1f\n", fovea_render_hop_name(h),
                        static_cast<unsigned long long>(s.count), s.p50_ns / 1e3, s.p99_ns / 1e3,
                        s.max_ns / 1e3);
        }
        std::printf("frames %llu, stale gaze (> %.0f ms at frame begin, or none) %llu\n",
                    static_cast<unsigned long long>(c.frames), c.stale_threshold_ns / 1e6,
                    static_cast<unsigned long long>(c.stale_frames));
    }

private:
    std::shared_ptr<Client> client_;
    std::string instance_;
    size_t method_;
    FrameLatency hops_;
    bool open_ = false, submitted_ = false, warned_ = false;
    int64_t last_report_ns_ = now_ns();
};

void print_results(const std::vector<demo::MethodResult>& results, const char* label) {
    const double full_ms = results[0].ms_median;
    std::printf("%s\n%-10s %10s %8s %9s %10s", label, "method", "ms/frame", "ratio", "shaded",
                "fovea dB");
    for (int b = 0; b < vk::kBandCount; ++b) std::printf(" %8s", vk::band_name(b));
    std::printf("  (PSNR dB / SSIM per eccentricity band, degrees)\n");
    for (const auto& r : results) {
        if (!r.error.empty()) {
            std::printf("%-10s error: %s\n", r.name.c_str(), r.error.c_str());
            continue;
        }
        std::printf("%-10s %10.1f %8.3f %8.1f%% %10.2f", r.name.c_str(), r.ms_median,
                    r.ms_median / full_ms, 100.0 * r.shaded_fraction,
                    r.error_figures.psnr_fovea_db);
        for (double p : r.error_figures.psnr_bands_db) std::printf(" %8.2f", p);
        std::printf("\n%-10s %41s", "", "SSIM");
        for (double s : r.error_figures.ssim_bands) std::printf(" %8.4f", s);
        std::printf("\n");
    }
}

int run_demo(const DemoOptions& o) {
    vk::DeviceOptions dopt;
    dopt.validation = o.validation;
    dopt.log = [](vk::LogLevel l, const std::string& m) {
        if (l >= vk::LogLevel::kWarning) std::fprintf(stderr, "vk: %s\n", m.c_str());
    };
    auto device = vk::Device::create_headless(dopt);
    if (!device) {
        std::fprintf(stderr, "fovea demo: %s\n", device.error().message.c_str());
        return 1;
    }
    demo::RunOptions ro;
    ro.methods = {"full", o.method};
    ro.frames = o.frames;
    ro.frame_dt_s = o.dt;
    ro.png_dir = o.out;
    ro.post_chain = o.post;
    ro.options = o.options;
    ro.scene = o.scene == "zoneplate" ? demo::SceneKind::kZonePlate
               : o.scene == "grating" ? demo::SceneKind::kGrating
                                      : demo::SceneKind::kDemo;
    std::shared_ptr<DemoLatency> latency;
    ro.progress = [&latency](const std::string& line) {
        std::fprintf(stderr, "%s\n", line.c_str());
        if (latency) latency->shown();  // called once the frame's PNGs are written
    };

    // Gaze: --trace, else the live ring of a running fovead, else the scripted trace.
    std::shared_ptr<demo::GazeTrace> trace;
    std::shared_ptr<Client> client;
    if (!o.trace.empty()) {
        size_t dropped = 0;
        auto t = demo::GazeTrace::load(o.trace, &dropped);
        if (!t) {
            std::fprintf(stderr, "fovea demo: %s\n", t.error().message.c_str());
            return 1;
        }
        if (dropped)
            std::fprintf(stderr, "fovea demo: %zu malformed trace lines skipped\n", dropped);
        trace = std::make_shared<demo::GazeTrace>(std::move(*t));
        ro.gaze = [trace](double t_s) { return trace->at(t_s); };
        std::fprintf(stderr, "gaze: trace %s (%zu samples)\n", o.trace.c_str(),
                     trace->samples().size());
    } else {
        try {
            client = std::make_shared<Client>(global_options().instance);
            // the runner renders "full" first, then the foveated method (index 1 unless it is
            // "full" itself)
            latency = std::make_shared<DemoLatency>(client, global_options().instance,
                                                    o.method == "full" ? 0 : 1);
            ro.gaze = [latency](double) { return latency->frame_gaze(); };
            ro.on_frame = [latency](size_t method, int, const vk::Foveator&, const demo::Rgb8&) {
                latency->rendered(method);
            };
            std::fprintf(stderr, "gaze: live from fovead instance '%s'\n",
                         global_options().instance.c_str());
        } catch (const std::exception& e) {
            std::fprintf(stderr, "gaze: no running fovead (%s); using the scripted trace\n",
                         e.what());
        }
    }
    struct Preset {
        const char* label;
        vk::EyeDisplay display;
        float eye_offset;
        const char* prefix;
    };
    std::vector<Preset> presets;
    if (o.hmd) {
        presets.push_back({"HMD left eye 1440x1600", vk::EyeDisplay::hmd_eye(), -0.032f, "left"});
        presets.push_back({"HMD right eye 1440x1600", vk::EyeDisplay::hmd_eye(), 0.032f, "right"});
    } else {
        presets.push_back({"desktop 1920x1080", vk::EyeDisplay::desktop_1080p(), 0.f, "frame"});
    }
    std::printf("device: %s; method %s; %d frames\n", device->name().c_str(), o.method.c_str(),
                o.frames);
    for (const Preset& p : presets) {
        ro.display = p.display;
        ro.eye_offset_m = p.eye_offset;
        ro.png_prefix = p.prefix;
        auto r = demo::run(*device, ro);
        if (!r) {
            std::fprintf(stderr, "fovea demo: %s\n", r.error().message.c_str());
            return 1;
        }
        print_results(*r, p.label);
        if (!(*r)[1].error.empty()) return 1;
    }
    if (latency) {
        latency->report();
        latency->print();
    }
    std::printf("PNGs in %s/ (<prefix>_<frame>_<method>.png, _reference.png, _<method>_rate.png)\n",
                o.out.c_str());
    if (const uint64_t n = device->validation_errors(); n > 0) {
        std::fprintf(stderr, "fovea demo: %llu Vulkan validation errors\n",
                     static_cast<unsigned long long>(n));
        return 1;
    }
    return 0;
}

void setup(CLI::App& app) {
    auto o = std::make_shared<DemoOptions>();
    app.add_option("--method", o->method, "Foveation method (full, cps, layers, kfr, adaptive)");
    app.add_option("--frames,-n", o->frames, "Frames to render")->check(CLI::Range(1, 100000));
    app.add_option("--trace", o->trace, "Gaze trace CSV (t_s,x,y[,event,landing_x,landing_y,...])");
    app.add_flag("--hmd", o->hmd, "HMD preset: two eyes of 1440x1600 instead of 1920x1080");
    app.add_option("--out", o->out, "Directory for the PNGs");
    app.add_option("--scene", o->scene, "demo | zoneplate | grating")
        ->check(CLI::IsMember({"demo", "zoneplate", "grating"}));
    app.add_option("--option", o->options, "Method/pass option key=value (e.g. kfr.sigma=1.6)");
    app.add_option("--post", o->post, "Post passes after shading (e.g. taa contrast)");
    app.add_option("--dt", o->dt, "Seconds between rendered frames along the path")
        ->check(CLI::Range(0.001, 10.0));
    app.add_flag("--validation", o->validation,
                 "Vulkan validation layers on; any validation error fails the run");
    app.callback([o] {
        if (const int rc = run_demo(*o); rc != 0) throw CLI::RuntimeError(rc);
    });
}

const Command kDemo{
    "demo", "Render the foveated demo scene headless against the full-rate reference", &setup};

}  // namespace
}  // namespace fovea::cli
