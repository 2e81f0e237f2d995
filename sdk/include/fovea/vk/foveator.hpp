// fovea::vk::Foveator: gaze-contingent shading of a host G-buffer with a run-time selectable
// method ("full", "cps", and the methods listed by Foveator::methods()), followed by an optional
// post-process chain (TAA, enhancement). DESIGN.md §5.
//
// Per frame, on the host's render thread:
//   1. views(frame, inputs) when the method renders from views (method "layers"; harmless
//      otherwise), jitter(frame) -> add to the projection (fovea/vk/projection.hpp); write the
//      G-buffer (gbuffer(), GENERAL layout) and every requested view.
//   2. record(cmd, frame, inputs) into the host's command buffer after those writes.
//   3. submit; after the GPU finished, stats() reads this frame's counters; output() is the final
//      linear HDR colour (GENERAL layout) and rate() the normalized shading rate S_t.
// Frames in flight (FoveatorConfig::frames_in_flight = N): record() of frame n may start while
// frames n - N + 1 .. n - 1 execute; frame n - N must have completed (the host's fence). The
// module keeps N sets of what the CPU writes or reads per frame (uniforms, counters,
// timestamps); its images are shared by all frames and ordered by the queue and the barriers.
//
// Synchronisation contract (what record() puts in `cmd` and what it expects around it):
// - Entry: one global memory barrier, src ALL_COMMANDS / MEMORY_WRITE -> dst COMPUTE_SHADER +
//   TRANSFER / MEMORY_READ | MEMORY_WRITE. Every write the host recorded earlier on the same
//   queue (this command buffer or an earlier submission) is visible to the module, whatever
//   stage made it (colour attachment, compute, transfer); the host adds no barrier of its own.
//   Writes from another queue need the host's semaphore on the submission, as usual.
// - Exit: one global memory barrier, src COMPUTE_SHADER / SHADER_WRITE -> dst ALL_COMMANDS +
//   HOST / MEMORY_READ | HOST_READ. Later commands on the queue may read output(), shaded(),
//   rate() at any stage, and may overwrite the G-buffer and views (the barrier orders them after
//   the module's reads), without a barrier of their own.
// - Layouts: every image the module hands out stays in VK_IMAGE_LAYOUT_GENERAL; a host that
//   transitions one (e.g. to use output() as a transfer source) returns it to GENERAL before
//   the next record().
// - Between frames: the host must not write the G-buffer or views while a recorded frame is
//   executing on another queue, and must not call record(), set_method(), set_post_chain() or
//   set_host_params() concurrently with each other (one render thread).
// - output() is one of the module's images, fixed between calls to set_post_chain() and
//   set_method() (which may select another ping-pong image); re-read it after those. gbuffer(),
//   shaded() and rate() never change for the Foveator's lifetime.
// - Gaze: FrameInputs::gaze may be NaN (a blink, tracking lost): the last valid gaze is held and
//   aged (GazeResolver, acuity.hpp); stats().gaze.held says so.

// The host's shading function (FoveatorConfig::shading_glsl) is GLSL compiled at run time
// (glslang) into each method's pipelines. It must define
//     vec3 fovea_shade(FoveaGSample g, FoveaFootprint fp);
// with the structs of shaders/fovea_frame.glsl: g is the G-buffer sample (position, distance,
// normal, albedo, material, depth, motion, background), fp the footprint the shade stands for, so
// it can pre-filter textures and lighting. FoveaFootprint units:
//   pixel            the region's centre in output pixels (origin top-left, pixel i spans
//                    [i, i + 1)), jitter included: where the G-buffer sample was taken
//   size_px          the region's edge in output (full-resolution) pixels: 1 at full rate, 2 or
//                    4 for coarse pixels (cps), a layer's sampling factor s (fractional, e.g. 2.3)
//                    for layers, the log-polar cell's size for kfr. A texture minified by
//                    t texels per output pixel is pre-filtered at LOD log2(t * size_px).
//   world_size       size_px times FrameInputs::radians_per_pixel times the view distance:
//                    the region's edge in world units at the sample (0 without radians_per_pixel)
//   eccentricity_deg from the resolved gaze, degrees of visual angle
//   rate_s           normalized shading rate S_t: 0 full rate .. 1 coarsest It may read the uniform
//   block fovea_frame (camera_pos, time,
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
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fovea/result.hpp"
#include "fovea/vk/acuity.hpp"
#include "fovea/vk/device.hpp"
#include "fovea/vk/gbuffer.hpp"
#include "fovea/vk/host_images.hpp"
#include "fovea/vk/vrs.hpp"

namespace fovea::vk {

inline constexpr uint32_t kMaxFramesInFlight = 4;

// How the host and the module split a frame (DESIGN.md §5; sdk/src/vk/README.md shows each in a
// page of code). Fixed for a Foveator's lifetime.
enum class IntegrationPath {
    // 1. The host writes the G-buffer (gbuffer()) and hands over its shading as GLSL; `method`
    //    shades only what it needs (cps, layers, kfr, adaptive, full).
    kDeferred,
    // 2. Guenter's setting: the host renders every eccentricity layer views() asks for with its
    //    own pipelines, colour + depth + motion into ViewRequest::targets (or its own images,
    //    FrameInputs::view_images); the module resolves and composites the layers and runs the
    //    post chain. No G-buffer, no GLSL; the method is "layers".
    kForwardLayers,
    // 3. The host renders with hardware rates from the module's rate image (rate_image(); see
    //    RateImageKind) into colour + depth + motion (host_targets() or its own images); the
    //    module runs the post chain on it. Needs the device's VRS or density-map support.
    kRateImage,
    // 4. The host renders colour + depth + motion at full rate (host_targets() or its own); the
    //    module runs only the post chain (TAA, contrast, noise) with gaze.
    kPostOnly,
};

// Path 3's hardware rate image.
enum class RateImageKind {
    kShadingRate,  // VK_KHR_fragment_shading_rate attachment (VrsAttachment)
    kDensityMap,   // VK_EXT_fragment_density_map (DensityMap)
};

struct FoveatorConfig {
    VkExtent2D extent{1920, 1080};
    IntegrationPath path = IntegrationPath::kDeferred;
    std::string method = "cps";           // path 1 only; see Foveator::methods()
    std::vector<std::string> post_chain;  // e.g. {"taa", "contrast"}; see post_passes()
    EyeDisplay display;                   // its pixel size should equal extent
    AcuityParams acuity;
    std::string shading_glsl;  // path 1: defines fovea_shade(); see above
    // Path 1: the host's own descriptor set layout (textures, light lists, shadow maps, ...),
    // bound as set FOVEA_HOST_SET (= 2) of every pipeline that runs shading_glsl; its bindings
    // must include VK_SHADER_STAGE_COMPUTE_BIT. Host-owned, outlives the Foveator. The set
    // itself comes with each frame (FrameInputs::host_set).
    VkDescriptorSetLayout host_set_layout = VK_NULL_HANDLE;
    RateImageKind rate_image = RateImageKind::kShadingRate;  // path 3
    uint32_t jitter_length = 8;  // Halton(2,3) period; 0 disables jitter
    // Frames the host may have recorded and not yet seen complete: record() of frame n needs
    // frame n - frames_in_flight completed. 1..kMaxFramesInFlight.
    uint32_t frames_in_flight = 1;
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
    bool camera_cut = false;  // history-based passes reset
    // Host-shaded paths: the host's own images, read in place of the module's targets. Paths 3
    // and 4: `host_images` for the full view (empty: host_targets() hold the frame); path 2:
    // `view_images`, one per views() request in its order (empty: every ViewRequest::targets).
    std::optional<HostFrameImages> host_images;
    std::vector<HostFrameImages> view_images;
    // Path 1 with FoveatorConfig::host_set_layout: this frame's set of that layout, bound while
    // the recorded frame runs (the host keeps it alive and unchanged until the frame completed).
    VkDescriptorSet host_set = VK_NULL_HANDLE;
};

// A view the host must render this frame besides the full-resolution one (e.g. an eccentricity
// layer, method "layers"). The host renders the normalized sub-rectangle `crop` of its full view
// (x0, y0, x1, y1 in 0..1 of the full frame, origin top-left; crop the projection, not the
// viewport: crop_projection() in projection.hpp) into the whole of `extent`, adding `jitter_px`
// (in this view's pixels): on path 1 as a G-buffer into `gbuffer`, on path 2 with its own
// shading into `targets` (or its own images of this extent, FrameInputs::view_images).
struct ViewRequest {
    std::string name;
    VkExtent2D extent{0, 0};
    GBufferRefs gbuffer;  // path 1
    HostTargets targets;  // path 2
    std::array<float, 4> crop{0.f, 0.f, 1.f, 1.f};
    std::array<float, 2> jitter_px{0.f, 0.f};
};

// Counters of the last completed frame.
struct FrameStats {
    uint64_t frame_index = 0;
    // Host shading function invocations (path 1); samples the host rendered (path 2: layer
    // texels; path 4: every pixel); path 3: fragment invocations the rate image implies.
    uint64_t shaded_samples = 0;
    uint64_t edge_samples = 0;        // of which re-shaded at coarse-pixel discontinuities
    std::array<uint32_t, 4> tiles{};  // tiles at rate 1, 2, 4, skipped
    // Tile classification (method "cps", option cps.skip; shaders/cps_classify.comp):
    uint32_t skipped_tiles = 0;     // tiles[3]: no host shading call (reused + background)
    uint32_t reused_tiles = 0;      // of which last frame's shading kept (still, converged)
    uint32_t background_tiles = 0;  // of which environment only (fovea_background)
    uint32_t flat_tiles = 0;        // shaded coarser than their acuity rate: flat or saturated
    uint32_t no_detail_tiles = 0;   // no detail to extend (background, flat or saturated)
    double shaded_fraction = 0.0;   // shaded_samples / pixels
    double method_gpu_ms = 0.0;     // GPU time of the method's passes (timestamps; 0 if none)
    double post_gpu_ms = 0.0;       // GPU time of the post chain
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
    // Path 1's G-buffer; empty (extent 0) on the other paths.
    const GBufferRefs& gbuffer() const;
    // Paths 3 and 4: the module's full-view colour, depth and motion the host renders into;
    // empty on the others.
    const HostTargets& host_targets() const;
    // Path 3: the rate image (FoveatorConfig::rate_image; fovea/vk/vrs.hpp for the render-pass
    // set-up), GENERAL layout, one texel per rate_image_texel() pixels square. Empty elsewhere.
    const ImageRef& rate_image() const;
    uint32_t rate_image_texel() const;
    // Path 3: records this frame's rate image. Call before the host's render pass that uses it
    // (same command buffer or an earlier submission), then record() after that pass.
    void record_rate_image(VkCommandBuffer cmd, const FrameInputs& inputs);
    const ImageRef& output() const;  // final colour after the post chain, RGBA16F linear
    const ImageRef& shaded() const;  // method output before the post chain
    const ImageRef& rate() const;    // S_t per pixel, R16F
    const ImageRef& rate_tiles()
        const;  // rate per tile (1, 2, 4) of the last cps-style frame, R8_UINT

    // G-buffers the host renders this frame in addition to gbuffer() (empty for most methods),
    // and whether the method reads the full-resolution gbuffer() at all. Call before record()
    // for the same frame_index: record() logs a warning (once per method) when a method with
    // views is recorded without it, since it then shades whatever those images last held.
    std::vector<ViewRequest> views(uint64_t frame_index, const FrameInputs& inputs);
    bool needs_full_gbuffer() const;

    // This frame's sub-pixel jitter in pixels (Halton(2,3)), also passed to the shaders.
    std::array<float, 2> jitter(uint64_t frame_index) const;
    // 16 vec4 of host parameters visible to the shading function as fovea_frame.host[].
    void set_host_params(const std::array<float, 64>& params);

    // Records this frame's shading and post chain. frame_index increases by one per frame.
    void record(VkCommandBuffer cmd, uint64_t frame_index, const FrameInputs& inputs);
    // Counters of the last recorded frame, after its GPU work completed.
    FrameStats stats() const;
    // Counters of frame `frame_index`, one of the last frames_in_flight recorded, after it
    // completed (FrameStats::frame_index says which frame the slot held, should it be another).
    FrameStats stats(uint64_t frame_index) const;

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
