// fovea::vk::Foveator: gaze-contingent shading of a host G-buffer with a run-time selectable
// method ("full", "cps", and the methods listed by Foveator::methods()), followed by an optional
// post-process chain (TAA, enhancement). DESIGN.md §5.
//
// Per frame, on the host's render thread:
//   1. jitter(frame) -> add to the projection; write the G-buffer (gbuffer(), GENERAL layout).
//   2. record(cmd, inputs) into the host's command buffer after the G-buffer writes; the module
//      inserts the barriers it needs between its own passes and before reading the G-buffer.
//   3. submit; after the GPU finished, stats() reads this frame's counters; output() is the final
//      linear HDR colour (GENERAL layout) and rate() the normalized shading rate S_t.
// One frame in flight: the previous recorded frame must have completed before the next record().
//
// The host's shading function (FoveatorConfig::shading_glsl) is GLSL compiled at run time
// (glslang) into each method's pipelines. It must define
//     vec3 fovea_shade(FoveaGSample g, FoveaFootprint fp);
// with the structs of shaders/fovea_frame.glsl: g is the G-buffer sample (position, distance,
// normal, albedo, material, depth, motion, background), fp the footprint the shade stands for
// (pixel centre, size_px full-resolution pixels, world_size, eccentricity_deg, rate_s) so it can
// pre-filter textures and lighting. It may read the uniform block fovea_frame (camera_pos, time,
// host[16] set with set_host_params) and may declare its own functions and constants; it must be
// deterministic (the foveal region must equal the full-rate reference) and write nothing.
//
// Optionally it also defines the environment alone,
//     vec3 fovea_background(FoveaGSample g, FoveaFootprint fp);
// returning what fovea_shade returns for a background sample (g.background: no geometry, g.normal
// the view direction in the demo), at most cheaper. Method "cps" then shades tiles whose every
// pixel is background with it instead of fovea_shade (these shades are not counted in
// shaded_samples; FrameStats::background_tiles). Without it, background is shaded as before.
// The module detects it by name in shading_glsl. Method "cps" also reuses the shading of still
// tiles (FrameStats::reused_tiles): fovea_shade should then depend on the G-buffer, the
// footprint and fovea_frame only slowly through time (reused tiles are refreshed every
// cps.skip.refresh frames), and the G-buffer's motion must show object motion; see
// sdk/src/vk/README.md "Skipping what the scene doesn't need".
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "fovea/result.hpp"
#include "fovea/vk/acuity.hpp"
#include "fovea/vk/device.hpp"
#include "fovea/vk/gbuffer.hpp"

namespace fovea::vk {

struct FoveatorConfig {
    VkExtent2D extent{1920, 1080};
    std::string method = "cps";            // see Foveator::methods()
    std::vector<std::string> post_chain;   // e.g. {"taa", "contrast"}; see post_passes()
    EyeDisplay display;                    // its pixel size should equal extent
    AcuityParams acuity;
    std::string shading_glsl;              // defines fovea_shade(); see above
    uint32_t jitter_length = 8;            // Halton(2,3) period; 0 disables jitter
    // Method- or pass-specific options as "key=value" strings (e.g. "layers.count=3"); unknown
    // keys are ignored by the others.
    std::vector<std::string> options;
};

// What the host knows about this frame.
struct FrameInputs {
    GazeState gaze;
    std::array<float, 3> camera_pos{0.f, 0.f, 0.f};
    float radians_per_pixel = 0.0f;  // view-centre pixel angle, for footprint world sizes
    double time_s = 0.0;
    bool camera_cut = false;         // history-based passes reset
};

// An extra G-buffer the host must render this frame besides the full-resolution one (e.g. an
// eccentricity layer, method "layers"). The host renders the normalized sub-rectangle `crop` of
// its full view (x0, y0, x1, y1 in 0..1 of the full frame, origin top-left; crop the projection,
// not the viewport) into the whole of `gbuffer`, adding `jitter_px` (in this view's pixels).
struct ViewRequest {
    std::string name;
    GBufferRefs gbuffer;
    std::array<float, 4> crop{0.f, 0.f, 1.f, 1.f};
    std::array<float, 2> jitter_px{0.f, 0.f};
};

// Counters of the last completed frame.
struct FrameStats {
    uint64_t frame_index = 0;
    uint64_t shaded_samples = 0;   // host shading function invocations
    uint64_t edge_samples = 0;     // of which re-shaded at coarse-pixel discontinuities
    std::array<uint32_t, 4> tiles{};  // tiles at rate 1, 2, 4, skipped
    // Tile classification (method "cps", option cps.skip; shaders/cps_classify.comp):
    uint32_t skipped_tiles = 0;     // tiles[3]: no host shading call (reused + background)
    uint32_t reused_tiles = 0;      // of which last frame's shading kept (still, converged)
    uint32_t background_tiles = 0;  // of which environment only (fovea_background)
    uint32_t flat_tiles = 0;        // shaded coarser than their acuity rate: flat or saturated
    uint32_t no_detail_tiles = 0;   // no detail to extend (background, flat or saturated)
    double shaded_fraction = 0.0;  // shaded_samples / pixels
    double method_gpu_ms = 0.0;    // GPU time of the method's passes (timestamps; 0 if none)
    double post_gpu_ms = 0.0;      // GPU time of the post chain
    ResolvedGaze gaze;
};

class Foveator {
public:
    // Builds every pipeline (compiles the host GLSL; errors carry glslang's log). Blocking.
    static Result<Foveator> create(const Device& device, FoveatorConfig config);

    Foveator(Foveator&&) noexcept;
    Foveator& operator=(Foveator&&) noexcept;
    Foveator(const Foveator&) = delete;
    Foveator& operator=(const Foveator&) = delete;
    ~Foveator();

    // Names of the compiled-in methods and post passes (registry order).
    static std::vector<std::string> methods();
    static std::vector<std::string> post_passes();

    // Switches the method; builds its pipelines on first use. Not while a frame is in flight.
    Result<void> set_method(std::string_view name);
    const std::string& method() const;
    Result<void> set_post_chain(const std::vector<std::string>& names);

    const FoveatorConfig& config() const;
    const GBufferRefs& gbuffer() const;
    const ImageRef& output() const;       // final colour after the post chain, RGBA16F linear
    const ImageRef& shaded() const;       // method output before the post chain
    const ImageRef& rate() const;         // S_t per pixel, R16F
    const ImageRef& rate_tiles() const;   // rate per tile (1, 2, 4) of the last cps-style frame, R8_UINT

    // G-buffers the host renders this frame in addition to gbuffer() (empty for most methods),
    // and whether the method reads the full-resolution gbuffer() at all.
    std::vector<ViewRequest> views(uint64_t frame_index, const FrameInputs& inputs);
    bool needs_full_gbuffer() const;

    // This frame's sub-pixel jitter in pixels (Halton(2,3)), also passed to the shaders.
    std::array<float, 2> jitter(uint64_t frame_index) const;
    // 16 vec4 of host parameters visible to the shading function as fovea_frame.host[].
    void set_host_params(const std::array<float, 64>& params);

    // Records this frame's shading and post chain. frame_index increases by one per frame.
    void record(VkCommandBuffer cmd, uint64_t frame_index, const FrameInputs& inputs);
    // After the frame's GPU work completed.
    FrameStats stats() const;

    // Convenience for headless hosts: writes nothing itself; records `before` (G-buffer), the
    // frame, submits and waits. Returns wall-clock milliseconds of the submit.
    double render_blocking(uint64_t frame_index, const FrameInputs& inputs,
                           const std::function<void(VkCommandBuffer)>& before);

private:
    struct Impl;
    explicit Foveator(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace fovea::vk
