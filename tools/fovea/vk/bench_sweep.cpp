#include "bench_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <set>

#include "bench_analysis.hpp"
#include "bench_flip.hpp"
#include "fovea/vk/foveator.hpp"

namespace fovea::bench {
namespace {

constexpr double kFrameDt = 1.0 / 60.0;  // display rate: motion vectors span one frame
constexpr uint64_t kGazeSeed = 7;        // the demo's scripted trace
// The temporal runs: long enough for kSettledFrom plus 6 settled frame pairs.
constexpr int kTemporalFrames = kSettledFrom + 6;

std::string join(const std::vector<std::string>& v, const char* sep) {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : sep) + x;
    return s;
}

std::string display_name(const vk::EyeDisplay& d, const char* what) {
    return std::string(what) + " " + std::to_string(d.width_px) + "x" + std::to_string(d.height_px);
}

// The keys of a configuration this method (or its post chain) reads: acuity is shared, options
// are prefixed by the method or pass name ("kfr.sigma", "taa.alpha").
std::string settings_for(const Config& c, const std::string& method) {
    std::vector<std::string> keys = c.acuity;
    for (const auto& kv : c.options) {
        const std::string prefix = kv.substr(0, kv.find('.'));
        const bool layers = prefix == "layers" && method == "forward-layers";  // path 2's method
        if (prefix == method || layers || std::count(c.post.begin(), c.post.end(), prefix))
            keys.push_back(kv);
    }
    keys.push_back("post=" + (c.post.empty() ? std::string("none") : join(c.post, "+")));
    return join(keys, " ");
}

// Gaze: the scripted trace from two frames before its first saccade after 1 s, so even the
// quick run's few frames see the fovea jump (the landing point used in flight).
std::function<vk::GazeState(double)> saccade_window(const vk::EyeDisplay& display) {
    auto trace =
        std::make_shared<demo::GazeTrace>(demo::GazeTrace::scripted(30.0, kGazeSeed, display));
    double start = 1.0;
    for (const auto& s : trace->samples())
        if (s.t_s >= 1.0 && s.gaze.in_saccade) {
            start = s.t_s - 2.0 * kFrameDt;
            break;
        }
    return [trace, start](double t) { return trace->at(start + t); };
}

}  // namespace

bool apply_acuity_setting(vk::AcuityParams& p, const std::string& key_value) {
    const auto eq = key_value.find('=');
    if (eq == std::string::npos) return false;
    const std::string key = key_value.substr(0, eq), value = key_value.substr(eq + 1);
    char* end = nullptr;
    const double v = std::strtod(value.c_str(), &end);
    if (value.empty() || *end != '\0' || !std::isfinite(v)) return false;
    if (key == "acuity.mar_slope")
        p.mar_slope = float(v);
    else if (key == "acuity.mar_omega0")
        p.mar_omega0 = float(v);
    else if (key == "acuity.foveal_radius_deg")
        p.foveal_radius_deg = float(v);
    else if (key == "acuity.transition_deg")
        p.transition_deg = float(v);
    else if (key == "acuity.max_rate")
        p.max_rate = float(v);
    else
        return false;
    return true;
}

std::vector<Config> sweep_configs(const SweepOptions& o) {
    std::vector<std::string> all;
    for (const auto& m : o.methods.empty() ? vk::Foveator::methods() : o.methods)
        if (m != "full") all.push_back(m);
    const auto only = [&](std::vector<std::string> wanted) {
        std::erase_if(wanted,
                      [&](const std::string& m) { return !std::count(all.begin(), all.end(), m); });
        return wanted;
    };
    vk::EyeDisplay desktop = vk::EyeDisplay::desktop_1080p();
    std::string desktop_name = display_name(desktop, "desktop");
    const bool presets = o.width == 0 && !o.scene_display;
    if (o.scene_display) {
        desktop = *o.scene_display;
        desktop_name = display_name(desktop, "scene");
    } else if (o.width > 0) {  // tests: a small display with the desktop's field of view
        desktop = vk::EyeDisplay::from_fov(o.width, o.height, desktop.fov_h_deg, desktop.fov_v_deg);
        desktop_name = display_name(desktop, "small");
    }
    std::vector<Config> c;
    const auto add = [&](std::string tag, const vk::EyeDisplay& d, const std::string& dname,
                         std::vector<std::string> acuity, std::vector<std::string> options,
                         std::vector<std::string> post, std::vector<std::string> methods) {
        if (methods.empty()) return;
        options.insert(options.end(), o.extra_options.begin(), o.extra_options.end());
        c.push_back({std::move(tag), dname, d, std::move(acuity), std::move(options),
                     std::move(post), std::move(methods)});
    };
    add("default", desktop, desktop_name, {}, {}, {}, all);
    add("taa", desktop, desktop_name, {}, {}, {"taa"}, all);
    // Settled and camera-cut temporal figures need kTemporalFrames; the quick sweep runs them on
    // the desktop's field of view at half resolution to stay within two minutes.
    const auto add_temporal = [&] {
        if (!o.temporal) return;
        vk::EyeDisplay d = desktop;
        std::string name = desktop_name;
        if (o.quick && o.width == 0) {
            d = vk::EyeDisplay::from_fov(desktop.width_px / 2, desktop.height_px / 2,
                                         desktop.fov_h_deg, desktop.fov_v_deg);
            name = display_name(d, "half-desktop");
        }
        add("temporal", d, name, {}, {}, {}, all);
        c.back().frames = kTemporalFrames;
        add("temporal taa", d, name, {}, {}, {"taa"}, all);
        c.back().frames = kTemporalFrames;
    };
    if (o.quick) {
        add_temporal();
        return c;
    }
    add("taa+contrast", desktop, desktop_name, {}, {}, {"taa", "contrast"}, all);
    add("m=0.034", desktop, desktop_name, {"acuity.mar_slope=0.034"}, {}, {},
        only({"cps", "layers", "forward-layers"}));
    add("fovea 7.5deg", desktop, desktop_name, {"acuity.foveal_radius_deg=7.5"}, {}, {},
        only({"cps"}));
    add("gentle rate", desktop, desktop_name, {"acuity.transition_deg=10", "acuity.max_rate=2"}, {},
        {}, only({"cps"}));
    add("sweep A", desktop, desktop_name, {},
        {"kfr.sigma=1.6", "kfr.alpha=3", "adaptive.omega_p=0.05", "layers.count=2"}, {},
        only({"kfr", "adaptive", "layers", "forward-layers"}));
    add("sweep B", desktop, desktop_name, {},
        {"kfr.sigma=2.2", "kfr.alpha=5", "adaptive.omega_p=0.01", "layers.half_rate=1"}, {},
        only({"kfr", "adaptive", "layers", "forward-layers"}));
    if (presets) {
        // Guenter's study monitor (V* = 59 cm, W* = 51 cm, D* = 1920): pure §4.3 layers at
        // quality B, every layer every frame and outer layers at half rate (the ≤ 1/8 target).
        const vk::EyeDisplay study =
            vk::EyeDisplay::from_size(1920, 1080, 0.51, 0.51 * 9 / 16, 0.59);
        const std::string study_name = display_name(study, "guenter-study");
        add("guenter B", study, study_name, {"acuity.mar_slope=0.022"}, {"layers.fovea_deg=0"}, {},
            only({"layers"}));
        add("guenter B half", study, study_name, {"acuity.mar_slope=0.022"},
            {"layers.fovea_deg=0", "layers.half_rate=1"}, {}, only({"layers"}));
    }
    if (o.hmd && presets) {
        const vk::EyeDisplay hmd = vk::EyeDisplay::hmd_eye();
        const std::string hmd_name = display_name(hmd, "hmd-eye");
        add("default", hmd, hmd_name, {}, {}, {}, all);
        add("taa", hmd, hmd_name, {}, {}, {"taa"}, all);
    }
    add_temporal();
    return c;
}

namespace {

double mean_where(const std::vector<std::pair<int, double>>& v, int from, int to) {
    std::vector<double> x;
    for (const auto& [frame, value] : v)
        if (frame >= from && frame < to) x.push_back(value);
    return finite_mean(x);
}

}  // namespace

Result<std::vector<Row>> run_sweep(
    const vk::Device& device, const std::vector<Config>& configs, int frames,
    const std::function<void(int, int, const std::string&)>& progress, const FrameRunner& runner) {
    int total = 0, done = 0;
    for (const auto& c : configs)
        total += int(c.methods.size() + 1) * (c.frames ? c.frames : frames);
    std::vector<Row> rows;
    std::set<std::string> references;  // one full-rate row per display, post chain and length
    std::unique_ptr<BenchFlip> flip;
    std::string flip_display;
    for (const auto& c : configs) {
        const int n_frames = c.frames ? c.frames : frames;
        demo::RunOptions ro;
        ro.display = c.display;
        for (const auto& kv : c.acuity)
            if (!apply_acuity_setting(ro.acuity, kv)) return make_error("bad acuity setting " + kv);
        ro.methods = c.methods;
        ro.post_chain = c.post;
        ro.options = c.options;
        ro.frames = n_frames;
        ro.frame_dt_s = kFrameDt;
        ro.gaze = saccade_window(c.display);
        const uint32_t w = c.display.width_px, h = c.display.height_px;
        const size_t n = c.methods.size() + 1;
        if (!flip || flip_display != c.display_name) {
            flip.reset();  // one display's buffers at a time
            auto created = BenchFlip::create(device, c.display);
            if (!created) return created.error();
            flip = std::move(*created);
            flip_display = c.display_name;
        }
        flip->begin(n);
        std::vector<float> motion;
        demo::BandLabels labels;
        std::vector<std::vector<float>> previous(n), previous_8bit(n);
        std::vector<std::vector<std::pair<int, double>>> atd(n);
        std::vector<std::vector<double>> atd_8bit(n);
        std::vector<double> skipped(n, 0.0), reused(n, 0.0);
        std::vector<std::string> names{"full"};
        names.insert(names.end(), c.methods.begin(), c.methods.end());
        ro.on_frame = [&](size_t k, int frame, const vk::Foveator& f, const demo::Rgb8& img) {
            if (k >= n) return;  // a runner breaking the contract; reported below
            // "full" renders first in every frame and always fills a full-resolution motion image.
            if (k == 0) {
                // The deferred path's G-buffer, or the host's own targets (scene reference).
                const vk::ImageRef& m = f.config().path == vk::IntegrationPath::kDeferred
                                            ? f.gbuffer()[vk::GBufferImage::kMotion]
                                            : f.host_targets().motion;
                motion = decode_rg16f(device.read_image(m));
                // G-buffer motion runs from the unjittered pixel centre to the jittered sample's
                // previous position; the displayed pixel centres flow by motion + jitter, which
                // is what back-projecting the previous frame must follow (else every frame is
                // compared half a pixel off, a floor TAA cannot lower).
                const auto j = f.jitter(f.stats().frame_index);
                for (size_t i = 0; i + 1 < motion.size(); i += 2) {
                    motion[i] += j[0];
                    motion[i + 1] += j[1];
                }
                labels =
                    demo::band_labels(w, h, c.display, f.stats().gaze, ro.acuity.foveal_radius_deg);
            }
            flip->add_frame(k, frame, f.output(), labels, motion, names[k].rfind("full", 0) == 0);
            std::vector<float> luma = luminance_rgba16f(device.read_image(f.output()), w, h);
            std::vector<float> luma_8bit = luminance(img.rgb, w, h);
            if (frame > 0 && !previous[k].empty()) {
                atd[k].emplace_back(frame, temporal_difference(previous[k], luma, motion, w, h));
                atd_8bit[k].push_back(
                    temporal_difference(previous_8bit[k], luma_8bit, motion, w, h));
            }
            previous[k] = std::move(luma);
            previous_8bit[k] = std::move(luma_8bit);
            const vk::FrameStats st = f.stats();
            skipped[k] += st.skipped_tiles;
            reused[k] += st.reused_tiles;
            if (progress) progress(++done, total, c.tag + " " + c.display_name + " " + names[k]);
        };
        auto results = runner ? runner(ro) : demo::run(device, ro);
        if (!results) return results.error();
        if (results->size() != n)
            return make_error("configuration " + c.tag + ": " + std::to_string(results->size()) +
                              " results for " + std::to_string(n) + " methods");
        for (size_t k = 0; k < results->size(); ++k) {
            const demo::MethodResult& r = (*results)[k];
            // References ("full", the scene's "full-forward"): one row per display, post chain
            // and frame count.
            if (r.name.rfind("full", 0) == 0 &&
                !references
                     .insert(c.display_name + "|" + join(c.post, "+") + "|" +
                             std::to_string(n_frames) + "|" + r.name)
                     .second)
                continue;
            Row row;
            row.method = r.name;
            row.tag = c.tag;
            row.display_name = c.display_name;
            row.settings = settings_for(c, r.name);
            row.width = w;
            row.height = h;
            row.error = r.error;
            if (r.error.empty()) {
                row.frames = int(r.ms.size());
                row.ms_median = r.ms_median;
                row.ms_p95 = percentile(r.ms, 95.0);
                row.method_gpu_ms = r.method_gpu_ms;
                row.gbuffer_gpu_ms = r.gbuffer_gpu_ms;
                row.shaded_fraction = r.shaded_fraction;
                const demo::ErrorFigures& e = r.error_figures;
                row.psnr_db = e.psnr_db;
                row.psnr_fovea_db = e.psnr_fovea_db;
                row.psnr_bands_pooled = e.psnr_bands_db;
                row.ssim_bands = e.ssim_bands;
                const FlipSums& fs = flip->sums(k);
                double flip_sum = 0, flip67_sum = 0, pixels = 0;
                for (int b = 0; b < vk::kBandCount; ++b) {
                    row.flip_bands[b] = fs.display.mean(b);
                    row.flip_bands_67ppd[b] = fs.tool.mean(b);
                    row.band_ppd[b] = fs.ppd.mean(b);
                    flip_sum += fs.display.sum(b);
                    flip67_sum += fs.tool.sum(b);
                    pixels += fs.display.count(b);
                }
                row.flip_mean = pixels > 0 ? flip_sum / pixels : NAN;
                row.flip_mean_67ppd = pixels > 0 ? flip67_sum / pixels : NAN;
                row.flip_gpu_ms = demo::median(fs.gpu_ms);
                std::vector<double> atd_all;
                for (const auto& a : atd[k]) atd_all.push_back(a.second);
                row.atd = finite_mean(atd_all);
                row.atd_8bit = finite_mean(atd_8bit[k]);
                row.atd_cut = mean_where(atd[k], 1, kSettledFrom);
                row.atd_settled = mean_where(atd[k], kSettledFrom, n_frames);
                row.tflip = mean_where(fs.temporal, 1, n_frames);
                row.tflip_cut = mean_where(fs.temporal, 1, kSettledFrom);
                row.tflip_settled = mean_where(fs.temporal, kSettledFrom, n_frames);
                row.skipped_tiles = row.frames > 0 ? skipped[k] / row.frames : 0.0;
                row.reused_tiles = row.frames > 0 ? reused[k] / row.frames : 0.0;
            }
            rows.push_back(std::move(row));
        }
    }
    return rows;
}

}  // namespace fovea::bench
