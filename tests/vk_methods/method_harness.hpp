// A tiny host for the GPU tests of the issue-6 methods: an analytic scene ray-cast on the CPU
// (checkered plane, three spheres, sky) written into the Foveator's G-buffer and into every
// extra view a method requests (crop + jitter, as the demo host does), a deterministic shading
// function, and image metrics against the full-rate reference.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "fovea/half.hpp"
#include "fovea/vk/acuity.hpp"
#include "fovea/vk/device.hpp"
#include "fovea/vk/foveator.hpp"
#include "gpu.hpp"

namespace fovea::vk::test {

inline const char* kTestShading = R"GLSL(
vec3 fovea_shade(FoveaGSample g, FoveaFootprint fp) {
    if (g.background)
        return mix(vec3(0.55, 0.65, 0.85), vec3(0.15, 0.25, 0.6), clamp(g.normal.y, 0.0, 1.0));
    vec3 l = normalize(vec3(0.3, 0.8, 0.5));
    vec3 v = normalize(fovea_frame.camera_pos.xyz - g.position);
    vec3 h = normalize(l + v);
    float stripes = 0.5 + 0.5 * sin(g.position.x * 9.0) * exp(-fp.world_size * 4.0);
    vec3 base = g.albedo * (0.75 + 0.25 * stripes);
    float spec = pow(max(dot(g.normal, h), 0.0), 40.0);
    return base * (0.15 + max(dot(g.normal, l), 0.0)) + vec3(0.6) * spec;
}
)GLSL";

struct Vec3 {
    double x, y, z;
};
inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator*(double s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
inline double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 normalize(Vec3 a) { return (1.0 / std::sqrt(dot(a, a))) * a; }

// CPU ray caster: camera at the origin looking down -z, static (motion follows the contract:
// unjittered texel centre minus the previous position of the jittered sample = -jitter).
class TestScene {
public:
    TestScene(double tan_half_x, double tan_half_y) : tx_(tan_half_x), ty_(tan_half_y) {}

    // Packed bytes of the G-buffer images (gbuffer.hpp) for a view of `w` x `h` covering `crop`.
    std::array<std::vector<uint8_t>, kGBufferImageCount> render(uint32_t w, uint32_t h,
                                                                std::array<float, 4> crop,
                                                                std::array<float, 2> jitter) const {
        std::array<std::vector<uint8_t>, kGBufferImageCount> out;
        const std::size_t n = std::size_t(w) * h;
        out[0].resize(n * 16);
        out[1].resize(n * 16);
        out[2].resize(n * 4);
        out[3].resize(n * 4);
        for (uint32_t y = 0; y < h; ++y)
            for (uint32_t x = 0; x < w; ++x) {
                const double u = (x + 0.5 + jitter[0]) / w;
                const double v = (y + 0.5 + jitter[1]) / h;
                const double fx = crop[0] + (crop[2] - crop[0]) * u;
                const double fy = crop[1] + (crop[3] - crop[1]) * v;
                const Vec3 rd = normalize({(2 * fx - 1) * tx_, (1 - 2 * fy) * ty_, -1.0});
                double t = 1e30;
                Vec3 nrm{0, 0, 1}, alb{0, 0, 0};
                float mat = 0;
                const std::array<std::array<double, 4>, 3> spheres{
                    {{-0.6, 0.1, -4.0, 0.5}, {0.5, -0.2, -3.5, 0.35}, {0.05, 0.35, -5.0, 0.6}}};
                for (std::size_t i = 0; i < spheres.size(); ++i) {
                    const auto& s = spheres[i];
                    const Vec3 c{s[0], s[1], s[2]};
                    const double b = dot(rd, c);
                    const double disc = b * b - dot(c, c) + s[3] * s[3];
                    if (disc < 0) continue;
                    const double ti = b - std::sqrt(disc);
                    if (ti > 0 && ti < t) {
                        t = ti;
                        nrm = normalize(ti * rd - c);
                        alb = {0.3 + 0.2 * i, 0.6 - 0.15 * i, 0.3 + 0.1 * i};
                        mat = float(2 + i);
                    }
                }
                if (rd.z < 0) {  // the back wall z = -6, checkered
                    const double ti = -6.0 / rd.z;
                    if (ti < t) {
                        t = ti;
                        nrm = {0, 0, 1};
                        const Vec3 p = ti * rd;
                        const bool odd = (int(std::floor(p.x * 3)) + int(std::floor(p.y * 3))) & 1;
                        alb = odd ? Vec3{0.8, 0.8, 0.75} : Vec3{0.2, 0.25, 0.3};
                        mat = 1;
                    }
                }
                const std::size_t i = std::size_t(y) * w + x;
                const bool hit = t < 1e29;
                const Vec3 p = hit ? t * rd : Vec3{0, 0, 0};
                const float pos[4] = {float(p.x), float(p.y), float(p.z), hit ? float(t) : 0.f};
                std::memcpy(&out[0][i * 16], pos, 16);
                const Vec3 nn = hit ? nrm : rd;
                SurfaceSample surface;
                surface.normal = {float(nn.x), float(nn.y), float(nn.z)};
                surface.albedo = {float(alb.x), float(alb.y), float(alb.z)};
                surface.material = {mat, mat > 1 ? 0.3f : 0.8f, 0.f, 0.f};
                const SurfaceTexel st = pack_surface(surface);
                std::memcpy(&out[1][i * 16], st.data(), 16);
                const float depth = hit ? float(1.0 - 0.1 / std::max(t, 0.1)) : 1.0f;
                std::memcpy(&out[2][i * 4], &depth, 4);
                const uint16_t mo[2] = {fovea::half_bits(-jitter[0]), fovea::half_bits(-jitter[1])};
                std::memcpy(&out[3][i * 4], mo, 4);
            }
        return out;
    }

private:
    double tx_, ty_;
};

struct Frame {
    uint32_t width = 0, height = 0;
    std::vector<float> rgba;  // linear, 4 per pixel
    FrameStats stats;
    double wall_ms = 0;  // render_blocking: upload + method + submit/wait
    bool finite() const {
        return std::all_of(rgba.begin(), rgba.end(), [](float v) { return std::isfinite(v); });
    }
};

// One Foveator on the shared device; render() writes the G-buffers the method asks for.
class MethodHarness {
public:
    MethodHarness(Device& device, uint32_t w, uint32_t h, std::string method,
                  std::vector<std::string> options = {}, uint32_t jitter_length = 8,
                  std::string shading = kTestShading, bool native_display = false)
        : device_(device) {
        FoveatorConfig c;
        c.extent = {w, h};
        c.jitter_length = jitter_length;
        // The pixel density of a 24" 1080p monitor at 60 cm on a smaller frame.
        const EyeDisplay desk = EyeDisplay::desktop_1080p();
        c.display = native_display ? desk
                                   : EyeDisplay::from_fov(w, h, desk.fov_h_deg * w / desk.width_px,
                                                          desk.fov_v_deg * h / desk.height_px);
        c.method = std::move(method);
        c.shading_glsl = std::move(shading);
        c.options = std::move(options);
        auto f = Foveator::create(device, c);
        if (!f) {
            error_ = f.error().message;
            return;
        }
        foveator_ = std::make_unique<Foveator>(std::move(*f));
        constexpr double kDeg = 3.14159265358979323846 / 360.0;
        scene_ = std::make_unique<TestScene>(std::tan(c.display.fov_h_deg * kDeg),
                                             std::tan(c.display.fov_v_deg * kDeg));
    }

    bool ok() const { return foveator_ != nullptr; }
    const std::string& error() const { return error_; }
    Foveator& foveator() { return *foveator_; }

    Frame render(uint64_t frame, float gaze_x, float gaze_y, double time_s = -1.0) {
        FrameInputs in;
        in.gaze.x = gaze_x;
        in.gaze.y = gaze_y;
        in.time_s = time_s >= 0.0 ? time_s : double(frame) / 60.0;
        const FoveatorConfig& c = foveator_->config();
        in.radians_per_pixel = float(
            2.0 * std::atan(std::tan(c.display.fov_h_deg * 3.14159265 / 360.0)) / c.extent.width);
        struct Upload {
            GBufferRefs refs;
            std::array<std::vector<uint8_t>, kGBufferImageCount> data;
        };
        std::vector<Upload> uploads;
        if (foveator_->needs_full_gbuffer())
            uploads.push_back(
                {foveator_->gbuffer(), scene_->render(c.extent.width, c.extent.height, {0, 0, 1, 1},
                                                      foveator_->jitter(frame))});
        for (const ViewRequest& v : foveator_->views(frame, in))
            uploads.push_back(
                {v.gbuffer, scene_->render(v.gbuffer.extent.width, v.gbuffer.extent.height, v.crop,
                                           v.jitter_px)});
        VkDeviceSize total = 0;
        for (const Upload& u : uploads)
            for (const auto& d : u.data) total += (d.size() + 15) / 16 * 16;
        Buffer staging(device_, std::max<VkDeviceSize>(total, 16), VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                       true);
        const double wall = foveator_->render_blocking(frame, in, [&](VkCommandBuffer cmd) {
            VkDeviceSize offset = 0;
            for (const Upload& u : uploads)
                for (int i = 0; i < kGBufferImageCount; ++i) {
                    std::memcpy(static_cast<uint8_t*>(staging.data()) + offset,
                                u.data[std::size_t(i)].data(), u.data[std::size_t(i)].size());
                    VkBufferImageCopy r{};
                    r.bufferOffset = offset;
                    r.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
                    r.imageExtent = {u.refs.extent.width, u.refs.extent.height, 1};
                    vkCmdCopyBufferToImage(cmd, staging.get(), u.refs.images[std::size_t(i)].image,
                                           VK_IMAGE_LAYOUT_GENERAL, 1, &r);
                    offset += (u.data[std::size_t(i)].size() + 15) / 16 * 16;  // texel-aligned
                }
        });
        Frame f;
        f.width = c.extent.width;
        f.height = c.extent.height;
        f.stats = foveator_->stats();
        f.wall_ms = wall;
        const std::vector<uint8_t> raw = device_.read_image(foveator_->shaded());
        f.rgba.resize(raw.size() / 2);
        for (std::size_t i = 0; i < f.rgba.size(); ++i) {
            uint16_t h;
            std::memcpy(&h, &raw[i * 2], 2);
            f.rgba[i] = fovea::half_from_bits(h);
        }
        return f;
    }

private:
    Device& device_;
    std::unique_ptr<Foveator> foveator_;
    std::unique_ptr<TestScene> scene_;
    std::string error_;
};

// PSNR (peak 1) over the pixels whose eccentricity from the gaze lies in [lo, hi) degrees.
inline double psnr_band(const Frame& a, const Frame& ref, const EyeDisplay& d, float gx_px,
                        float gy_px, double lo, double hi) {
    double se = 0;
    std::size_t n = 0;
    for (uint32_t y = 0; y < a.height; ++y)
        for (uint32_t x = 0; x < a.width; ++x) {
            const double e = eccentricity_deg(d, x + 0.5f, y + 0.5f, gx_px, gy_px);
            if (e < lo || e >= hi) continue;
            for (int c = 0; c < 3; ++c) {
                const std::size_t i = (std::size_t(y) * a.width + x) * 4 + std::size_t(c);
                const double diff = std::clamp(double(a.rgba[i]), 0.0, 1.0) -
                                    std::clamp(double(ref.rgba[i]), 0.0, 1.0);
                se += diff * diff;
            }
            ++n;
        }
    if (n == 0) return 0.0;
    const double mse = se / (3.0 * n);
    return mse <= 1e-12 ? 120.0 : 10.0 * std::log10(1.0 / mse);
}

}  // namespace fovea::vk::test
