// The demo scene, the zone-plate target and the comparison runner (issue 5).
#include <algorithm>
#include <cmath>
#include <cstring>

#include "fovea/demo/demo.hpp"
#include "vk_test_util.hpp"

namespace fovea::demo {
namespace {

// The coarse pixel shader keeps the zone plate's frequencies the MAR line says the eye resolves
// and removes those its coarse grid would alias: measured ring by ring against the model.
TEST(ZonePlate, PeripheralAttenuationFollowsTheMarLine) {
    FOVEA_REQUIRE_DEVICE();
    constexpr uint32_t kSize = 512;
    vk::FoveatorConfig c;
    c.extent = {kSize, kSize};
    c.display = vk::EyeDisplay::from_fov(kSize, kSize, 30.0, 30.0);
    c.acuity.mar_slope = 0.1f;  // steep, so a 512 px target spans all rates
    c.acuity.foveal_radius_deg = 2.f;
    c.acuity.transition_deg = 2.f;
    c.method = "full";
    c.shading_glsl = shading_glsl();
    auto f = vk::Foveator::create(*device, c);
    ASSERT_TRUE(f) << f.error().message;
    const Camera cam = target_camera(c.display);
    const double unit = 2.0 * cam.tan_x / kSize;   // plane units per pixel
    const double k = 0.5 / (256.0 * unit * unit);  // local frequency 0.5 cycles/px at r = 256
    std::array<float, 64> host{};
    host[0] = static_cast<float>(k);
    host[2] = static_cast<float>(unit);
    f->set_host_params(host);
    SceneRenderer scene(*device);
    vk::FrameInputs in;  // gaze at the centre
    auto render = [&] {
        f->render_blocking(0, in, [&](VkCommandBuffer cmd) {
            scene.begin_frame();
            scene.record(cmd, f->gbuffer(), SceneKind::kZonePlate, cam, cam, 0.0);
        });
        const auto raw = device->read_image(f->output());
        std::vector<float> g(kSize * kSize);
        for (size_t i = 0; i < g.size(); ++i)
            g[i] = fovea::half_from_bits(uint16_t(raw[i * 8] | raw[i * 8 + 1] << 8));
        return g;
    };
    const auto ref = render();
    ASSERT_TRUE(f->set_method("cps"));
    const auto cps = render();
    const vk::ResolvedGaze gaze = f->stats().gaze;

    // Amplitude of the zone plate's cosine in rings of 3 px around the gaze.
    constexpr int kRings = 84;
    std::array<double, kRings> a_ref{}, a_cps{}, n{}, cc{};
    for (uint32_t y = 0; y < kSize; ++y)
        for (uint32_t x = 0; x < kSize; ++x) {
            const double dx = x + 0.5 - kSize / 2.0, dy = y + 0.5 - kSize / 2.0;
            const double r = std::hypot(dx, dy);
            const int ring = static_cast<int>(r / 3.0);
            if (ring >= kRings) continue;
            const double ru = r * unit;
            const double cs = std::cos(M_PI * k * ru * ru);
            a_ref[ring] += (ref[y * kSize + x] - 0.5) * cs;
            a_cps[ring] += (cps[y * kSize + x] - 0.5) * cs;
            n[ring] += 1;
            cc[ring] += 0.5 * cs * cs;
        }
    int checked_pass = 0, checked_stop = 0;
    for (int i = 2; i < kRings; ++i) {
        const double r = (i + 0.5) * 3.0;
        // Least-squares amplitude of 0.5 * A * cos(phase) in the ring.
        const double ar = a_ref[i] / cc[i], ac = a_cps[i] / cc[i];
        const double f_px = k * unit * unit * r;  // cycles per pixel
        const float px = kSize / 2.f + static_cast<float>(r), py = kSize / 2.f;
        const float e = vk::eccentricity_deg(c.display, px, py, gaze.x_px, gaze.y_px);
        const float pix = vk::pixel_size_deg(c.display, px, py);
        const double f_mar = pix / vk::mar_deg(c.acuity, e);  // resolvable, cycles per pixel
        const double rate = vk::rate_at(c.display, c.acuity, gaze, px, py);
        const double q = rate >= 4 ? 4 : rate >= 2 ? 2 : 1;
        if (f_px < 0.3) { EXPECT_GT(ar, 0.8) << "reference ring " << i; }
        if (q == 1) { EXPECT_NEAR(ac, ar, 0.02) << "full-rate ring " << i; }
        if (f_px <= 0.5 * f_mar) {  // well inside what the eye resolves here: kept
            EXPECT_GT(ac, 0.6 * ar) << "ring " << i << " e " << e << " f " << f_px;
            ++checked_pass;
        }
        if (f_px >= 1.0 / q) {  // beyond twice the coarse grid's Nyquist: removed, no alias
            EXPECT_LT(std::abs(ac), 0.15) << "ring " << i << " e " << e << " f " << f_px;
            ++checked_stop;
        }
    }
    EXPECT_GT(checked_pass, 10);
    EXPECT_GT(checked_stop, 10);
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

// The runner renders the demo scene with full and cps: the reference equals itself, cps shades
// a fraction of the pixels and its fovea equals the reference.
TEST(DemoRunner, CpsMatchesReferenceInTheFoveaOnTheDemoScene) {
    FOVEA_REQUIRE_DEVICE();
    RunOptions o;
    o.display = vk::EyeDisplay::from_size(480, 270, 0.531, 0.299, 0.60);
    o.frames = 2;
    o.acuity.foveal_radius_deg = 3.f;
    o.acuity.transition_deg = 2.f;
    o.acuity.mar_slope = 0.1f;  // a 480 px screen has few pixels per degree
    auto r = run(*device, o);
    ASSERT_TRUE(r) << r.error().message;
    ASSERT_EQ(r->size(), 2u);
    const MethodResult& full = (*r)[0];
    const MethodResult& cps = (*r)[1];
    EXPECT_EQ(full.name, "full");
    EXPECT_TRUE(cps.error.empty()) << cps.error;
    EXPECT_EQ(full.error_figures.psnr_fovea_db, INFINITY);  // pooled, uncapped
    EXPECT_NEAR(full.shaded_fraction, 1.0, 1e-9);
    EXPECT_LT(cps.shaded_fraction, 0.6);
    EXPECT_GE(cps.error_figures.psnr_fovea_db, 40.0);
    EXPECT_GT(cps.error_figures.ssim_bands[0], 0.95);
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

// The rasterized G-buffer against what a ray-cast through each pixel centre gives: every pixel is
// either sky (normal = the pixel's ray) or a surface on that ray with consistent distance, depth
// and unit normal, for the full view and for a cropped, sub-pixel-jittered one (the layers
// method's views). With the previous camera equal to the current one the motion is -jitter.
TEST(SceneRenderer, RasterizedGBufferMatchesThePixelRays) {
    FOVEA_REQUIRE_DEVICE();
    constexpr uint32_t kW = 320, kH = 180;
    const auto display = vk::EyeDisplay::from_size(kW, kH, 0.531, 0.299, 0.60);
    const Camera cam = camera_at(1.0, display);
    SceneRenderer scene(*device);
    std::vector<vk::Image> images;
    vk::GBufferRefs g;
    g.extent = {kW, kH};
    for (int i = 0; i < vk::kGBufferImageCount; ++i) {
        images.emplace_back(*device, g.extent, vk::kGBufferFormats[i], vk::kGBufferUsage);
        g.images[i] = images.back().ref();
    }
    struct Case {
        std::array<float, 4> crop;
        std::array<float, 2> jitter;
    };
    for (const Case& c : {Case{{0.f, 0.f, 1.f, 1.f}, {0.f, 0.f}},
                          Case{{0.3f, 0.05f, 0.7f, 0.45f}, {0.3f, -0.2f}}}) {
        SCOPED_TRACE(testing::Message() << "crop x0 " << c.crop[0] << " jitter " << c.jitter[0]);
        device->submit_and_wait([&](VkCommandBuffer cmd) {
            scene.begin_frame();
            scene.record(cmd, g, SceneKind::kDemo, cam, cam, 1.0, c.crop, c.jitter);
        });
        const auto pos = device->read_image(g[vk::GBufferImage::kPosition]);
        const auto srf = device->read_image(g[vk::GBufferImage::kSurface]);
        const auto dep = device->read_image(g[vk::GBufferImage::kDepth]);
        const auto mot = device->read_image(g[vk::GBufferImage::kMotion]);
        auto surface = [&](size_t i) {
            vk::SurfaceTexel t;
            std::memcpy(t.data(), srf.data() + 16 * i, 16);
            return vk::unpack_surface(t);
        };
        auto f32 = [](const std::vector<uint8_t>& b, size_t i) {
            float v;
            std::memcpy(&v, b.data() + 4 * i, 4);
            return v;
        };
        auto f16 = [](const std::vector<uint8_t>& b, size_t i) {
            return fovea::half_from_bits(uint16_t(b[2 * i] | b[2 * i + 1] << 8));
        };
        int sky = 0, terrain = 0, objects = 0, bad = 0;
        for (uint32_t y = 0; y < kH; ++y)
            for (uint32_t x = 0; x < kW; ++x) {
                const size_t i = size_t{y} * kW + x;
                const float fx =
                    c.crop[0] + (c.crop[2] - c.crop[0]) * (x + 0.5f + c.jitter[0]) / kW;
                const float fy =
                    c.crop[1] + (c.crop[3] - c.crop[1]) * (y + 0.5f + c.jitter[1]) / kH;
                std::array<double, 3> rd{};
                for (int k = 0; k < 3; ++k)
                    rd[k] = cam.fwd[k] + cam.right[k] * (2 * fx - 1) * cam.tan_x +
                            cam.up[k] * (1 - 2 * fy) * cam.tan_y;
                const double len = std::hypot(rd[0], rd[1], rd[2]);
                const vk::SurfaceSample s = surface(i);
                const double n[3] = {s.normal[0], s.normal[1], s.normal[2]};
                const double dist = f32(pos, 4 * i + 3);
                const int id = static_cast<int>(s.material[0]);
                bool ok;
                if (dist == 0.0) {  // sky: the normal carries the pixel's ray
                    ++sky;
                    ok = id == 0 && f32(dep, i) == 1.f;
                    for (int k = 0; k < 3; ++k) ok = ok && std::abs(n[k] - rd[k] / len) < 1e-4;
                } else {
                    (id == 1 ? terrain : objects) += 1;
                    const double p[3] = {f32(pos, 4 * i) - cam.pos[0],
                                         f32(pos, 4 * i + 1) - cam.pos[1],
                                         f32(pos, 4 * i + 2) - cam.pos[2]};
                    const double along = (p[0] * rd[0] + p[1] * rd[1] + p[2] * rd[2]) / len;
                    const double off_ray = std::sqrt(std::max(0.0, dist * dist - along * along));
                    ok = id >= 1 && id <= 5 &&
                         std::abs(std::hypot(p[0], p[1], p[2]) - dist) < 1e-3 * dist &&
                         off_ray < 1e-3 * dist &&
                         std::abs(f32(dep, i) - (1.0 - 0.1 / dist)) < 1e-5 &&
                         std::abs(std::hypot(n[0], n[1], n[2]) - 1.0) < 1e-5 &&
                         std::abs(f16(mot, 2 * i) + c.jitter[0]) < 0.02 &&
                         std::abs(f16(mot, 2 * i + 1) + c.jitter[1]) < 0.02;
                }
                bad += !ok;
            }
        EXPECT_EQ(bad, 0);
        // The fly-over at t = 1 s sees sky, terrain and several objects in both views.
        EXPECT_GT(sky, 0.02 * kW * kH) << terrain << " " << objects;
        EXPECT_GT(terrain, 0.2 * kW * kH) << sky << " " << objects;
        EXPECT_GT(objects, 0.02 * kW * kH) << sky << " " << terrain;
    }
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

TEST(GazeTrace, ScriptedTraceHasSaccadesWithLandingPoints) {
    const auto d = vk::EyeDisplay::desktop_1080p();
    const GazeTrace t = GazeTrace::scripted(5.0, 3, d);
    int saccade = 0, landing = 0;
    for (const auto& s : t.samples()) {
        saccade += s.gaze.in_saccade;
        landing += s.gaze.landing_valid;
        ASSERT_TRUE(std::isfinite(s.gaze.x) && std::isfinite(s.gaze.y));
    }
    EXPECT_GT(saccade, 20);
    EXPECT_GT(landing, 10);
    EXPECT_GT(t.samples().back().t_s, 4.9);
}

}  // namespace
}  // namespace fovea::demo
