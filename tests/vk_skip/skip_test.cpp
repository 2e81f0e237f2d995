// Tile classification of method "cps" (shaders/cps_classify.comp): cost tracks what the scene
// needs. A CPU-written G-buffer (sky above a horizon, a flat wall, an over-exposed panel and a
// detailed textured floor, a camera that pans horizontally) is shaded with "full", cps with
// skipping and cps without (option cps.skip=0); counters and PSNR against the full-rate frame.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "fovea/vk/acuity.hpp"
#include "fovea/vk/foveator.hpp"
#include "gpu.hpp"
#include "vk_test_util.hpp"

namespace fovea::vk::test {
namespace {

constexpr uint32_t kW = 256, kH = 144;

// Deterministic and time-independent, so a reused shade equals a fresh one. Material 1: detailed
// stripes; 2: plain (flat); 3: over-exposed emitter with a faint texture. fovea_background
// returns exactly what fovea_shade returns for background samples.
const char* kShading = R"GLSL(
vec3 skip_sky(vec3 d) {
    return mix(vec3(0.55, 0.65, 0.85), vec3(0.15, 0.25, 0.6), clamp(d.y * 2.0, 0.0, 1.0));
}
vec3 fovea_background(FoveaGSample g, FoveaFootprint fp) { return skip_sky(g.normal); }
vec3 fovea_shade(FoveaGSample g, FoveaFootprint fp) {
    if (g.background) return skip_sky(g.normal);
    if (g.material.x > 2.5) return vec3(9.0 + sin(g.position.x * 40.0));
    float light = 0.2 + 0.8 * max(dot(g.normal, normalize(vec3(0.3, 0.8, 0.5))), 0.0);
    if (g.material.x > 1.5) return g.albedo * light;
    float stripes = 0.5 + 0.5 * sin(g.position.x * 25.0 + g.position.z * 7.0) *
                    exp(-fp.world_size * 20.0);
    return g.albedo * light * (0.6 + 0.4 * stripes);
}
)GLSL";

struct View {
    float pan_px = 0.f;       // camera pan: world x of pixel column 0
    float prev_pan_px = 0.f;  // last frame's pan (motion vectors)
    uint32_t sky_rows = 0;    // rows from the top without geometry
};

// The G-buffer images of one frame, packed as the formats of gbuffer.hpp.
std::array<std::vector<uint8_t>, kGBufferImageCount> make_gbuffer(const View& v,
                                                                  std::array<float, 2> jitter) {
    std::array<std::vector<uint8_t>, kGBufferImageCount> out;
    const size_t n = size_t{kW} * kH;
    const size_t bytes[kGBufferImageCount] = {16, 16, 4, 4};
    for (int i = 0; i < kGBufferImageCount; ++i) out[i].assign(n * bytes[i], 0);
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            const size_t i = size_t{y} * kW + x;
            const float sx = x + 0.5f + jitter[0], sy = y + 0.5f + jitter[1];
            const float wx = (sx + v.pan_px) * 0.01f;  // world x of the sample
            const bool sky = y < v.sky_rows;
            float pos[4] = {0, 0, 0, 0}, depth = 1.f, mat = 0.f;
            float nrm[3];
            uint8_t alb[3] = {0, 0, 0};
            if (sky) {
                const float dy = 1.f - sy / kH;
                const float len = std::sqrt(dy * dy + 1.f);
                nrm[0] = 0.f, nrm[1] = dy / len, nrm[2] = -1.f / len;
            } else {
                const float dist = 2.f + sy * 0.02f;
                pos[0] = wx, pos[1] = -1.f, pos[2] = -dist, pos[3] = dist;
                depth = 1.f - 0.1f / dist;
                nrm[0] = 0.f, nrm[1] = 1.f, nrm[2] = 0.f;
                const float u = sx / kW;
                mat = u < 0.3f ? 2.f : (u < 0.45f ? 3.f : 1.f);
                const bool odd = (int(std::floor(wx * 4.f)) + int(std::floor(sy * 0.04f))) & 1;
                const uint8_t a = mat == 1.f ? (odd ? 200 : 60) : 150;
                alb[0] = a, alb[1] = uint8_t(a * 0.8f), alb[2] = uint8_t(a * 0.6f);
            }
            std::memcpy(&out[0][i * 16], pos, 16);
            SurfaceSample s;
            s.normal = {nrm[0], nrm[1], nrm[2]};
            for (int c = 0; c < 3; ++c) s.albedo[size_t(c)] = float(alb[c]) / 255.f;
            s.material[0] = mat;
            const SurfaceTexel t = pack_surface(s);
            std::memcpy(&out[1][i * 16], t.data(), 16);
            std::memcpy(&out[2][i * 4], &depth, 4);
            // Current minus previous position of the jittered sample (previous view unjittered).
            const uint16_t mo[2] = {fovea::half_bits(-jitter[0] - (v.pan_px - v.prev_pan_px)),
                                    fovea::half_bits(-jitter[1])};
            std::memcpy(&out[3][i * 4], mo, 4);
        }
    return out;
}

struct Shot {
    std::vector<float> rgb;  // linear, 3 per pixel
    FrameStats stats;
};

class Host {
public:
    Host(Device& device, const std::string& method, std::vector<std::string> options,
         uint32_t jitter_length = 8)
        : device_(device) {
        FoveatorConfig c;
        c.extent = {kW, kH};
        // A desktop monitor's pixel density on a small frame (6.4 x 3.6 degrees), with a fovea
        // and a MAR slope scaled to match so the frame holds all three rates.
        const EyeDisplay desk = EyeDisplay::desktop_1080p();
        c.display = EyeDisplay::from_fov(kW, kH, desk.fov_h_deg * kW / desk.width_px,
                                         desk.fov_v_deg * kH / desk.height_px);
        c.acuity.foveal_radius_deg = 0.3f;
        c.acuity.transition_deg = 0.3f;
        c.acuity.mar_slope = 0.1f;
        c.method = method;
        c.shading_glsl = kShading;
        c.options = std::move(options);
        c.jitter_length = jitter_length;
        auto f = Foveator::create(device, c);
        if (!f) {
            error_ = f.error().message;
            return;
        }
        f_ = std::make_unique<Foveator>(std::move(*f));
    }
    bool ok() const { return f_ != nullptr; }
    const std::string& error() const { return error_; }

    Shot render(uint64_t frame, const View& v, float gaze_x, float gaze_y, bool cut = false) {
        const auto g = make_gbuffer(v, f_->jitter(frame));
        for (int i = 0; i < kGBufferImageCount; ++i)
            upload_image(device_, f_->gbuffer().images[size_t(i)], g[size_t(i)]);
        FrameInputs in;
        in.gaze.x = gaze_x;
        in.gaze.y = gaze_y;
        in.camera_pos = {v.pan_px * 0.01f, 0.f, 0.f};
        in.radians_per_pixel = 0.0008f;
        in.time_s = double(frame) / 60.0;
        in.camera_cut = cut;
        f_->render_blocking(frame, in, {});
        Shot s;
        s.stats = f_->stats();
        const std::vector<uint8_t> raw = device_.read_image(f_->output());
        s.rgb.resize(size_t{kW} * kH * 3);
        for (size_t p = 0; p < size_t{kW} * kH; ++p)
            for (int c = 0; c < 3; ++c) {
                uint16_t h;
                std::memcpy(&h, &raw[(p * 4 + size_t(c)) * 2], 2);
                s.rgb[p * 3 + size_t(c)] = fovea::half_from_bits(h);
            }
        return s;
    }
    const FoveatorConfig& config() const { return f_->config(); }

private:
    Device& device_;
    std::unique_ptr<Foveator> f_;
    std::string error_;
};

// PSNR (peak 1, values clamped to the display range) over the whole frame.
double psnr(const Shot& a, const Shot& ref) {
    double se = 0;
    for (size_t i = 0; i < a.rgb.size(); ++i) {
        const double d =
            std::clamp(double(a.rgb[i]), 0.0, 1.0) - std::clamp(double(ref.rgb[i]), 0.0, 1.0);
        se += d * d;
    }
    const double mse = se / double(a.rgb.size());
    return mse <= 1e-12 ? 120.0 : 10.0 * std::log10(1.0 / mse);
}

uint32_t shaded_tiles(const FrameStats& s) { return s.tiles[0] + s.tiles[1] + s.tiles[2]; }

#define FOVEA_HOST(name, ...)        \
    Host name(*device, __VA_ARGS__); \
    ASSERT_TRUE(name.ok()) << name.error()

// Half the frame sky: half the host shading calls (the environment function does the rest),
// and without skipping the same frame costs as much as one without sky.
TEST(CpsSkip, HalfSkyFrameShadesHalfTheSamples) {
    FOVEA_REQUIRE_DEVICE();
    FOVEA_HOST(skip, "cps", {});
    FOVEA_HOST(plain, "cps", {"cps.skip=0"});
    const View ground{0.f, 0.f, 0}, half_sky{0.f, 0.f, kH / 2};
    // Camera cuts: nothing is reused, only the background class differs between the frames.
    // The first frame of each kind is a warm-up (lavapipe compiles shaders on first use).
    skip.render(0, half_sky, 0.5f, 0.5f, true);
    plain.render(0, half_sky, 0.5f, 0.5f, true);
    const Shot a = skip.render(1, ground, 0.5f, 0.5f, true);
    const Shot b = skip.render(2, half_sky, 0.5f, 0.5f, true);
    const Shot a0 = plain.render(1, ground, 0.5f, 0.5f, true);
    const Shot b0 = plain.render(2, half_sky, 0.5f, 0.5f, true);
    const uint32_t sky_tiles = (kW / 16) * (half_sky.sky_rows / 16);  // 4 of 9 tile rows
    EXPECT_EQ(a.stats.background_tiles, 0u);
    EXPECT_EQ(b.stats.background_tiles, sky_tiles);
    EXPECT_EQ(b.stats.skipped_tiles, sky_tiles);
    EXPECT_EQ(b.stats.reused_tiles, 0u);
    const double ratio = double(b.stats.shaded_samples) / double(a.stats.shaded_samples);
    EXPECT_GT(ratio, 0.40);
    EXPECT_LT(ratio, 0.60);
    EXPECT_NEAR(double(b0.stats.shaded_samples) / double(a0.stats.shaded_samples), 1.0, 0.15);
    EXPECT_EQ(b0.stats.skipped_tiles, 0u);
    // The environment function equals the shading function on the sky: the same picture.
    EXPECT_GE(psnr(b, b0), 60.0);
    std::printf(
        "half sky / no sky: samples %.3f (unskipped %.3f), method GPU ms %.2f / %.2f "
        "(unskipped %.2f / %.2f)\n",
        ratio, double(b0.stats.shaded_samples) / double(a0.stats.shaded_samples),
        b.stats.method_gpu_ms, a.stats.method_gpu_ms, b0.stats.method_gpu_ms,
        a0.stats.method_gpu_ms);
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

// A still camera with a fixed gaze, no jitter: after two shaded frames the tiles are reused; only
// the staggered refresh (1 in cps.skip.refresh frames per tile) is shaded again.
TEST(CpsSkip, StillCameraConvergesToNearZeroShading) {
    FOVEA_REQUIRE_DEVICE();
    FOVEA_HOST(skip, "cps", {"cps.skip.refresh=30"}, 0);
    const View still{40.f, 40.f, 0};
    const uint32_t tiles = (kW / 16) * (kH / 16);
    std::vector<Shot> shots;
    for (uint64_t i = 0; i < 6; ++i) shots.push_back(skip.render(i, still, 0.4f, 0.6f, i == 0));
    EXPECT_EQ(shots[0].stats.reused_tiles, 0u);
    EXPECT_EQ(shots[1].stats.reused_tiles, 0u);  // converging: shaded twice before reuse
    for (size_t i = 2; i < shots.size(); ++i) {
        const FrameStats& s = shots[i].stats;
        EXPECT_GE(s.reused_tiles, tiles - tiles / 30 - 2) << "frame " << i;
        EXPECT_LT(s.shaded_fraction, 0.05 * shots[0].stats.shaded_fraction + 0.01) << "frame " << i;
        EXPECT_EQ(shaded_tiles(s) + s.skipped_tiles, tiles);
        EXPECT_GE(psnr(shots[i], shots[1]), 60.0) << "frame " << i;  // nothing changed
    }
    std::printf("still camera shaded fraction per frame:");
    for (const Shot& s : shots) std::printf(" %.4f", s.stats.shaded_fraction);
    std::printf("\n");
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

// With jitter (8 phases) a tile is reused once every phase was shaded still, and a reused tile
// is the shading of the frame with the same jitter: the unskipped frame, pixel for pixel.
TEST(CpsSkip, StillCameraUnderJitterReusesTheShadingOfTheSamePhase) {
    FOVEA_REQUIRE_DEVICE();
    FOVEA_HOST(skip, "cps", {"cps.skip.refresh=0"}, 8);
    FOVEA_HOST(plain, "cps", {"cps.skip=0"}, 8);
    const View still{0.f, 0.f, 0};
    const uint32_t tiles = (kW / 16) * (kH / 16);
    for (uint64_t i = 0; i < 12; ++i) {
        const Shot s = skip.render(i, still, 0.45f, 0.5f, i == 0);
        const Shot p = plain.render(i, still, 0.45f, 0.5f, i == 0);
        if (i < 8) {
            EXPECT_EQ(s.stats.reused_tiles, 0u) << "frame " << i;
        } else {
            EXPECT_EQ(s.stats.reused_tiles, tiles) << "frame " << i;
            EXPECT_EQ(s.stats.shaded_samples, 0u) << "frame " << i;
        }
        EXPECT_GE(psnr(s, p), 60.0) << "frame " << i;
    }
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

// After convergence a small gaze move re-shades exactly the tiles whose rate changed.
TEST(CpsSkip, GazeMoveReshadesOnlyTilesWhoseRateChanged) {
    FOVEA_REQUIRE_DEVICE();
    FOVEA_HOST(skip, "cps", {"cps.skip.refresh=0"}, 0);
    const View still{0.f, 0.f, 0};
    for (uint64_t i = 0; i < 2; ++i) skip.render(i, still, 0.5f, 0.5f, i == 0);
    const Shot converged = skip.render(2, still, 0.5f, 0.5f);
    const Shot moved = skip.render(3, still, 0.56f, 0.52f);
    // The acuity model's rates (flat tiles are shaded coarser but keep their acuity rate).
    const EyeDisplay& d = skip.config().display;
    const AcuityParams& a = skip.config().acuity;
    const std::vector<uint8_t> before =
        cpu_rate_tiles(d, a, converged.stats.gaze, a.tile_size, a.tile_size);
    const std::vector<uint8_t> after =
        cpu_rate_tiles(d, a, moved.stats.gaze, a.tile_size, a.tile_size);
    uint32_t changed = 0;
    for (size_t i = 0; i < before.size(); ++i) changed += before[i] != after[i];
    EXPECT_GT(changed, 5u);
    EXPECT_LT(changed, before.size() / 2);
    EXPECT_EQ(shaded_tiles(moved.stats), changed);
    EXPECT_EQ(moved.stats.reused_tiles, before.size() - changed);
    // And it equals the unskipped frame at the new gaze (no jitter, time-independent shading).
    FOVEA_HOST(plain, "cps", {"cps.skip=0"}, 0);
    const Shot ref = plain.render(3, still, 0.56f, 0.52f, true);
    EXPECT_GE(psnr(moved, ref), 60.0);
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

// Panning, then still, with a gaze move: against the full-rate frame cps with skipping loses at
// most 0.5 dB to cps without, while shading fewer samples; flat and saturated tiles are found.
TEST(CpsSkip, ErrorStaysWithinHalfADecibelOfTheUnskippedResult) {
    FOVEA_REQUIRE_DEVICE();
    FOVEA_HOST(full, "full", {});
    FOVEA_HOST(skip, "cps", {});
    FOVEA_HOST(plain, "cps", {"cps.skip=0"});
    double db_skip = 0, db_plain = 0;
    uint64_t samples_skip = 0, samples_plain = 0;
    uint32_t flat = 0, no_detail = 0;
    const int frames = 16;  // still from frame 4: reuse starts after the 8 jitter phases
    float pan = 0.f, prev = 0.f;
    for (int i = 0; i < frames; ++i) {
        if (i < 4) pan += 3.f;  // panning, then still
        const View v{pan, i == 0 ? pan : prev, kH / 3};
        prev = pan;
        const float gx = i < 13 ? 0.35f : 0.4f;
        const bool cut = i == 0;
        const Shot ref = full.render(uint64_t(i), v, gx, 0.6f, cut);
        const Shot s = skip.render(uint64_t(i), v, gx, 0.6f, cut);
        const Shot p = plain.render(uint64_t(i), v, gx, 0.6f, cut);
        db_skip += psnr(s, ref) / frames;
        db_plain += psnr(p, ref) / frames;
        samples_skip += s.stats.shaded_samples;
        samples_plain += p.stats.shaded_samples;
        flat += s.stats.flat_tiles;
        no_detail += s.stats.no_detail_tiles;
    }
    std::printf(
        "PSNR vs full rate: skip %.2f dB, unskipped %.2f dB; samples %.3f of unskipped; "
        "flat tiles %u, no-detail tiles %u\n",
        db_skip, db_plain, double(samples_skip) / double(samples_plain), flat, no_detail);
    EXPECT_GE(db_skip, db_plain - 0.5);
    EXPECT_LT(samples_skip, samples_plain * 7 / 10);
    EXPECT_GT(flat, 0u);
    EXPECT_GT(no_detail, flat);
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

}  // namespace
}  // namespace fovea::vk::test
