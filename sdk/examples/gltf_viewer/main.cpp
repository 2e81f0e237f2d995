// gltf_viewer: renders a TOML scene of glTF 2.0 models headless through the Fovea SDK's
// integration paths and compares each with its own full-rate render. Built against the
// installed SDK only (find_package(fovea) -> fovea::vk).
//
//   gltf_viewer SCENE.toml [--paths deferred,forward-layers,post-only,rate-image]
//       [--method cps] [--post taa,contrast] [--frames 4] [--dt 0.016667] [--size WxH]
//       [--gaze centre|X,Y|fovead[:instance]|trace.csv] [--data-dir DIR] [--out DIR]
//       [--validation] [--prefer-gpu]
//
// Per path it prints one line: time per frame (wall, submit to done) against the full-rate
// render, shaded fraction, foveal PSNR and PSNR per eccentricity band (8-bit, tone-mapped), and
// writes PNGs of the last frame: <path>.png, <path>_reference.png, <path>_rate.png.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <numeric>
#include <string>
#include <vector>

#include "gltf_viewer/frame_host.hpp"
#include "gltf_viewer/gaze_source.hpp"
#include "gltf_viewer/image_io.hpp"

namespace {

using fovea::vk::IntegrationPath;

struct Options {
    std::string scene, data_dir, out = "gltf_viewer_out", method = "cps", gaze = "centre";
    std::vector<std::string> paths{"deferred", "forward-layers", "post-only", "rate-image"};
    std::vector<std::string> post;
    bool post_set = false;
    int frames = 4;
    double dt = 1.0 / 60.0;
    uint32_t width = 0, height = 0;
    bool validation = false, prefer_gpu = false;
};

std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> out;
    size_t a = 0;
    while (a <= s.size()) {
        const size_t b = s.find(',', a);
        const std::string part = s.substr(a, b == std::string::npos ? std::string::npos : b - a);
        if (!part.empty()) out.push_back(part);
        if (b == std::string::npos) break;
        a = b + 1;
    }
    return out;
}

bool parse(int argc, char** argv, Options& o) {
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw std::runtime_error(a + " needs a value");
            return argv[++i];
        };
        if (a == "--paths") {
            o.paths = split(value());
        } else if (a == "--method") {
            o.method = value();
        } else if (a == "--post") {
            o.post = split(value());
            o.post_set = true;
        } else if (a == "--frames") {
            o.frames = std::stoi(value());
        } else if (a == "--dt") {
            o.dt = std::stod(value());
        } else if (a == "--size") {
            const std::string v = value();
            if (std::sscanf(v.c_str(), "%ux%u", &o.width, &o.height) != 2 || !o.width || !o.height)
                throw std::runtime_error("--size wants WxH, got " + v);
        } else if (a == "--gaze") {
            o.gaze = value();
        } else if (a == "--data-dir") {
            o.data_dir = value();
        } else if (a == "--out") {
            o.out = value();
        } else if (a == "--validation") {
            o.validation = true;
        } else if (a == "--prefer-gpu") {
            o.prefer_gpu = true;
        } else if (a == "--help" || a == "-h") {
            return false;
        } else if (o.scene.empty() && a[0] != '-') {
            o.scene = a;
        } else {
            throw std::runtime_error("unknown argument " + a);
        }
    }
    if (o.scene.empty()) throw std::runtime_error("no scene file given");
    if (o.frames < 1 || o.frames > 100000) throw std::runtime_error("--frames must be 1..100000");
    if (!(o.dt > 0.0)) throw std::runtime_error("--dt must be positive");
    return true;
}

struct PathRun {
    std::string name;
    IntegrationPath path;
    std::string method;
};

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

int run(const Options& o) {
    gltfv::SceneFile scene;
    if (std::string e = gltfv::load_scene_file(o.scene, o.data_dir, scene); !e.empty()) {
        std::fprintf(stderr, "gltf_viewer: %s\n", e.c_str());
        return 1;
    }
    const VkExtent2D extent{o.width ? o.width : scene.width, o.height ? o.height : scene.height};
    std::string error;
    auto device = gltfv::HostDevice::create(!o.prefer_gpu, o.validation, error);
    if (!device) {
        std::fprintf(stderr, "gltf_viewer: %s\n", error.c_str());
        return 1;
    }
    auto gaze = gltfv::make_gaze_source(o.gaze, error);
    if (!gaze) {
        std::fprintf(stderr, "gltf_viewer: %s\n", error.c_str());
        return 1;
    }
    std::vector<std::string> warnings;
    auto host = gltfv::FrameHost::create(*device, scene, warnings, error);
    for (const auto& w : warnings) std::fprintf(stderr, "gltf_viewer: warning: %s\n", w.c_str());
    if (!host) {
        std::fprintf(stderr, "gltf_viewer: %s\n", error.c_str());
        return 1;
    }
    std::filesystem::create_directories(o.out);
    std::printf("gltf_viewer: %s, %u x %u, %u triangles, %zu models, %s, device %s\n",
                o.scene.c_str(), extent.width, extent.height, host->renderer().triangles(),
                scene.models.size(), gaze->describe().c_str(), device->name().c_str());
    std::printf("%-15s %9s %9s %7s %8s %s\n", "path", "ms/frame", "full ms", "shaded", "fovea dB",
                "band dB (0-5 5-10 10-20 20-30 >30)");
    fovea::vk::Device& sdk = device->sdk();
    int failures = 0;
    for (const std::string& p : o.paths) {
        PathRun r{p, IntegrationPath::kDeferred, o.method};
        if (p == "deferred")
            r.path = IntegrationPath::kDeferred;
        else if (p == "forward-layers")
            r.path = IntegrationPath::kForwardLayers;
        else if (p == "post-only")
            r.path = IntegrationPath::kPostOnly;
        else if (p == "rate-image")
            r.path = IntegrationPath::kRateImage;
        else {
            std::fprintf(stderr,
                         "gltf_viewer: unknown path '%s' (deferred, forward-layers, "
                         "post-only, rate-image)\n",
                         p.c_str());
            return 1;
        }
        // Post-only exists for its post chain; the others run without one unless asked.
        std::vector<std::string> post = o.post;
        if (!o.post_set && r.path == IntegrationPath::kPostOnly) post = {"taa", "contrast"};
        fovea::vk::FoveatorConfig fc = host->config(r.path, extent);
        fc.post_chain = post;
        fc.method = r.method;
        auto f = fovea::vk::Foveator::create(sdk, fc);
        if (!f) {
            std::printf("%-15s skipped: %s\n", p.c_str(), f.error().message.c_str());
            continue;
        }
        // Its own full-rate render: the deferred method "full", or the forward frame at rate 1
        // everywhere (S_t = 0) through the same post chain.
        fovea::vk::FoveatorConfig rc =
            host->config(r.path == IntegrationPath::kDeferred ? IntegrationPath::kDeferred
                                                              : IntegrationPath::kPostOnly,
                         extent);
        rc.post_chain = post;
        rc.method = "full";
        rc.acuity.max_rate = 1.f;
        auto ref = fovea::vk::Foveator::create(sdk, rc);
        if (!ref) {
            std::fprintf(stderr, "gltf_viewer: reference: %s\n", ref.error().message.c_str());
            return 1;
        }
        std::vector<double> ms, ref_ms, fovea_db, shaded;
        std::array<double, fovea::vk::kBandCount> band_sum{};
        std::array<int, fovea::vk::kBandCount> band_n{};
        gltfv::Rgb8 last, last_ref, last_rate;
        for (int i = -1; i < o.frames; ++i) {  // frame -1 warms both up (shader JIT), unmeasured
            const double t = std::max(i, 0) * o.dt;
            fovea::vk::FrameInputs in = host->inputs(t, extent);
            in.gaze = gaze->at(t);
            in.camera_cut = i <= 0;
            const auto frame = [&](fovea::vk::Foveator& fov) {
                fovea::vk::FrameInputs fin = in;
                if (fov.config().host_set_layout) fin.host_set = host->renderer().scene_set();
                const auto t0 = std::chrono::steady_clock::now();
                sdk.submit_and_wait([&](VkCommandBuffer cmd) {
                    host->record(cmd, fov, uint64_t(i + 1), fin, t, o.dt);
                    fov.record(cmd, uint64_t(i + 1), fin);
                });
                return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() -
                                                                 t0)
                    .count();
            };
            if (i < 0) {
                frame(*f);
                frame(*ref);
                continue;
            }
            ms.push_back(frame(*f));
            const fovea::vk::FrameStats st = f->stats();
            shaded.push_back(st.shaded_fraction);
            last = gltfv::tonemap(sdk.read_image(f->output()), extent.width, extent.height);
            last_rate = gltfv::rate_colours(sdk.read_image(f->rate()), extent.width, extent.height);
            ref_ms.push_back(frame(*ref));
            last_ref = gltfv::tonemap(sdk.read_image(ref->output()), extent.width, extent.height);
            const gltfv::Psnr e =
                gltfv::psnr(last, last_ref, fc.display, st.gaze, fc.acuity.foveal_radius_deg);
            fovea_db.push_back(e.fovea_db);
            for (int b = 0; b < fovea::vk::kBandCount; ++b)
                if (std::isfinite(e.bands_db[size_t(b)])) {
                    band_sum[size_t(b)] += e.bands_db[size_t(b)];
                    ++band_n[size_t(b)];
                }
        }
        const double min_fovea = *std::min_element(fovea_db.begin(), fovea_db.end());
        std::printf("%-15s %9.1f %9.1f %6.1f%% %8.1f ", p.c_str(), median(ms), median(ref_ms),
                    100.0 * std::accumulate(shaded.begin(), shaded.end(), 0.0) / shaded.size(),
                    min_fovea);
        for (int b = 0; b < fovea::vk::kBandCount; ++b)
            std::printf(" %5.1f",
                        band_n[size_t(b)] ? band_sum[size_t(b)] / band_n[size_t(b)] : NAN);
        std::printf("\n");
        const std::string base = o.out + "/" + p;
        gltfv::write_png(base + ".png", last);
        gltfv::write_png(base + "_reference.png", last_ref);
        gltfv::write_png(base + "_rate.png", last_rate);
        if (!(min_fovea >= 40.0)) ++failures;
    }
    if (device->validation_errors() > 0) {
        std::fprintf(stderr, "gltf_viewer: %llu validation errors\n",
                     static_cast<unsigned long long>(device->validation_errors()));
        return 1;
    }
    return failures == 0 ? 0 : 3;  // 3: a path's fovea fell below 40 dB
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    try {
        if (!parse(argc, argv, o)) {
            std::printf(
                "usage: gltf_viewer SCENE.toml [--paths deferred,forward-layers,"
                "post-only,rate-image] [--method cps] [--post taa,contrast] [--frames N] [--dt S] "
                "[--size WxH] [--gaze centre|X,Y|fovead[:instance]|trace.csv] [--data-dir DIR] "
                "[--out DIR] [--validation] [--prefer-gpu]\n");
            return 0;
        }
        return run(o);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "gltf_viewer: %s\n", e.what());
        return 1;
    }
}
