// The Vulkan foveation core against its CPU model and its full-rate reference (issue 5).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <vector>

#include "fovea/vk/acuity.hpp"
#include "fovea/vk/foveator.hpp"
#include "fovea/vk/vrs.hpp"
#include "gpu.hpp"
#include "shaders.hpp"
#include "vk_test_util.hpp"

namespace fovea::vk {
namespace {

// A cheap host shading function with per-pixel detail: what matters here is equality, not cost.
constexpr const char* kTestShading = R"(
vec3 fovea_shade(FoveaGSample g, FoveaFootprint fp) {
    if (g.background) return vec3(0.1, 0.2, 0.3);
    float s = sin(g.position.x * 3.1) * cos(g.position.y * 2.3);
    return g.albedo * (0.5 + 0.5 * s) + vec3(0.02) * fp.size_px;
}
)";

FoveatorConfig config_for(uint32_t w, uint32_t h, const char* method) {
    FoveatorConfig c;
    c.extent = {w, h};
    c.display = EyeDisplay::from_size(w, h, 0.531 * w / 1920.0, 0.299 * h / 1080.0, 0.60);
    c.method = method;
    c.shading_glsl = kTestShading;
    return c;
}

// A G-buffer with per-pixel content: position ramps, two material regions, varying albedo.
void upload_test_gbuffer(const Device& device, const Foveator& f) {
    const VkExtent2D e = f.gbuffer().extent;
    const size_t n = size_t{e.width} * e.height;
    std::vector<float> pos(n * 4);
    std::vector<SurfaceTexel> surface(n);
    std::vector<uint16_t> motion(n * 2);
    std::vector<float> depth(n);
    for (uint32_t y = 0; y < e.height; ++y)
        for (uint32_t x = 0; x < e.width; ++x) {
            const size_t i = size_t{y} * e.width + x;
            const bool obj = (x / 37 + y / 29) % 3 == 0;
            pos[i * 4 + 0] = x * 0.05f;
            pos[i * 4 + 1] = y * 0.05f;
            pos[i * 4 + 2] = obj ? -3.f : -5.f;
            pos[i * 4 + 3] = obj ? 3.f : 5.f;
            SurfaceSample s;
            s.normal = {0.f, 0.f, 1.f};
            s.material[0] = obj ? 2.f : 1.f;
            s.albedo = {float(uint8_t(x * 7)) / 255.f, float(uint8_t(y * 5)) / 255.f,
                        obj ? 200.f / 255.f : 60.f / 255.f};
            surface[i] = pack_surface(s);
            depth[i] = obj ? 0.9f : 0.95f;
        }
    auto bytes = [](const auto& v) {
        return std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(v.data()),
                                        v.size() * sizeof(v[0]));
    };
    const GBufferRefs& g = f.gbuffer();
    upload_image(device, g[GBufferImage::kPosition], bytes(pos));
    upload_image(device, g[GBufferImage::kSurface], bytes(surface));
    upload_image(device, g[GBufferImage::kDepth], bytes(depth));
    upload_image(device, g[GBufferImage::kMotion], bytes(motion));
}

std::vector<float> read_rgba16f(const Device& device, const ImageRef& img) {
    const auto raw = device.read_image(img);
    std::vector<float> out(raw.size() / 2);
    for (size_t i = 0; i < out.size(); ++i) {
        uint16_t h;
        std::memcpy(&h, &raw[i * 2], 2);
        out[i] = fovea::half_from_bits(h);
    }
    return out;
}

uint64_t expected_coarse_samples(const std::vector<uint8_t>& tiles, uint32_t tiles_x, uint32_t w,
                                 uint32_t h, uint32_t ts) {
    uint64_t n = 0;
    for (size_t i = 0; i < tiles.size(); ++i) {
        const uint32_t tx = static_cast<uint32_t>(i % tiles_x),
                       ty = static_cast<uint32_t>(i / tiles_x);
        const uint32_t r = tiles[i];
        const uint32_t pw = std::min(ts, w - tx * ts), ph = std::min(ts, h - ty * ts);
        n += uint64_t{(pw + r - 1) / r} * ((ph + r - 1) / r);
    }
    return n;
}

TEST(AcuityModel, MarLineMatchesGuenter) {
    AcuityParams a;
    EXPECT_NEAR(mar_deg(a, 0.f), 1.0f / 48.0f, 1e-7);
    EXPECT_NEAR(mar_deg(a, 20.f), 0.022f * 20.f + 1.0f / 48.0f, 1e-6);
    a.mar_slope = 0.034f;
    EXPECT_NEAR(mar_deg(a, 10.f), 0.34f + 1.0f / 48.0f, 1e-6);
}

TEST(AcuityModel, DesktopPresetMatchesGeometry) {
    const EyeDisplay d = EyeDisplay::desktop_1080p();
    EXPECT_NEAR(d.fov_h_deg, 47.75f, 0.05f);
    // A flat screen's centre pixels subtend the largest angle: tan(1 deg) * 0.60 / 0.531 * 1920.
    EXPECT_NEAR(d.pixels_per_degree(), 37.87f, 0.05f);
    // Eccentricity along the horizontal axis is exactly the visual angle (Stengel Eq. 3).
    const float e = eccentricity_deg(d, 1920.f, 540.f, 960.f, 540.f);
    EXPECT_NEAR(e, d.fov_h_deg * 0.5f, 0.01f);
}

TEST(AcuityModel, RateIsFullInsideFoveaAndGrowsWithEccentricity) {
    const EyeDisplay d = EyeDisplay::desktop_1080p();
    const AcuityParams a;
    const ResolvedGaze g = resolve_gaze(GazeState{}, d, a);
    EXPECT_FLOAT_EQ(rate_at(d, a, g, 960.f, 540.f), 1.f);
    EXPECT_FLOAT_EQ(rate_at(d, a, g, 960.f + 4.5f * 41.f, 540.f), 1.f);
    float prev = 1.f;
    for (float x = 960.f; x < 1920.f; x += 20.f) {
        const float r = rate_at(d, a, g, x, 540.f);
        EXPECT_GE(r, prev - 1e-5f) << x;
        prev = r;
    }
    EXPECT_GE(prev, 4.f);
}

TEST(AcuityModel, UncertaintyAndAgeWidenTheFovea) {
    const EyeDisplay d = EyeDisplay::desktop_1080p();
    const AcuityParams a;
    GazeState g;
    const ResolvedGaze sharp = resolve_gaze(g, d, a);
    g.uncertainty_deg = 1.0f;
    g.age_s = 0.5f;
    const ResolvedGaze wide = resolve_gaze(g, d, a);
    EXPECT_NEAR(wide.margin_deg, 2.f * 1.0f + 0.5f * 1.0f, 1e-5);
    const float x = 960.f + 6.f * 41.f;  // 6 deg: in the transition for the sharp gaze
    EXPECT_GT(rate_at(d, a, sharp, x, 540.f), 1.f);
    EXPECT_FLOAT_EQ(rate_at(d, a, wide, x, 540.f), 1.f);
}

TEST(AcuityModel, SaccadeUsesPredictedLanding) {
    const EyeDisplay d = EyeDisplay::desktop_1080p();
    GazeState g;
    g.x = 0.2f;
    g.in_saccade = true;
    g.landing_valid = true;
    g.landing_x = 0.8f;
    g.landing_y = 0.3f;
    g.landing_uncertainty_deg = 1.5f;
    const ResolvedGaze r = resolve_gaze(g, d, AcuityParams{});
    EXPECT_TRUE(r.used_landing);
    EXPECT_FLOAT_EQ(r.x_px, 0.8f * 1920.f);
    EXPECT_FLOAT_EQ(r.margin_deg, 3.0f);
}

TEST(AcuityModel, NanGazeFallsBackToCentre) {
    const EyeDisplay d = EyeDisplay::desktop_1080p();
    GazeState g;
    g.x = std::numeric_limits<float>::quiet_NaN();
    const ResolvedGaze r = resolve_gaze(g, d, AcuityParams{});
    EXPECT_TRUE(r.fell_back);
    EXPECT_FLOAT_EQ(r.x_px, 960.f);
    EXPECT_FLOAT_EQ(r.y_px, 540.f);
    g.x = std::numeric_limits<float>::infinity();
    EXPECT_TRUE(resolve_gaze(g, d, AcuityParams{}).fell_back);
}

// A blink (NaN gaze) keeps the fovea where the eye last was, ageing the held gaze by the frame
// time so the margin widens; only before any valid gaze does the centre stand in.
TEST(GazeResolver, HoldsLastValidGazeThroughNanAndAgesIt) {
    const EyeDisplay d = EyeDisplay::desktop_1080p();
    AcuityParams a;
    GazeResolver r(d, a);
    GazeState nan;
    nan.x = nan.y = std::numeric_limits<float>::quiet_NaN();
    const ResolvedGaze first = r.resolve(nan, 0.0);
    EXPECT_TRUE(first.fell_back);
    EXPECT_FALSE(first.held);
    EXPECT_FLOAT_EQ(first.x_px, 960.f);

    GazeState g;
    g.x = 0.2f;
    g.y = 0.7f;
    g.age_s = 0.02f;
    const ResolvedGaze valid = r.resolve(g, 1.0);
    EXPECT_FALSE(valid.held);
    EXPECT_FLOAT_EQ(valid.x_px, 0.2f * 1920.f);

    const ResolvedGaze held = r.resolve(nan, 1.25);
    EXPECT_TRUE(held.held);
    EXPECT_FALSE(held.fell_back);
    EXPECT_FLOAT_EQ(held.x_px, valid.x_px);
    EXPECT_FLOAT_EQ(held.y_px, valid.y_px);
    EXPECT_NEAR(held.margin_deg, valid.margin_deg + 0.25f * a.drift_dps, 1e-5f);

    GazeState inf = g;
    inf.y = std::numeric_limits<float>::infinity();
    EXPECT_TRUE(r.resolve(inf, 1e6).held);
    EXPECT_FLOAT_EQ(r.resolve(inf, 1e6).margin_deg, a.max_margin_deg);  // capped, never inf
    EXPECT_TRUE(r.resolve(nan, std::numeric_limits<double>::quiet_NaN()).held);
    r.reset();
    EXPECT_TRUE(r.resolve(nan, 2.0).fell_back);
}

// In a saccade the landing prediction alone is a valid gaze, even when the position is NaN.
TEST(GazeResolver, FiniteLandingCountsAsValid) {
    const EyeDisplay d = EyeDisplay::desktop_1080p();
    GazeResolver r(d, AcuityParams{});
    GazeState s;
    s.x = s.y = std::numeric_limits<float>::quiet_NaN();
    s.in_saccade = s.landing_valid = true;
    s.landing_x = 0.9f;
    s.landing_y = 0.1f;
    const ResolvedGaze out = r.resolve(s, 0.0);
    EXPECT_TRUE(out.used_landing);
    EXPECT_FALSE(out.held);
    EXPECT_FLOAT_EQ(out.x_px, 0.9f * 1920.f);
}

TEST(AcuityModel, HaltonJitterIsInRangeAndPeriodic) {
    float x0, y0, x1, y1;
    for (uint64_t i = 0; i < 64; ++i) {
        halton_jitter(i, 8, x0, y0);
        halton_jitter(i + 8, 8, x1, y1);
        EXPECT_GE(x0, -0.5f);
        EXPECT_LT(x0, 0.5f);
        EXPECT_GE(y0, -0.5f);
        EXPECT_LT(y0, 0.5f);
        EXPECT_EQ(x0, x1);
        EXPECT_EQ(y0, y1);
    }
    halton_jitter(0, 8, x0, y0);
    EXPECT_FLOAT_EQ(x0, 0.0f);  // Halton(2) index 1 = 1/2
    EXPECT_FLOAT_EQ(y0, 1.f / 3.f - 0.5f);
    halton_jitter(5, 0, x0, y0);
    EXPECT_EQ(x0, 0.f);
}

// The classification pass's per-tile rate equals the CPU model texel by texel, for gaze at the
// centre, the corners, off screen and NaN.
TEST(CoarsePixelShading, RateTilesMatchCpuModelTexelByTexel) {
    FOVEA_REQUIRE_DEVICE();
    auto f = Foveator::create(*device, config_for(1920, 1080, "cps"));
    ASSERT_TRUE(f) << f.error().message;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::array<std::array<float, 2>, 7> gazes{{{0.5f, 0.5f},
                                                     {0.f, 0.f},
                                                     {1.f, 1.f},
                                                     {0.f, 1.f},
                                                     {1.7f, -0.4f},
                                                     {-30.f, 0.5f},
                                                     {nan, nan}}};
    const FoveatorConfig& c = f->config();
    const uint32_t ts = c.acuity.tile_size;
    for (const auto& gz : gazes) {
        FrameInputs in;
        in.gaze.x = gz[0];
        in.gaze.y = gz[1];
        f->render_blocking(0, in, {});
        const FrameStats s = f->stats();
        const auto gpu = device->read_image(f->rate_tiles());
        const auto cpu = cpu_rate_tiles(c.display, c.acuity, s.gaze, ts, ts);
        ASSERT_EQ(gpu.size(), cpu.size());
        size_t mismatches = 0;
        for (size_t i = 0; i < cpu.size(); ++i) mismatches += gpu[i] != cpu[i];
        EXPECT_EQ(mismatches, 0u) << "gaze " << gz[0] << "," << gz[1];
        EXPECT_EQ(s.gaze.held, std::isnan(gz[0]));  // holds the previous gaze (off screen)
        // Work is proportional to the samples shaded: exactly one shade per coarse pixel
        // (this G-buffer is uniform, so there are no edge re-shades).
        const uint32_t tiles_x = (1920 + ts - 1) / ts;
        EXPECT_EQ(s.shaded_samples - s.edge_samples,
                  expected_coarse_samples(cpu, tiles_x, 1920, 1080, ts));
        EXPECT_EQ(s.edge_samples, 0u);
        EXPECT_EQ(uint64_t{s.tiles[0]} + s.tiles[1] + s.tiles[2], cpu.size());
    }
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

TEST(CoarsePixelShading, DefaultSettingsShadeAtMostThirtyPercent) {
    FOVEA_REQUIRE_DEVICE();
    auto f = Foveator::create(*device, config_for(1920, 1080, "cps"));
    ASSERT_TRUE(f) << f.error().message;
    f->render_blocking(0, FrameInputs{}, {});
    const FrameStats s = f->stats();
    EXPECT_LE(s.shaded_fraction, 0.30);
    EXPECT_GT(s.shaded_fraction, 0.02);
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

// Foveal pixels (rate-1 tiles) equal the full-rate reference; S_t is 0 there and 0.5/1 in
// coarser tiles; discontinuities inside coarse pixels are re-shaded.
TEST(CoarsePixelShading, FovealPixelsEqualFullRateReference) {
    FOVEA_REQUIRE_DEVICE();
    FoveatorConfig c = config_for(256, 256, "full");
    // A small target that still spans all three rates: 20 deg field, steep MAR slope.
    c.display = EyeDisplay::from_fov(256, 256, 20.0, 20.0);
    c.acuity.foveal_radius_deg = 2.f;
    c.acuity.transition_deg = 2.f;
    c.acuity.mar_slope = 0.1f;
    auto f = Foveator::create(*device, c);
    ASSERT_TRUE(f) << f.error().message;
    upload_test_gbuffer(*device, *f);
    FrameInputs in;
    in.gaze.x = 0.3f;
    in.gaze.y = 0.6f;
    f->render_blocking(0, in, {});
    const auto ref = read_rgba16f(*device, f->output());
    ASSERT_TRUE(f->set_method("cps"));
    f->render_blocking(1, in, {});
    const FrameStats s = f->stats();
    const auto cps = read_rgba16f(*device, f->output());
    const auto rate = device->read_image(f->rate());
    const auto tiles = device->read_image(f->rate_tiles());
    EXPECT_GT(s.tiles[0], 0u);
    EXPECT_GT(s.tiles[2], 0u);
    EXPECT_GT(s.edge_samples, 0u);
    const uint32_t ts = c.acuity.tile_size, tiles_x = (256 + ts - 1) / ts;
    size_t foveal = 0, bad = 0, rate_bad = 0;
    double peripheral_err = 0.0;
    for (uint32_t y = 0; y < 256; ++y)
        for (uint32_t x = 0; x < 256; ++x) {
            const size_t i = size_t{y} * 256 + x;
            const uint8_t r = tiles[(y / ts) * tiles_x + x / ts];
            uint16_t sh;
            std::memcpy(&sh, &rate[i * 2], 2);
            rate_bad += fovea::half_from_bits(sh) != normalized_rate(r);
            for (int ch = 0; ch < 3; ++ch) {
                const float d = std::abs(cps[i * 4 + ch] - ref[i * 4 + ch]);
                if (r == 1)
                    bad += d > 1.0f / 255.0f;
                else
                    peripheral_err += d;
            }
            foveal += r == 1;
        }
    EXPECT_GT(foveal, 1000u);
    EXPECT_EQ(bad, 0u);
    EXPECT_EQ(rate_bad, 0u);
    EXPECT_GT(peripheral_err, 0.0);  // the periphery really is shaded coarsely
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

TEST(Foveator, TinyAndHugeTargetsWork) {
    FOVEA_REQUIRE_DEVICE();
    for (const auto& [w, h] :
         std::array<std::pair<uint32_t, uint32_t>, 2>{{{1, 1}, {7680, 4320}}}) {
        auto f = Foveator::create(*device, config_for(w, h, "cps"));
        ASSERT_TRUE(f) << f.error().message;
        FrameInputs in;
        in.gaze.x = 0.9f;
        f->render_blocking(0, in, {});
        const FrameStats s = f->stats();
        EXPECT_GE(s.shaded_samples, 1u);
        EXPECT_LE(s.shaded_fraction, 1.0);
        if (w > 1) { EXPECT_LE(s.shaded_fraction, 0.30); }
    }
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

TEST(Foveator, PostChainRunsAndCopies) {
    FOVEA_REQUIRE_DEVICE();
    FoveatorConfig c = config_for(64, 48, "cps");
    c.post_chain = {"copy", "copy", "copy"};
    auto f = Foveator::create(*device, c);
    ASSERT_TRUE(f) << f.error().message;
    upload_test_gbuffer(*device, *f);
    f->render_blocking(0, FrameInputs{}, {});
    EXPECT_NE(f->output().image, f->shaded().image);
    EXPECT_EQ(device->read_image(f->output()), device->read_image(f->shaded()));
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

// TAA writes the display luminance an enhancement pass after it would compute first; with a copy
// in between the enhancement computes it itself. Both must give the same bytes, frame after frame.
TEST(Foveator, TaaHandsTheEnhancementPassTheLuminanceItWouldCompute) {
    FOVEA_REQUIRE_DEVICE();
    for (const char* enhancement : {"contrast", "noise"}) {
        // Wide and coarse enough that the periphery has a noise band (F_L / ppd < 1/2).
        FoveatorConfig c = config_for(640, 400, "cps");
        c.display = EyeDisplay::from_fov(640, 400, 50.0, 32.0);
        c.acuity.foveal_radius_deg = 2.f;
        c.acuity.transition_deg = 2.f;
        c.acuity.mar_slope = 0.1f;
        c.post_chain = {"taa", enhancement};
        auto fused = Foveator::create(*device, c);
        c.post_chain = {"taa", "copy", enhancement};
        auto apart = Foveator::create(*device, c);
        c.post_chain = {"taa"};
        auto plain = Foveator::create(*device, c);
        ASSERT_TRUE(fused) << fused.error().message;
        ASSERT_TRUE(apart) << apart.error().message;
        ASSERT_TRUE(plain) << plain.error().message;
        for (Foveator* f : {&*fused, &*apart, &*plain}) upload_test_gbuffer(*device, *f);
        bool enhanced = false;
        for (uint64_t i = 0; i < 4; ++i) {
            FrameInputs in;
            in.gaze.x = 0.1f + 0.05f * float(i);
            in.gaze.y = 0.4f;
            fused->render_blocking(i, in, {});
            apart->render_blocking(i, in, {});
            plain->render_blocking(i, in, {});
            const auto out = device->read_image(fused->output());
            EXPECT_EQ(out, device->read_image(apart->output())) << enhancement << " frame " << i;
            enhanced = enhanced || out != device->read_image(plain->output());
        }
        EXPECT_TRUE(enhanced) << enhancement << " changed nothing: the comparison proves nothing";
    }
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

// A host alternating methods frame by frame (fovea bench, the demo) must not blend one method's
// frame into another's TAA history: each method keeps its own post-chain instance.
TEST(Foveator, EachMethodKeepsItsOwnPostChainHistory) {
    FOVEA_REQUIRE_DEVICE();
    FoveatorConfig c = config_for(64, 48, "full");
    c.display = EyeDisplay::from_fov(64, 48, 40.0, 30.0);  // wide: a coarse periphery
    c.acuity.foveal_radius_deg = 2.f;
    c.acuity.transition_deg = 2.f;
    c.acuity.mar_slope = 0.1f;
    c.post_chain = {"taa"};
    auto alone = Foveator::create(*device, c);
    auto mixed = Foveator::create(*device, c);
    ASSERT_TRUE(alone) << alone.error().message;
    ASSERT_TRUE(mixed) << mixed.error().message;
    upload_test_gbuffer(*device, *alone);
    upload_test_gbuffer(*device, *mixed);
    FrameInputs in;
    in.gaze.x = 0.2f;
    in.gaze.y = 0.3f;
    bool cps_differs = false;
    for (uint64_t i = 0; i < 3; ++i) {
        alone->render_blocking(i, in, {});
        ASSERT_TRUE(mixed->set_method("full"));
        mixed->render_blocking(i, in, {});
        const auto full = device->read_image(mixed->output());
        EXPECT_EQ(device->read_image(alone->output()), full) << "frame " << i;
        ASSERT_TRUE(mixed->set_method("cps"));
        mixed->render_blocking(i, in, {});
        cps_differs = cps_differs || device->read_image(mixed->output()) != full;
    }
    EXPECT_TRUE(cps_differs);  // otherwise a shared history would go unnoticed
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

TEST(Foveator, BadInputIsAnErrorNotACrash) {
    FOVEA_REQUIRE_DEVICE();
    FoveatorConfig c = config_for(64, 64, "cps");
    c.shading_glsl = "vec3 fovea_shade(FoveaGSample g, FoveaFootprint fp) { return oops; }";
    auto bad_glsl = Foveator::create(*device, c);
    ASSERT_FALSE(bad_glsl);
    EXPECT_NE(bad_glsl.error().message.find("oops"), std::string::npos) << bad_glsl.error().message;
    c = config_for(64, 64, "no-such-method");
    auto bad_method = Foveator::create(*device, c);
    ASSERT_FALSE(bad_method);
    EXPECT_NE(bad_method.error().message.find("cps"), std::string::npos);
    c = config_for(64, 64, "cps");
    c.extent = {0, 64};
    EXPECT_FALSE(Foveator::create(*device, c));
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

// Validation asked for and not installed is an error, so no "zero validation errors" check can pass
// without the layer. The loader finds no explicit layer when VK_LAYER_PATH names an empty folder.
TEST(Device, ValidationRequestedButNotInstalledIsAnError) {
    FOVEA_REQUIRE_DEVICE();
    const std::string empty = std::string(FOVEA_BINARY_DIR) + "/tests/vk/no_layers";
    std::filesystem::create_directories(empty);
    const char* saved = std::getenv("VK_LAYER_PATH");
    const std::string saved_value = saved ? saved : "";
    ::setenv("VK_LAYER_PATH", empty.c_str(), 1);
    DeviceOptions o;
    o.validation = true;
    auto d = Device::create_headless(o);
    if (saved)
        ::setenv("VK_LAYER_PATH", saved_value.c_str(), 1);
    else
        ::unsetenv("VK_LAYER_PATH");
    ASSERT_FALSE(d) << "validation silently off";
    EXPECT_EQ(d.error().code, static_cast<int>(VK_ERROR_LAYER_NOT_PRESENT));
    EXPECT_NE(d.error().message.find("vulkan-validationlayers"), std::string::npos)
        << d.error().message;
    o.validation = false;
    auto plain = Device::create_headless(o);
    ASSERT_TRUE(plain) << plain.error().message;
    EXPECT_FALSE(plain->validation_enabled());
    EXPECT_EQ(device->validation_enabled(), test::kValidation);
    EXPECT_EQ(device->validation_errors(), validation_errors_before);
}

// The hardware path: lavapipe has no VK_KHR_fragment_shading_rate, which is reported cleanly;
// the attachment image itself is generated and read back, equal to the CPU model.
TEST(VrsAttachment, ReportsSupportAndImageMatchesCpuModel) {
    FOVEA_REQUIRE_DEVICE();
    const VrsSupport s = VrsAttachment::supported(*device);
    if (!s.supported) {
        EXPECT_FALSE(s.reason.empty());
        EXPECT_FALSE(VrsAttachment::create(*device, EyeDisplay::desktop_1080p()));
    }
    const EyeDisplay d = EyeDisplay::desktop_1080p();
    const AcuityParams a;
    for (uint32_t texel : {8u, 16u, 32u}) {
        auto vrs = VrsAttachment::create(*device, d, texel, texel, true);
        ASSERT_TRUE(vrs) << vrs.error().message;
        GazeState g;
        g.x = 0.25f;
        g.y = 0.7f;
        const ResolvedGaze rg = resolve_gaze(g, d, a);
        device->submit_and_wait([&](VkCommandBuffer cmd) { vrs->record(cmd, a, rg); });
        const auto gpu = device->read_image(vrs->image());
        const auto cpu = cpu_vrs_texels(d, a, rg, texel, texel);
        ASSERT_EQ(gpu.size(), cpu.size());
        size_t mismatches = 0, first = cpu.size();
        for (size_t i = 0; i < cpu.size(); ++i)
            if (gpu[i] != cpu[i]) {
                ++mismatches;
                first = std::min(first, i);
            }
        EXPECT_EQ(mismatches, 0u) << "texel " << texel << ", first at " << first << ": gpu "
                                  << int(first < cpu.size() ? gpu[first] : 0) << " cpu "
                                  << int(first < cpu.size() ? cpu[first] : 0);
        // Encodings present: 1x1 (0), 2x2 ((1 << 2) | 1 = 5), 4x4 ((2 << 2) | 2 = 10).
        EXPECT_NE(std::find(gpu.begin(), gpu.end(), 0), gpu.end());
        EXPECT_NE(std::find(gpu.begin(), gpu.end(), 10), gpu.end());
    }
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

}  // namespace
}  // namespace fovea::vk
