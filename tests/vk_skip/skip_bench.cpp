// vk_skip_bench: what method "cps" skipping saves on the demo scene and what it costs in error.
// Renders the same frames with "full" (the reference), cps with cps.skip=0 and cps with
// skipping, for a still camera (fixed gaze, the shading's lights keep moving) and for the demo
// camera path (scripted gaze trace with saccades), and prints per configuration the shaded
// fraction, the method's GPU time (timestamps) and wall time per frame (medians), the tile
// counters and the PSNR of the tone-mapped frame against the reference (fovea and whole frame).
//   vk_skip_bench [--width 1920 --height 1080 --frames 8 --dt 0.25 --jitter 8]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "fovea/demo/demo.hpp"
#include "fovea/vk/device.hpp"
#include "fovea/vk/foveator.hpp"

using namespace fovea;

namespace {

struct Row {
    std::string label;
    std::vector<double> gpu_ms, wall_ms;
    double shaded = 0, skipped = 0, reused = 0, background = 0, flat = 0;
    demo::ErrorPool errors;  // PSNR pooled over the frames
    int frames = 0;
};

}  // namespace

int main(int argc, char** argv) {
    uint32_t width = 1920, height = 1080, jitter = 8;
    int frames = 8;
    double dt = 0.25;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string k = argv[i];
        const char* v = argv[i + 1];
        if (k == "--width")
            width = uint32_t(std::atoi(v));
        else if (k == "--height")
            height = uint32_t(std::atoi(v));
        else if (k == "--frames")
            frames = std::atoi(v);
        else if (k == "--dt")
            dt = std::atof(v);
        else if (k == "--jitter")
            jitter = uint32_t(std::atoi(v));
        else {
            std::fprintf(stderr, "unknown option %s\n", k.c_str());
            return 2;
        }
    }
    vk::DeviceOptions dopt;
    auto device = vk::Device::create_headless(dopt);
    if (!device) {
        std::fprintf(stderr, "no Vulkan device: %s\n", device.error().message.c_str());
        return 1;
    }
    const vk::EyeDisplay display =
        vk::EyeDisplay::from_fov(width, height, vk::EyeDisplay::desktop_1080p().fov_h_deg,
                                 vk::EyeDisplay::desktop_1080p().fov_v_deg);
    struct Config {
        std::string label, method;
        std::vector<std::string> options;
    };
    const std::vector<Config> configs = {
        {"full", "full", {}}, {"cps skip=0", "cps", {"cps.skip=0"}}, {"cps skip=1", "cps", {}}};
    std::vector<vk::Foveator> foveators;
    for (const Config& c : configs) {
        vk::FoveatorConfig fc;
        fc.extent = {width, height};
        fc.display = display;
        fc.method = c.method;
        fc.options = c.options;
        fc.jitter_length = jitter;
        fc.shading_glsl = demo::shading_glsl();
        auto f = vk::Foveator::create(*device, fc);
        if (!f) {
            std::fprintf(stderr, "%s: %s\n", c.label.c_str(), f.error().message.c_str());
            return 1;
        }
        foveators.push_back(std::move(*f));
    }
    demo::SceneRenderer scene(*device);
    const demo::GazeTrace trace = demo::GazeTrace::scripted(frames * dt + 1.0, 7, display);
    const float foveal_deg = vk::AcuityParams{}.foveal_radius_deg;

    for (const bool still : {true, false}) {
        std::vector<Row> rows(configs.size());
        for (size_t k = 0; k < rows.size(); ++k) rows[k].label = configs[k].label;
        for (int i = 0; i < frames; ++i) {
            const double t = i * dt;
            const demo::Camera cam = demo::camera_at(still ? 0.0 : t, display);
            const demo::Camera prev = still ? cam : demo::camera_at(t - 1.0 / 60.0, display);
            vk::FrameInputs in;
            in.gaze = still ? vk::GazeState{} : trace.at(t);
            if (still) in.gaze.x = 0.45f, in.gaze.y = 0.55f;
            in.camera_pos = cam.pos;
            in.radians_per_pixel = 2.f * cam.tan_y / float(height);
            in.time_s = t;
            in.camera_cut = i == 0;
            demo::Rgb8 reference;
            for (size_t k = 0; k < configs.size(); ++k) {
                vk::Foveator& f = foveators[k];
                const auto j = f.jitter(uint64_t(i));
                const double wall = f.render_blocking(uint64_t(i), in, [&](VkCommandBuffer cmd) {
                    scene.begin_frame();
                    scene.record(cmd, f.gbuffer(), demo::SceneKind::kDemo, cam, prev, t,
                                 {0, 0, 1, 1}, j);
                });
                const vk::FrameStats s = f.stats();
                const demo::Rgb8 img = demo::tonemap(device->read_image(f.output()), width, height);
                if (k == 0) reference = img;
                Row& r = rows[k];
                r.errors.add(img, reference,
                             demo::band_labels(width, height, display, s.gaze, foveal_deg));
                r.gpu_ms.push_back(s.method_gpu_ms);
                r.wall_ms.push_back(wall);
                r.shaded += s.shaded_fraction / frames;
                r.skipped += double(s.skipped_tiles) / frames;
                r.reused += double(s.reused_tiles) / frames;
                r.background += double(s.background_tiles) / frames;
                r.flat += double(s.flat_tiles) / frames;
                std::printf(
                    "%s frame %d %-11s %6.1f ms gpu %6.1f ms wall, shaded %.3f, skipped "
                    "%u reused %u background %u flat %u\n",
                    still ? "still" : "path", i, configs[k].label.c_str(), s.method_gpu_ms, wall,
                    s.shaded_fraction, s.skipped_tiles, s.reused_tiles, s.background_tiles,
                    s.flat_tiles);
                std::fflush(stdout);
            }
        }
        std::printf(
            "\n%s camera, %ux%u, %d frames, jitter %u (means over frames, PSNR pooled over "
            "them; ms medians)\n",
            still ? "still" : "moving", width, height, frames, jitter);
        std::printf("%-11s %9s %9s %8s %8s %8s %8s %8s %10s %10s\n", "config", "gpu_ms", "wall_ms",
                    "shaded", "skipped", "reused", "bg", "flat", "fovea_dB", "frame_dB");
        for (Row& r : rows)
            std::printf("%-11s %9.1f %9.1f %8.3f %8.1f %8.1f %8.1f %8.1f %10.2f %10.2f\n",
                        r.label.c_str(), demo::median(r.gpu_ms), demo::median(r.wall_ms), r.shaded,
                        r.skipped, r.reused, r.background, r.flat, r.errors.figures().psnr_fovea_db,
                        r.errors.figures().psnr_db);
        std::printf("\n");
    }
    return 0;
}
