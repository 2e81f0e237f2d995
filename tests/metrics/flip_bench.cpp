// flip_bench: the GPU FLIP pass against a full-rate frame of the demo scene, interleaved round by
// round on the same device (lavapipe: the ratio is what carries across machines). Prints a table
// and writes a CSV. Target (issue 19): one FLIP compare at 1920x1080 <= 0.3x a full-rate frame.
// Besides wall and GPU-timestamp milliseconds it reports the process's CPU time (all threads, so
// lavapipe's workers) over the same calls: on a machine shared with other work, wall time grows
// with the contention and CPU time much less, so the CPU-time ratio is the steadier one.
//   flip_bench [--width 1920] [--height 1080] [--rounds 7] [--csv flip_bench.csv]
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "fovea/demo/demo.hpp"
#include "fovea/metrics/gpu_flip.hpp"
#include "fovea/vk/foveator.hpp"

using namespace fovea;

namespace {

double cpu_ms() {  // user + system time of every thread of this process
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    const auto ms = [](const timeval& t) { return t.tv_sec * 1e3 + t.tv_usec * 1e-3; };
    return ms(u.ru_utime) + ms(u.ru_stime);
}

}  // namespace

int main(int argc, char** argv) {
    uint32_t width = 1920, height = 1080;
    int rounds = 7;
    std::string csv_path = "flip_bench.csv";
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string k = argv[i], v = argv[i + 1];
        if (k == "--width")
            width = uint32_t(std::stoul(v));
        else if (k == "--height")
            height = uint32_t(std::stoul(v));
        else if (k == "--rounds")
            rounds = std::stoi(v);
        else if (k == "--csv")
            csv_path = v;
        else {
            std::fprintf(stderr, "flip_bench: unknown option %s\n", k.c_str());
            return 2;
        }
    }
    auto device = vk::Device::create_headless({});
    if (!device) {
        std::fprintf(stderr, "no Vulkan device: %s\n", device.error().message.c_str());
        return 1;
    }
    const vk::EyeDisplay desktop = vk::EyeDisplay::desktop_1080p();
    const vk::EyeDisplay display =
        vk::EyeDisplay::from_fov(width, height, desktop.fov_h_deg, desktop.fov_v_deg);
    vk::FoveatorConfig fc;
    fc.extent = {width, height};
    fc.display = display;
    fc.method = "full";
    fc.shading_glsl = demo::shading_glsl();
    auto f = vk::Foveator::create(*device, fc);
    if (!f) {
        std::fprintf(stderr, "%s\n", f.error().message.c_str());
        return 1;
    }
    auto flip = metrics::GpuFlip::create(
        *device, width, height,
        {metrics::display_ppd_field(display, width, height),
         metrics::PpdField::uniform(width, height, metrics::kFlipDefaultPpd)});
    if (!flip) {
        std::fprintf(stderr, "%s\n", flip.error().message.c_str());
        return 1;
    }
    demo::SceneRenderer scene(*device);
    struct Series {
        const char* name;
        std::vector<double> ms;
    };
    std::vector<Series> s = {{"full-rate frame (wall)", {}},
                             {"FLIP compare, display ppd (GPU)", {}},
                             {"  prepare", {}},
                             {"  horizontal", {}},
                             {"  vertical", {}},
                             {"FLIP compare, display ppd (wall)", {}},
                             {"FLIP compare, 67 ppd (GPU)", {}},
                             {"full-rate frame (CPU time)", {}},
                             {"FLIP compare, display ppd (CPU time)", {}},
                             {"FLIP compare, 67 ppd (CPU time)", {}}};
    for (int r = -1; r < rounds; ++r) {  // round -1 warms up
        const double t = 1.0 + 0.25 * std::max(r, 0);
        const demo::Camera cam = demo::camera_at(t, display),
                           prev = demo::camera_at(t - 1.0 / 60, display);
        vk::FrameInputs in;
        in.camera_pos = cam.pos;
        in.radians_per_pixel = 2.f * cam.tan_y / float(height);
        in.time_s = t;
        in.camera_cut = true;
        const uint64_t index = uint64_t(r + 1);
        const double frame_cpu0 = cpu_ms();
        const double frame_ms = f->render_blocking(index, in, [&](VkCommandBuffer cmd) {
            scene.begin_frame();
            scene.record(cmd, f->gbuffer(), demo::SceneKind::kDemo, cam, prev, t, {0, 0, 1, 1},
                         f->jitter(index));
        });
        const double frame_cpu = cpu_ms() - frame_cpu0;
        device->submit_and_wait([&](VkCommandBuffer cmd) {
            flip->record_reference(cmd, f->output(), metrics::FlipInput::kDemoDisplay, 0);
            flip->record_reference(cmd, f->output(), metrics::FlipInput::kDemoDisplay, 1);
        });
        const auto t0 = std::chrono::steady_clock::now();
        const double cpu0 = cpu_ms();
        device->submit_and_wait([&](VkCommandBuffer cmd) {
            flip->record_compare(cmd, f->output(), metrics::FlipInput::kDemoDisplay, 0);
        });
        const double wall =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count();
        const double cpu = cpu_ms() - cpu0;
        const metrics::FlipPassTimes p = flip->compare_gpu_times();
        const double cpu67_0 = cpu_ms();
        device->submit_and_wait([&](VkCommandBuffer cmd) {
            flip->record_compare(cmd, f->output(), metrics::FlipInput::kDemoDisplay, 1);
        });
        const double cpu67 = cpu_ms() - cpu67_0;
        const double tool = flip->compare_gpu_ms();
        if (r < 0) continue;
        const double v[] = {frame_ms,      p.total_ms, p.prepare_ms, p.horizontal_ms,
                            p.vertical_ms, wall,       tool,         frame_cpu,
                            cpu,           cpu67};
        for (size_t k = 0; k < s.size(); ++k) s[k].ms.push_back(v[k]);
        std::fprintf(stderr, "round %d: frame %.1f ms, FLIP %.1f ms (67 ppd %.1f)\n", r, frame_ms,
                     p.total_ms, tool);
    }
    const double frame = demo::median(s[0].ms), frame_cpu = demo::median(s[7].ms);
    std::printf("FLIP on %s, %ux%u, %d rounds interleaved (medians)\n", device->name().c_str(),
                width, height, rounds);
    std::printf("%-38s %10s %12s\n", "what", "ms", "x full frame");
    std::ofstream csv(csv_path);
    csv << "# flip_bench " << width << "x" << height << " rounds " << rounds << " on "
        << device->name() << "\nwhat,ms_median,ratio_to_full_frame\n";
    for (size_t k = 0; k < s.size(); ++k) {  // CPU-time rows against the frame's CPU time
        const double m = demo::median(s[k].ms), ratio = m / (k < 7 ? frame : frame_cpu);
        std::printf("%-38s %10.1f %12.3f\n", s[k].name, m, ratio);
        csv << "\"" << s[k].name << "\"," << m << "," << ratio << "\n";
    }
    std::printf("target: FLIP compare (GPU) <= 0.3 x full-rate frame: %s\nCSV: %s\n",
                demo::median(s[1].ms) <= 0.3 * frame ? "met" : "NOT met", csv_path.c_str());
    return 0;
}
