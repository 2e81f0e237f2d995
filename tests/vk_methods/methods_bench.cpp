// vk_methods_bench: time and error of the issue-6 methods against the full-rate reference on
// the same frames and gaze trace, with the demo's expensive shading function
// (shaders/demo_shading.glsl) on this directory's analytic test scene. Prints a table and CSV.
//   vk_methods_bench [--width 1920 --height 1080 --frames 10 --shading demo|test]
// Time is the method's GPU time (timestamps) per frame; every configuration renders each
// frame back to back and the speed-up is the median over frames of full/method (same load).
// PSNR/SSIM per eccentricity band (acuity.hpp kBandEdgesDeg) averaged over the frames.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "method_harness.hpp"
#include "shaders.hpp"

using namespace fovea::vk;
using namespace fovea::vk::test;

namespace {

struct Config {
    std::string label;
    std::string method;
    std::vector<std::string> options;
};

struct Row {
    std::string label;
    std::vector<double> ms;
    std::vector<double> ratio;  // full / this, per frame
    std::vector<double> wall;
    double shaded = 0;
    std::array<double, kBandCount> psnr{};
    std::array<double, kBandCount> ssim{};
    int frames = 0;
};

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// SSIM of luminance on non-overlapping 8x8 blocks, accumulated per band of the block centre.
void ssim_bands(const Frame& a, const Frame& b, const EyeDisplay& d, float gx, float gy,
                std::array<double, kBandCount>& sum, std::array<int, kBandCount>& n) {
    const double c1 = 1e-4, c2 = 9e-4;
    auto lum = [](const Frame& f, uint32_t x, uint32_t y) {
        const std::size_t i = (std::size_t(y) * f.width + x) * 4;
        return std::clamp(0.2126 * f.rgba[i] + 0.7152 * f.rgba[i + 1] + 0.0722 * f.rgba[i + 2], 0.0,
                          1.0);
    };
    for (uint32_t by = 0; by + 8 <= a.height; by += 8)
        for (uint32_t bx = 0; bx + 8 <= a.width; bx += 8) {
            double ma = 0, mb = 0, va = 0, vb = 0, cov = 0;
            for (uint32_t y = by; y < by + 8; ++y)
                for (uint32_t x = bx; x < bx + 8; ++x) {
                    ma += lum(a, x, y);
                    mb += lum(b, x, y);
                }
            ma /= 64;
            mb /= 64;
            for (uint32_t y = by; y < by + 8; ++y)
                for (uint32_t x = bx; x < bx + 8; ++x) {
                    const double da = lum(a, x, y) - ma, db = lum(b, x, y) - mb;
                    va += da * da;
                    vb += db * db;
                    cov += da * db;
                }
            va /= 63;
            vb /= 63;
            cov /= 63;
            const double s =
                ((2 * ma * mb + c1) * (2 * cov + c2)) / ((ma * ma + mb * mb + c1) * (va + vb + c2));
            const float e = eccentricity_deg(d, bx + 4.f, by + 4.f, gx, gy);
            for (int k = 0; k < kBandCount; ++k)
                if (e >= kBandEdgesDeg[k] && e < kBandEdgesDeg[k + 1]) {
                    sum[std::size_t(k)] += s;
                    ++n[std::size_t(k)];
                }
        }
}

}  // namespace

int main(int argc, char** argv) {
    uint32_t w = 1920, h = 1080;
    int frames = 10;
    bool cheap = false;  // --shading test: the tests' cheap shading, to expose fixed costs
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--shading")) cheap = !std::strcmp(argv[i + 1], "test");
        if (!std::strcmp(argv[i], "--width"))
            w = uint32_t(std::atoi(argv[i + 1]));
        else if (!std::strcmp(argv[i], "--height"))
            h = uint32_t(std::atoi(argv[i + 1]));
        else if (!std::strcmp(argv[i], "--frames"))
            frames = std::atoi(argv[i + 1]);
    }
    auto dev = Device::create_headless({});
    if (!dev) {
        std::fprintf(stderr, "no Vulkan device: %s\n", dev.error().message.c_str());
        return 2;
    }
    const EmbeddedShader* shading = find_shader("demo_shading.glsl");
    if (!shading) {
        std::fprintf(stderr, "demo_shading.glsl is not embedded\n");
        return 2;
    }
    const bool native = (w == 1920 && h == 1080);  // the 24" monitor preset itself
    std::vector<Config> configs = {
        {"full", "full", {}},
        {"layers", "layers", {}},
        {"layers-half", "layers", {"layers.half_rate=1"}},
        {"layers-fovea5", "layers", {"layers.fovea_deg=5"}},
        {"kfr-1.6", "kfr", {"kfr.sigma=1.6"}},
        {"kfr-1.8", "kfr", {"kfr.sigma=1.8"}},
        {"kfr-1.8-literal", "kfr", {"kfr.sigma=1.8", "kfr.literal=1"}},
        {"adaptive", "adaptive", {}},
    };
    if (const char* only = std::getenv("BENCH_ONLY")) {  // e.g. BENCH_ONLY=kfr-1.8
        std::vector<Config> keep{configs[0]};
        for (const Config& c : configs)
            if (c.label == only) keep.push_back(c);
        configs = keep;
    }
    // Gaze trace: fixation, slow pursuit, a saccade, fixation (normalized display coordinates).
    auto gaze = [&](int f) -> std::pair<float, float> {
        if (f < frames / 3) return {0.45f, 0.5f};
        if (f < 2 * frames / 3) return {0.45f + 0.01f * float(f - frames / 3), 0.5f};
        return {0.7f, 0.35f};
    };
    // All configurations render each frame back to back, so the time ratios compare
    // measurements taken under the same machine load (2 shared cores).
    std::vector<std::unique_ptr<MethodHarness>> harness;
    std::vector<Row> rows;
    for (const Config& c : configs) {
        auto m = std::make_unique<MethodHarness>(*dev, w, h, c.method, c.options, 8,
                                                 cheap ? kTestShading : shading->source, native);
        if (!m->ok()) {
            std::fprintf(stderr, "%s: %s\n", c.label.c_str(), m->error().c_str());
            return 1;
        }
        harness.push_back(std::move(m));
        rows.push_back(Row{});
        rows.back().label = c.label;
    }
    std::vector<std::array<int, kBandCount>> ssim_n(configs.size());
    std::vector<std::array<double, kBandCount>> se(configs.size()), se_n(configs.size());
    for (int f = 0; f < frames; ++f) {
        const auto [gx, gy] = gaze(f);
        Frame ref;
        double full_ms = 0;
        for (std::size_t i = 0; i < configs.size(); ++i) {
            Frame out = harness[i]->render(uint64_t(f), gx, gy);
            if (i == 0) {
                ref = out;
                full_ms = out.stats.method_gpu_ms;
            }
            if (f < 2) continue;  // warm-up: pipelines, histories
            Row& r = rows[i];
            r.ms.push_back(out.stats.method_gpu_ms);
            r.ratio.push_back(out.stats.method_gpu_ms > 0 ? full_ms / out.stats.method_gpu_ms : 0);
            r.wall.push_back(out.wall_ms);
            r.shaded += out.stats.shaded_fraction;
            ++r.frames;
            const EyeDisplay& d = harness[i]->foveator().config().display;
            const float px = gx * float(w), py = gy * float(h);
            for (int k = 0; k < kBandCount; ++k) {
                const double p =
                    psnr_band(out, ref, d, px, py, kBandEdgesDeg[k], kBandEdgesDeg[k + 1]);
                if (p > 0) {
                    se[i][std::size_t(k)] += std::pow(10.0, -p / 10.0);  // average the MSE
                    se_n[i][std::size_t(k)] += 1;
                }
            }
            ssim_bands(out, ref, d, px, py, r.ssim, ssim_n[i]);
        }
        std::fprintf(stderr, "frame %d done\n", f);
    }
    for (std::size_t i = 0; i < rows.size(); ++i) {
        Row& r = rows[i];
        r.shaded /= std::max(1, r.frames);
        for (std::size_t k = 0; k < std::size_t(kBandCount); ++k) {
            const double mse = se_n[i][k] > 0 ? se[i][k] / se_n[i][k] : 0;
            r.psnr[k] = mse > 1e-12 ? -10.0 * std::log10(mse) : (se_n[i][k] > 0 ? 120.0 : 0.0);
            r.ssim[k] = ssim_n[i][k] ? r.ssim[k] / ssim_n[i][k] : 0;
        }
    }
    std::printf("%dx%d, %d frames (%d timed), device %s\n", w, h, frames, frames - 2,
                dev->name().c_str());
    std::printf("%-16s %9s %9s %8s %8s  PSNR dB per band 0-5/5-10/10-20/20-30/>30   SSIM\n",
                "method", "gpu ms", "wall ms", "speedup", "shaded");
    for (const Row& r : rows) {
        std::printf("%-16s %9.2f %9.2f %8.2f %8.3f ", r.label.c_str(), median(r.ms), median(r.wall),
                    median(r.ratio), r.shaded);
        for (double p : r.psnr) std::printf(" %6.1f", p);
        std::printf("  ");
        for (double s : r.ssim) std::printf(" %5.3f", s);
        std::printf("\n");
    }
    std::printf("\ncsv:method,gpu_ms_median,wall_ms_median,speedup_median,shaded_fraction");
    for (int k = 0; k < kBandCount; ++k) std::printf(",psnr_%s", band_name(k));
    for (int k = 0; k < kBandCount; ++k) std::printf(",ssim_%s", band_name(k));
    std::printf("\n");
    for (const Row& r : rows) {
        std::printf("csv:%s,%.3f,%.3f,%.3f,%.4f", r.label.c_str(), median(r.ms), median(r.wall),
                    median(r.ratio), r.shaded);
        for (double p : r.psnr) std::printf(",%.2f", p);
        for (double s : r.ssim) std::printf(",%.4f", s);
        std::printf("\n");
    }
    return 0;
}
