// `fovea noise-bench`: cost of Tariq 2022's Gabor-noise enhancement against impulses per kernel
// (12, 16, 32, 64; Tariq §6.3, Fig. 15). Two implementations: the CPU reference
// (sdk/src/vk/post/enhance_model.cpp; parameter estimation and synthesis, --size² zone plate)
// and the GPU post pass "noise" (sdk/src/vk/post/noise.cpp; GPU timestamps around the pass at
// --gpu-resolution, desktop display, S_t from the acuity model) with the gaze at the centre
// ("foveated") and off screen (S_t = 1 everywhere: every pixel gets noise). Medians of
// --repeats runs. Writes a CSV and a PNG plot (time against impulses).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_easy_font.h>
#include <stb/stb_image_write.h>

#include "command.hpp"
#include "fovea/vk/acuity.hpp"
#include "fovea/vk/device.hpp"
#include "frame_uniforms.hpp"
#include "gpu.hpp"
#include "post/enhance_model.hpp"
#include "post_pass.hpp"

namespace fovea::vk {
std::unique_ptr<PostPass> make_noise_pass();
}

namespace fovea::cli {
namespace {

namespace post = fovea::vk::post;

struct NoiseBenchOptions {
    int size = 256;
    int repeats = 3;
    std::string csv = "noise_bench.csv";
    std::string png = "noise_bench.png";
    std::string gpu_resolution = "1920x1080";
    bool gpu = true;
};

struct Row {
    int impulses;
    double param_ms;
    double synth_ms;
    double gpu_foveated_ms = -1;  // < 0: not measured
    double gpu_periphery_ms = -1;
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// A plot with a white background: lines between points, axes, labels via stb_easy_font.
class Canvas {
public:
    Canvas(int w, int h) : w_(w), h_(h), px_(std::size_t(w) * h * 3, 255) {}
    void dot(int x, int y, const unsigned char* c) {
        if (x < 0 || y < 0 || x >= w_ || y >= h_) return;
        std::copy(c, c + 3, px_.begin() + (std::ptrdiff_t(y) * w_ + x) * 3);
    }
    void line(int x0, int y0, int x1, int y1, const unsigned char* c, int thick = 1) {
        const int n = std::max(std::abs(x1 - x0), std::abs(y1 - y0)) + 1;
        for (int i = 0; i <= n; ++i) {
            const int x = x0 + (x1 - x0) * i / n;
            const int y = y0 + (y1 - y0) * i / n;
            for (int t = -thick / 2; t <= thick / 2; ++t) {
                dot(x + t, y, c);
                dot(x, y + t, c);
            }
        }
    }
    void text(int x, int y, const std::string& s, const unsigned char* c) {
        static char buf[60000];
        const int quads =
            stb_easy_font_print(0, 0, const_cast<char*>(s.c_str()), nullptr, buf, sizeof(buf));
        const float* v = reinterpret_cast<const float*>(buf);
        for (int q = 0; q < quads; ++q) {  // 4 vertices of 16 bytes (x, y, z, colour)
            const float* a = v + q * 16;
            for (int yy = int(a[1]); yy < int(a[9]); ++yy)
                for (int xx = int(a[0]); xx < int(a[8]); ++xx) dot(x + xx, y + yy, c);
        }
    }
    bool write(const std::string& path) const {
        return stbi_write_png(path.c_str(), w_, h_, 3, px_.data(), w_ * 3) != 0;
    }

private:
    int w_, h_;
    std::vector<unsigned char> px_;
};

bool write_plot(const std::vector<Row>& rows, const std::string& path, int size,
                const std::string& gpu_resolution) {
    const int w = 560, h = 380, left = 60, right = 20, top = 40, bottom = 50;
    Canvas c(w, h);
    const unsigned char black[3] = {0, 0, 0}, blue[3] = {30, 90, 200}, red[3] = {200, 50, 40},
                        green[3] = {40, 150, 60}, orange[3] = {230, 140, 20},
                        grey[3] = {210, 210, 210};
    double ymax = 0;
    for (const Row& r : rows)
        ymax = std::max({ymax, r.param_ms + r.synth_ms, r.gpu_foveated_ms, r.gpu_periphery_ms});
    ymax *= 1.1;
    auto X = [&](int imp) { return left + int((imp - 0) * double(w - left - right) / 68.0); };
    auto Y = [&](double ms) { return h - bottom - int(ms / ymax * (h - top - bottom)); };
    for (int k = 1; k <= 4; ++k)
        c.line(left, Y(ymax * k / 4.4), w - right, Y(ymax * k / 4.4), grey);
    c.line(left, h - bottom, w - right, h - bottom, black);
    c.line(left, top, left, h - bottom, black);
    for (const Row& r : rows) {
        c.line(X(r.impulses), h - bottom, X(r.impulses), h - bottom + 4, black);
        c.text(X(r.impulses) - 6, h - bottom + 8, std::to_string(r.impulses), black);
    }
    for (int k = 0; k <= 4; ++k) {
        char b[32];
        std::snprintf(b, sizeof b, "%.0f", ymax * k / 4.4);
        c.text(8, Y(ymax * k / 4.4) - 3, b, black);
    }
    auto series = [&](auto value, const unsigned char* col) {
        for (std::size_t i = 0; i + 1 < rows.size(); ++i)
            c.line(X(rows[i].impulses), Y(value(rows[i])), X(rows[i + 1].impulses),
                   Y(value(rows[i + 1])), col, 3);
    };
    series([](const Row& r) { return r.param_ms + r.synth_ms; }, black);
    series([](const Row& r) { return r.synth_ms; }, red);
    series([](const Row& r) { return r.param_ms; }, blue);
    const bool gpu = !rows.empty() && rows.front().gpu_foveated_ms >= 0;
    if (gpu) {
        series([](const Row& r) { return r.gpu_foveated_ms; }, green);
        series([](const Row& r) { return r.gpu_periphery_ms; }, orange);
    }
    c.text(left, 4,
           "Gabor noise: ms vs impulses per kernel. CPU reference at " + std::to_string(size) +
               "x" + std::to_string(size),
           black);
    c.text(left + 10, 16, "CPU total", black);
    c.text(left + 80, 16, "CPU synthesis", red);
    c.text(left + 180, 16, "CPU parameter estimation", blue);
    if (gpu) {
        c.text(left + 10, 28, "GPU pass " + gpu_resolution + ": foveated", green);
        c.text(left + 200, 28, "GPU pass, all periphery", orange);
    }
    c.text(w / 2 - 50, h - 18, "impulses per kernel", black);
    return c.write(path);
}

// Times the GPU pass for each impulse count: `gaze_on_screen` puts the gaze at the centre with
// S_t from the acuity model, otherwise the gaze is off screen and S_t = 1 everywhere.
// Returns medians in ms per impulse count, or an error message.
Result<std::vector<double>> time_gpu_pass(const vk::Device& dev, VkExtent2D e,
                                          const std::vector<int>& impulses, int repeats,
                                          bool gaze_on_screen) {
    if (!dev.properties().limits.timestampComputeAndGraphics)
        return make_error("device has no compute timestamps");
    const int w = int(e.width), h = int(e.height);
    vk::EyeDisplay display = vk::EyeDisplay::desktop_1080p();
    display.width_px = e.width;
    display.height_px = e.height;
    vk::ResolvedGaze gaze;
    gaze.x_px = gaze_on_screen ? 0.5f * float(w) : -4.0f * float(w);
    gaze.y_px = 0.5f * float(h);
    const vk::AcuityParams acuity;
    // Linear colour whose display luminance is a zone plate; S_t per pixel.
    std::vector<uint16_t> colour(std::size_t(w) * h * 4), rate(std::size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float dx = float(x) - 0.5f * float(w), dy = float(y) - 0.5f * float(h);
            const float d = 0.5f + 0.3f * std::cos(3.14159265f * (dx * dx + dy * dy) / float(w));
            const float lin = post::display_decode(d);
            const std::size_t i = std::size_t(y) * w + x;
            for (int c = 0; c < 3; ++c) colour[i * 4 + c] = fovea::half_bits(lin);
            colour[i * 4 + 3] = fovea::half_bits(1.0f);
            const float s_t = vk::normalized_rate(
                vk::rate_at(display, acuity, gaze, float(x) + 0.5f, float(y) + 0.5f));
            rate[i] = fovea::half_bits(gaze_on_screen ? s_t : 1.0f);
        }
    const VkImageUsageFlags usage = VK_IMAGE_USAGE_STORAGE_BIT;
    vk::Image color_in(dev, e, VK_FORMAT_R16G16B16A16_SFLOAT, usage);
    vk::Image color_out(dev, e, VK_FORMAT_R16G16B16A16_SFLOAT, usage);
    vk::Image depth(dev, e, VK_FORMAT_R32_SFLOAT, usage);
    vk::Image motion(dev, e, VK_FORMAT_R16G16_SFLOAT, usage);
    vk::Image rate_img(dev, e, VK_FORMAT_R16_SFLOAT, usage);
    vk::Buffer staging(dev, colour.size() * 2 + rate.size() * 2, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                       true);
    std::memcpy(staging.data(), colour.data(), colour.size() * 2);
    std::memcpy(static_cast<char*>(staging.data()) + colour.size() * 2, rate.data(),
                rate.size() * 2);
    dev.submit_and_wait([&](VkCommandBuffer cmd) {
        VkBufferImageCopy r{};
        r.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        r.imageExtent = {e.width, e.height, 1};
        vkCmdCopyBufferToImage(cmd, staging.get(), color_in.get(), VK_IMAGE_LAYOUT_GENERAL, 1, &r);
        r.bufferOffset = colour.size() * 2;
        vkCmdCopyBufferToImage(cmd, staging.get(), rate_img.get(), VK_IMAGE_LAYOUT_GENERAL, 1, &r);
    });

    vk::FrameUniforms u{};
    u.extent[0] = float(w);
    u.extent[1] = float(h);
    u.gaze_px[0] = gaze.x_px;
    u.gaze_px[1] = gaze.y_px;
    u.display_size_px[0] = float(w);
    u.display_size_px[1] = float(h);
    u.display_half_tan[0] = float(std::tan(display.fov_h_deg * 0.5 * 0.017453292519943295));
    u.display_half_tan[1] = float(std::tan(display.fov_v_deg * 0.5 * 0.017453292519943295));
    VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qi.queryCount = 2;
    VkQueryPool raw_queries = VK_NULL_HANDLE;
    if (vkCreateQueryPool(dev.device(), &qi, nullptr, &raw_queries) != VK_SUCCESS)
        return make_error("cannot create a timestamp query pool");
    const vk::UniqueQueryPool owned_queries(dev.device(), raw_queries);
    const VkQueryPool queries = owned_queries.get();
    const double tick_ms = double(dev.properties().limits.timestampPeriod) * 1e-6;

    std::vector<double> medians;
    for (int n : impulses) {
        vk::FoveatorConfig config;
        config.extent = e;
        config.options = {"noise.impulses=" + std::to_string(n)};
        const vk::GBufferRefs gbuffer{};
        const vk::ImageRef rate_tiles{};
        const vk::ModuleContext ctx{dev, config, e, VK_NULL_HANDLE, gbuffer, rate_tiles};
        auto pass = vk::make_noise_pass();
        if (auto r = pass->init(ctx); !r) return r.error();
        const vk::FrameInputs inputs;
        std::vector<double> ms;
        for (int rep = 0; rep <= repeats; ++rep) {  // the first run warms up
            dev.submit_and_wait([&](VkCommandBuffer cmd) {
                vkCmdResetQueryPool(cmd, queries, 0, 2);
                vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries, 0);
                const vk::PostFrame f{cmd,         VK_NULL_HANDLE, uint64_t(rep),  u,
                                      inputs,      gaze,           color_in.ref(), color_out.ref(),
                                      depth.ref(), motion.ref(),   rate_img.ref(), {0.f, 0.f}};
                pass->record(f);
                vk::compute_barrier(cmd);
                vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, queries, 1);
            });
            uint64_t t[2] = {0, 0};
            vkGetQueryPoolResults(dev.device(), queries, 0, 2, sizeof(t), t, sizeof(uint64_t),
                                  VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT);
            if (rep > 0) ms.push_back(double(t[1] - t[0]) * tick_ms);
        }
        medians.push_back(median(ms));
    }
    return medians;
}

int run(const NoiseBenchOptions& o) {
    const int n = o.size;
    // Zone plate at 20° eccentricity, σ = 3 px, 40 px/deg: a non-empty noise band.
    post::Image luma(n, n, 1);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const float dx = float(x) - 0.5f * float(n), dy = float(y) - 0.5f * float(n);
            luma.at(x, y) = 0.5f + 0.3f * std::cos(3.14159265f * (dx * dx + dy * dy) / float(n));
        }
    const post::Image sigma(n, n, 1, 3.0f), ecc(n, n, 1, 20.0f);
    std::vector<Row> rows;
    using Clock = std::chrono::steady_clock;
    auto ms = [](Clock::time_point a, Clock::time_point b) {
        return std::chrono::duration<double, std::milli>(b - a).count();
    };
    std::printf("%-10s %12s %12s %12s\n", "impulses", "param_ms", "synth_ms", "total_ms");
    for (int impulses : {12, 16, 32, 64}) {
        post::NoiseParams p;
        p.impulses_per_kernel = impulses;
        std::vector<double> tp, ts;
        double checksum = 0;
        for (int r = 0; r < std::max(1, o.repeats); ++r) {
            const auto t0 = Clock::now();
            const post::Image params = post::noise_parameters({&luma, &sigma, &ecc}, p);
            const auto t1 = Clock::now();
            const post::Image noise = post::synthesize_gabor_noise(params, p);
            const auto t2 = Clock::now();
            tp.push_back(ms(t0, t1));
            ts.push_back(ms(t1, t2));
            checksum += noise.data[std::size_t(n) * n / 2];
        }
        rows.push_back({impulses, median(tp), median(ts)});
        std::printf("%-10d %12.2f %12.2f %12.2f   (checksum %.4g)\n", impulses,
                    rows.back().param_ms, rows.back().synth_ms,
                    rows.back().param_ms + rows.back().synth_ms, checksum);
    }
    if (o.gpu) {
        VkExtent2D e{};
        if (std::sscanf(o.gpu_resolution.c_str(), "%ux%u", &e.width, &e.height) != 2 ||
            e.width < 8 || e.height < 8) {
            std::fprintf(stderr, "noise-bench: --gpu-resolution wants WxH (>= 8x8), got %s\n",
                         o.gpu_resolution.c_str());
            return 1;
        }
        auto device = vk::Device::create_headless(vk::DeviceOptions{});
        if (!device) {
            std::fprintf(stderr, "noise-bench: %s\n", device.error().message.c_str());
            return 1;
        }
        std::vector<int> counts;
        for (const Row& r : rows) counts.push_back(r.impulses);
        const int reps = std::max(1, o.repeats);
        auto fov = time_gpu_pass(*device, e, counts, reps, true);
        auto per = fov ? time_gpu_pass(*device, e, counts, reps, false) : fov;
        if (!fov || !per) {
            std::fprintf(stderr, "noise-bench: GPU pass: %s\n",
                         (!fov ? fov : per).error().message.c_str());
            return 1;
        }
        std::printf("GPU pass \"noise\" at %s on %s (timestamps):\n%-10s %14s %14s\n",
                    o.gpu_resolution.c_str(), device->name().c_str(), "impulses", "foveated_ms",
                    "periphery_ms");
        for (std::size_t i = 0; i < rows.size(); ++i) {
            rows[i].gpu_foveated_ms = (*fov)[i];
            rows[i].gpu_periphery_ms = (*per)[i];
            std::printf("%-10d %14.2f %14.2f\n", rows[i].impulses, (*fov)[i], (*per)[i]);
        }
    }
    std::ofstream csv(o.csv);
    if (!csv) {
        std::fprintf(stderr, "noise-bench: cannot write %s\n", o.csv.c_str());
        return 1;
    }
    csv << "impulses_per_kernel,impulses_per_cell,param_ms,synth_ms,total_ms,size,"
           "gpu_foveated_ms,gpu_periphery_ms,gpu_resolution\n";
    for (const Row& r : rows) {
        csv << r.impulses << ',' << post::impulses_per_cell(r.impulses) << ',' << r.param_ms << ','
            << r.synth_ms << ',' << r.param_ms + r.synth_ms << ',' << n << ',';
        if (o.gpu) {
            csv << r.gpu_foveated_ms << ',' << r.gpu_periphery_ms << ',' << o.gpu_resolution;
        } else {
            csv << ",,";
        }
        csv << '\n';
    }
    if (!write_plot(rows, o.png, n, o.gpu_resolution)) {
        std::fprintf(stderr, "noise-bench: cannot write %s\n", o.png.c_str());
        return 1;
    }
    std::printf("wrote %s and %s\n", o.csv.c_str(), o.png.c_str());
    return 0;
}

void setup(CLI::App& app) {
    auto o = std::make_shared<NoiseBenchOptions>();
    app.add_option("--size", o->size, "Image edge in pixels")->check(CLI::Range(16, 4096));
    app.add_option("--repeats", o->repeats, "Runs per setting (median reported)")
        ->check(CLI::Range(1, 100));
    app.add_option("--csv", o->csv, "CSV output path");
    app.add_option("--png", o->png, "PNG plot output path");
    app.add_option("--gpu-resolution", o->gpu_resolution, "WxH of the GPU pass timing");
    app.add_flag("!--no-gpu", o->gpu, "Time the CPU reference only");
    app.callback([o] {
        if (const int rc = run(*o); rc != 0) throw CLI::RuntimeError(rc);
    });
}

const Command kNoiseBench{
    "noise-bench", "Gabor-noise enhancement cost against impulses per kernel (CSV + PNG)", &setup};

}  // namespace
}  // namespace fovea::cli
