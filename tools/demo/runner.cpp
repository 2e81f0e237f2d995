#include <cmath>
#include <cstdio>
#include <filesystem>

#include "fovea/demo/demo.hpp"

namespace fovea::demo {

Result<std::vector<MethodResult>> run(const vk::Device& device, const RunOptions& o) {
    vk::FoveatorConfig cfg;
    cfg.extent = {o.display.width_px, o.display.height_px};
    cfg.display = o.display;
    cfg.acuity = o.acuity;
    cfg.method = "full";
    cfg.post_chain = o.post_chain;
    cfg.options = o.options;
    cfg.shading_glsl = shading_glsl();
    auto fov = vk::Foveator::create(device, cfg);
    if (!fov) return fov.error();
    vk::Foveator& f = *fov;
    SceneRenderer scene(device);
    GazeTrace trace;
    auto gaze = o.gaze;
    if (!gaze) {
        trace = GazeTrace::scripted(o.frames * o.frame_dt_s + 1.0, 7, o.display);
        gaze = [&trace](double t) { return trace.at(t); };
    }
    if (o.scene != SceneKind::kDemo) {
        std::array<float, 64> host{};
        host[0] = 40.f;  // zone plate k
        host[1] = 60.f;  // grating cycles per plane unit
        host[2] = 2.f * target_camera(o.display).tan_x / o.display.width_px;
        f.set_host_params(host);
    }
    if (!o.png_dir.empty()) std::filesystem::create_directories(o.png_dir);

    std::vector<std::string> names{"full"};
    for (const auto& m : o.methods)
        if (m != "full") names.push_back(m);
    std::vector<MethodResult> results(names.size());
    std::vector<std::vector<double>> gpu_ms(names.size()), gbuffer_ms(names.size());
    std::vector<ErrorPool> errors(names.size());
    for (size_t k = 0; k < names.size(); ++k) {
        results[k].name = names[k];
        if (auto r = f.set_method(names[k]); !r) results[k].error = r.error().message;
    }
    if (!results[0].error.empty()) return make_error(results[0].error);
    const uint32_t w = cfg.extent.width, h = cfg.extent.height;

    auto render = [&](uint64_t index, double t, const vk::FrameInputs& in, const Camera& cam,
                      const Camera& prev) {
        std::vector<vk::ViewRequest> views = f.views(index, in);
        const bool full = f.needs_full_gbuffer();
        const auto jitter = f.jitter(index);
        return f.render_blocking(index, in, [&](VkCommandBuffer cmd) {
            scene.begin_frame();
            if (full) scene.record(cmd, f.gbuffer(), o.scene, cam, prev, t, {0, 0, 1, 1}, jitter);
            for (const auto& v : views)
                scene.record(cmd, v.gbuffer, o.scene, cam, prev, t, v.crop, v.jitter_px);
        });
    };

    for (int i = -1; i < o.frames; ++i) {  // frame -1 warms every method up, not measured
        const double t = std::max(i, 0) * o.frame_dt_s;
        const bool target = o.scene != SceneKind::kDemo;
        const Camera cam =
            target ? target_camera(o.display) : camera_at(t, o.display, o.eye_offset_m);
        const Camera prev = target ? cam : camera_at(t - 1.0 / 60.0, o.display, o.eye_offset_m);
        vk::FrameInputs in;
        in.gaze = gaze(t);
        in.camera_pos = cam.pos;
        in.radians_per_pixel = 2.f * cam.tan_y / static_cast<float>(h);
        in.time_s = t;
        in.camera_cut = i <= 0;
        Rgb8 reference;
        BandLabels labels;
        vk::ResolvedGaze resolved;
        std::string line;
        for (size_t k = 0; k < names.size(); ++k) {
            MethodResult& r = results[k];
            if (!r.error.empty()) continue;
            if (auto s = f.set_method(names[k]); !s) {
                r.error = s.error().message;
                continue;
            }
            const uint64_t index = static_cast<uint64_t>(i + 1);
            const double ms = render(index, t, in, cam, prev);
            if (i < 0) continue;
            const vk::FrameStats st = f.stats();
            resolved = st.gaze;
            r.ms.push_back(ms);
            gpu_ms[k].push_back(st.method_gpu_ms);
            gbuffer_ms[k].push_back(scene.gpu_ms());
            r.shaded_fraction += st.shaded_fraction / o.frames;
            r.skipped_tiles += static_cast<double>(st.skipped_tiles) / o.frames;
            r.reused_tiles += static_cast<double>(st.reused_tiles) / o.frames;
            const Rgb8 img = tonemap(device.read_image(f.output()), w, h);
            if (k == 0) {
                reference = img;
                labels = band_labels(w, h, o.display, st.gaze, o.acuity.foveal_radius_deg);
            }
            errors[k].add(img, reference, labels);
            if (o.on_frame) o.on_frame(k, i, f, img);
            if (!o.png_dir.empty()) {
                const std::string base =
                    o.png_dir + "/" + o.png_prefix + "_" + std::to_string(i) + "_" + names[k];
                write_png(base + ".png", img);
                if (k > 0)
                    write_png(base + "_rate.png", rate_map(device.read_image(f.rate()), w, h));
                else
                    write_png(
                        o.png_dir + "/" + o.png_prefix + "_" + std::to_string(i) + "_reference.png",
                        img);
            }
            char buf[224];
            std::snprintf(buf, sizeof(buf),
                          " %s %.0f ms (G-buffer %.0f, method %.0f) %.1f%% fovea "
                          "%.1f dB so far, skipped %u reused %u |",
                          names[k].c_str(), ms, gbuffer_ms[k].back(), st.method_gpu_ms,
                          100.0 * st.shaded_fraction, errors[k].figures().psnr_fovea_db,
                          st.skipped_tiles, st.reused_tiles);
            line += buf;
        }
        if (o.progress && i >= 0) {
            char head[96];
            std::snprintf(head, sizeof(head), "frame %d/%d gaze (%.0f, %.0f) px%s:", i + 1,
                          o.frames, resolved.x_px, resolved.y_px,
                          resolved.used_landing ? " [saccade landing]" : "");
            o.progress(head + line);
        }
    }
    for (size_t k = 0; k < names.size(); ++k) {
        MethodResult& r = results[k];
        if (!r.error.empty() || r.ms.empty()) continue;
        r.ms_median = median(r.ms);
        r.method_gpu_ms = median(gpu_ms[k]);
        r.gbuffer_gpu_ms = median(gbuffer_ms[k]);
        r.error_figures = errors[k].figures();
    }
    return results;
}

}  // namespace fovea::demo
