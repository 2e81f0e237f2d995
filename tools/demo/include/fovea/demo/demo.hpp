// The demo host app pieces (DESIGN.md §6): a scene in code rasterized into the module's G-buffer,
// its expensive procedural shading function, a scripted camera path, a gaze trace with saccades,
// and the runner that renders the same frames with several methods against the full-rate
// reference, with PSNR/SSIM over the fovea and per eccentricity band. All calls on one thread.
#pragma once

#include <array>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "fovea/demo/raster.hpp"
#include "fovea/metrics/pooling.hpp"
#include "fovea/result.hpp"
#include "fovea/vk/acuity.hpp"
#include "fovea/vk/foveator.hpp"
#include "gpu.hpp"

namespace fovea::demo {

enum class SceneKind { kDemo = 0, kZonePlate = 1, kGrating = 2 };

struct Camera {
    std::array<float, 3> pos{0.f, 0.f, 0.f}, right{1.f, 0.f, 0.f}, up{0.f, 1.f, 0.f},
        fwd{0.f, 0.f, -1.f};
    float tan_x = 0.5f, tan_y = 0.5f;  // tan of the half field of view
};

// The scripted fly-over at time t (seconds); eye_offset_m shifts along `right` (HMD eyes).
Camera camera_at(double t_s, const vk::EyeDisplay& display, float eye_offset_m = 0.f);
// Test targets: camera at the origin looking down -z; the target plane is z = -1.
Camera target_camera(const vk::EyeDisplay& display);
// GLSL of the demo's shading function (shaders/demo_shading.glsl).
std::string shading_glsl();

class SceneRenderer {
public:
    explicit SceneRenderer(const vk::Device& device);
    void begin_frame();  // before recording a frame's views (slots are reused per frame)
    // Rasterizes the crop of the view (0..1 of the full frame) into `gbuffer`, with jitter in
    // pixels of the gbuffer. prev: the previous frame's camera, for motion vectors.
    void record(VkCommandBuffer cmd, const vk::GBufferRefs& gbuffer, SceneKind scene,
                const Camera& cam, const Camera& prev, double time_s,
                std::array<float, 4> crop = {0.f, 0.f, 1.f, 1.f},
                std::array<float, 2> jitter = {0.f, 0.f});
    // GPU milliseconds of the last completed frame's G-buffer passes (all views; timestamps,
    // 0 where the device has none). Call after the frame's submission finished.
    double gpu_ms() const;

private:
    const vk::Device* device_;
    vk::UniqueQueryPool queries_;  // a begin/end timestamp pair per view slot
    uint32_t view_stride_;         // bytes per view slot of views_
    vk::Buffer views_;
    BufferSetLayout layout_;
    GBufferRenderPass pass_;
    GraphicsPipeline terrain_, objects_, sky_, target_;
    std::map<std::pair<uint32_t, uint32_t>, DepthImage> depth_;  // by view width, height
    uint32_t slot_ = 0;
};

// Gaze over time, normalized display coordinates.
class GazeTrace {
public:
    struct Sample {
        double t_s;
        vk::GazeState gaze;
    };
    // Fixations (200-450 ms, fixational noise) joined by saccades on the main sequence
    // (D = 2.2 A + 21 ms, minimum-jerk profile) with the landing point predicted in flight.
    static GazeTrace scripted(double duration_s, uint64_t seed, const vk::EyeDisplay& display);
    // CSV: header line, then t_s,x,y[,event,landing_x,landing_y,landing_uncertainty_deg,
    // uncertainty_deg]; event 2 = saccade (fovea_event). Bad lines are counted, not fatal.
    static Result<GazeTrace> load(const std::string& path, size_t* dropped_lines = nullptr);
    vk::GazeState at(double t_s) const;  // nearest earlier sample
    const std::vector<Sample>& samples() const { return samples_; }

private:
    std::vector<Sample> samples_;
};

struct Rgb8 {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> rgb;
};
// Linear HDR RGBA16F (as read back) -> display RGB8: exposure tone curve then sRGB (the GPU FLIP's
// metrics::FlipInput::kDemoDisplay is the same transform; tests/metrics pins both together).
Rgb8 tonemap(const std::vector<uint8_t>& rgba16f, uint32_t width, uint32_t height);
// S_t (R16F) -> a colour map: blue full rate, green 2x2, red 4x4.
Rgb8 rate_map(const std::vector<uint8_t>& r16f, uint32_t width, uint32_t height);
bool write_png(const std::string& path, const Rgb8& image);  // fovea::metrics::write_png

// Per pixel of a frame: its eccentricity band (vk::kBandEdgesDeg) and whether it lies within the
// foveal radius of the gaze. The metrics work in the rendered image's pixels, the model in the
// display's.
struct BandLabels {
    std::vector<int8_t> band;   // 0 .. kBandCount - 1
    std::vector<int8_t> fovea;  // 0 inside the foveal radius, -1 outside
};
BandLabels band_labels(uint32_t width, uint32_t height, const vk::EyeDisplay& display,
                       const vk::ResolvedGaze& gaze, float foveal_radius_deg);

// PSNR and SSIM pooled over every frame added (fovea::metrics::RegionSums): squared errors summed
// before the one log, no cap (identical frames give +inf), SSIM averaged over every pixel.
struct ErrorFigures {
    double psnr_db = 0.0;        // the whole frame
    double psnr_fovea_db = 0.0;  // pixels within the foveal radius of the gaze
    std::array<double, vk::kBandCount> psnr_bands_db{};  // NaN for bands no frame reached
    std::array<double, vk::kBandCount> ssim_bands{};
};
class ErrorPool {
public:
    void add(const Rgb8& test, const Rgb8& reference, const BandLabels& labels);
    ErrorFigures figures() const;

private:
    metrics::RegionSums sq_{vk::kBandCount}, ssim_{vk::kBandCount}, sq_fovea_{1};
};
// One frame's figures.
ErrorFigures compare(const Rgb8& test, const Rgb8& reference, const vk::EyeDisplay& display,
                     const vk::ResolvedGaze& gaze, float foveal_radius_deg);

// Renders `frames` frames of the camera path with each method and the full-rate reference.
struct RunOptions {
    vk::EyeDisplay display = vk::EyeDisplay::desktop_1080p();
    vk::AcuityParams acuity;
    std::vector<std::string> methods{"full", "cps"};  // "full" is always the reference
    std::vector<std::string> post_chain;
    SceneKind scene = SceneKind::kDemo;
    int frames = 4;
    double frame_dt_s = 0.25;  // spacing of frames along the path and the gaze trace
    float eye_offset_m = 0.f;
    std::function<vk::GazeState(double t_s)> gaze;  // default: a scripted trace
    std::string png_dir;                            // write PNGs of every method's frames when set
    std::string png_prefix = "frame";
    std::function<void(const std::string&)> progress;  // one line per frame
    std::vector<std::string> options;  // FoveatorConfig::options ("key=value") for every method
    // Called after every measured frame of every method (index into the results, frame >= 0)
    // with the tone-mapped output; the foveator's stats()/gbuffer() are this frame's.
    std::function<void(size_t method, int frame, const vk::Foveator&, const Rgb8& output)> on_frame;
};
struct MethodResult {
    std::string name;
    std::string error;       // init failure; the other fields are then empty
    std::vector<double> ms;  // wall time per frame (G-buffer + method + post), submit->done
    double ms_median = 0.0;
    double shaded_fraction = 0.0;  // mean over frames
    double method_gpu_ms = 0.0;    // median GPU time of the method's passes
    double skipped_tiles = 0.0;    // mean per frame: tiles without a host shading call (cps)
    double reused_tiles = 0.0;     // mean per frame: of which last frame's shading kept (cps)
    double gbuffer_gpu_ms = 0.0;   // median GPU time of the host's G-buffer passes (all views)
    ErrorFigures error_figures;    // pooled over the frames
};
Result<std::vector<MethodResult>> run(const vk::Device& device, const RunOptions& options);

double median(std::vector<double> v);

}  // namespace fovea::demo
