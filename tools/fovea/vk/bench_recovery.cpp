#include "bench_recovery.hpp"

#include <cmath>
#include <numbers>
#include <vector>

#include "bench_analysis.hpp"
#include "fovea/demo/demo.hpp"
#include "fovea/vk/foveator.hpp"

namespace fovea::bench {

Result<RecoveryResult> measure_saccade_recovery(const vk::Device& device,
                                                const RecoveryOptions& o) {
    const vk::EyeDisplay& d = o.display;
    const uint32_t w = d.width_px, h = d.height_px;
    // A and B sit symmetrically about the centre on the horizontal axis, jump_deg apart (the
    // per-axis angle of the acuity model, so eccentricity_deg(A, B) = jump_deg).
    const double s = 0.5 * w / std::tan(0.5 * double(d.fov_h_deg) * std::numbers::pi / 180.0);
    const double half = s * std::tan(0.5 * double(o.jump_deg) * std::numbers::pi / 180.0);
    const float ax = float((0.5 * w - half) / w), bx = float((0.5 * w + half) / w);
    // Runs: gaze at B throughout; A then B with the saccade term; A then B without it.
    const std::vector<std::vector<std::string>> options = {{}, {}, {"taa.saccade=0"}};
    std::vector<vk::Foveator> runs;
    for (const auto& opt : options) {
        vk::FoveatorConfig fc;
        fc.extent = {w, h};
        fc.display = d;
        fc.method = "cps";
        fc.post_chain = {"taa"};
        fc.options = opt;
        fc.shading_glsl = demo::shading_glsl();
        auto f = vk::Foveator::create(device, fc);
        if (!f) return f.error();
        runs.push_back(std::move(*f));
    }
    demo::SceneRenderer scene(device);
    const double t0 = 2.0;  // a still camera (and scene time) on the demo path
    const demo::Camera cam = demo::camera_at(t0, d);
    const float radius = vk::AcuityParams{}.foveal_radius_deg;
    std::vector<size_t> region;
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x)
            if (vk::eccentricity_deg(d, x + 0.5f, y + 0.5f, bx * w, 0.5f * h) < radius)
                region.push_back(size_t(y) * w + x);
    if (region.empty()) return make_error("saccade recovery: empty foveal region");
    RecoveryResult r;
    r.frames = r.frames_no_term = o.max_frames + 1;
    bool done[2] = {false, false};
    for (int i = 0; i < o.settle_frames + o.max_frames; ++i) {
        const bool jumped = i >= o.settle_frames;
        std::vector<float> luma[3];
        for (size_t k = 0; k < runs.size(); ++k) {
            vk::FrameInputs in;
            in.gaze.x = (k == 0 || jumped) ? bx : ax;
            in.gaze.y = 0.5f;
            in.camera_pos = cam.pos;
            in.radians_per_pixel = 2.f * cam.tan_y / float(h);
            in.time_s = t0;
            in.camera_cut = i == 0;
            vk::Foveator& f = runs[k];
            const auto j = f.jitter(uint64_t(i));
            f.render_blocking(uint64_t(i), in, [&](VkCommandBuffer cmd) {
                scene.begin_frame();
                scene.record(cmd, f.gbuffer(), demo::SceneKind::kDemo, cam, cam, t0, {0, 0, 1, 1},
                             j);
            });
            if (jumped) luma[k] = luminance_rgba16f(device.read_image(f.output()), w, h);
        }
        if (!jumped) continue;
        const int after = i - o.settle_frames + 1;  // 1 = the jump frame
        for (int v = 0; v < 2; ++v) {
            double err = 0;
            for (size_t p : region) err += std::fabs(double(luma[v + 1][p]) - luma[0][p]);
            err /= double(region.size());
            if (after == 1) (v == 0 ? r.first_error : r.first_error_no_term) = err;
            if (!done[v] && err <= o.tolerance) {
                (v == 0 ? r.frames : r.frames_no_term) = after;
                done[v] = true;
            }
        }
        if (done[0] && done[1]) break;
    }
    return r;
}

}  // namespace fovea::bench
