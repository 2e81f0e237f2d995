#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "fovea/demo/demo.hpp"
#include "shaders.hpp"

namespace fovea::demo {
namespace {

using V3 = std::array<float, 3>;
V3 sub(V3 a, V3 b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
V3 cross(V3 a, V3 b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
V3 normalize(V3 a) {
    const float l = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    return {a[0] / l, a[1] / l, a[2] / l};
}

constexpr double kDegToRad = 0.017453292519943295;

// Matches DemoView in shaders/demo_raster.glsl (std430: ten vec4).
struct DemoView {
    float pos[4], right[4], up[4], fwd[4], crop[4], jitter[4];
    float prev_pos[4], prev_right[4], prev_up[4], prev_fwd[4];
};
constexpr uint32_t kSlots = 64;

// Bytes between the views' uniform blocks: sizeof(DemoView) rounded up to the dynamic offset's
// alignment.
uint32_t view_stride(const vk::Device& device) {
    const auto align =
        static_cast<uint32_t>(device.properties().limits.minUniformBufferOffsetAlignment);
    return (static_cast<uint32_t>(sizeof(DemoView)) + align - 1) / align * align;
}

// Terrain clipmap (shaders/demo_terrain.vert): level 0 is kTerrainCells^2 cells of
// kTerrainSpacing metres; each further level doubles the spacing around a hole the size of the
// previous level, until the terrain reaches kFarM (beyond it: sky). 32 cells of
// 25 cm: 38k vertices, cells 1/16 to 1/8 of their distance wide; 64 cells of 12.5 cm (154k) cost
// ~13 ms more vertex work on lavapipe for no visible gain (the normal is analytic per pixel).
constexpr uint32_t kTerrainCells = 32;
constexpr float kTerrainSpacing = 0.25f;
constexpr float kFarM = 400.f;
constexpr uint32_t terrain_levels() {
    uint32_t levels = 1;
    for (float half = 0.5f * kTerrainCells * kTerrainSpacing; half < kFarM; half *= 2.f) ++levels;
    return levels;
}
constexpr uint32_t kTerrainVertices =
    6 * (kTerrainCells * kTerrainCells +
         (terrain_levels() - 1) * (kTerrainCells * kTerrainCells * 3 / 4));
// A 36-vertex box per object of shaders/demo_scene.glsl's kGridX x kGridZ grid (6 x 4).
constexpr uint32_t kObjectVertices = 36 * 6 * 4;

void put(float* dst, const V3& v, float w) {
    dst[0] = v[0];
    dst[1] = v[1];
    dst[2] = v[2];
    dst[3] = w;
}

}  // namespace

Camera camera_at(double t, const vk::EyeDisplay& d, float eye_offset_m) {
    Camera c;
    const float tf = static_cast<float>(t);
    const V3 pos{6.0f * std::sin(0.15f * tf), 3.0f + 0.5f * std::sin(0.4f * tf),
                 3.0f + 1.5f * std::cos(0.1f * tf)};
    const V3 target{3.0f * std::sin(0.2f * tf), -0.5f, -16.0f};
    c.fwd = normalize(sub(target, pos));
    c.right = normalize(cross(c.fwd, {0.f, 1.f, 0.f}));
    c.up = cross(c.right, c.fwd);
    c.pos = {pos[0] + c.right[0] * eye_offset_m, pos[1] + c.right[1] * eye_offset_m,
             pos[2] + c.right[2] * eye_offset_m};
    c.tan_x = static_cast<float>(std::tan(d.fov_h_deg * 0.5 * kDegToRad));
    c.tan_y = static_cast<float>(std::tan(d.fov_v_deg * 0.5 * kDegToRad));
    return c;
}

Camera target_camera(const vk::EyeDisplay& d) {
    Camera c;
    c.tan_x = static_cast<float>(std::tan(d.fov_h_deg * 0.5 * kDegToRad));
    c.tan_y = static_cast<float>(std::tan(d.fov_v_deg * 0.5 * kDegToRad));
    return c;
}

std::string shading_glsl() {
    const vk::EmbeddedShader* s = vk::find_shader("demo_shading.glsl");
    return s ? s->source : "";
}

SceneRenderer::SceneRenderer(const vk::Device& device)
    : device_(&device),
      view_stride_(view_stride(device)),
      views_(device, view_stride_ * kSlots, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, true),
      layout_(device, views_.get(), sizeof(DemoView)),
      pass_(device) {
    const auto pipeline = [&](const char* vert, const char* frag, RasterState state,
                              std::span<const uint32_t> spec = {}) {
        return GraphicsPipeline(device, layout_.layout(), pass_.get(), vk::kGBufferImageCount,
                                vk::shader_spirv(vert), vk::shader_spirv(frag), state, spec);
    };
    uint32_t spacing_bits;
    std::memcpy(&spacing_bits, &kTerrainSpacing, sizeof(spacing_bits));
    const uint32_t terrain_spec[] = {kTerrainCells, spacing_bits};
    terrain_ = pipeline("demo_terrain.vert", "demo_terrain.frag", {}, terrain_spec);
    // Back faces of the proxy boxes: their footprint is the box's even with the camera inside.
    objects_ =
        pipeline("demo_object.vert", "demo_object.frag", {VK_CULL_MODE_FRONT_BIT, true, true});
    sky_ = pipeline("demo_fullscreen.vert", "demo_sky.frag", {VK_CULL_MODE_NONE, true, false});
    target_ =
        pipeline("demo_fullscreen.vert", "demo_target.frag", {VK_CULL_MODE_NONE, false, false});
    if (device.properties().limits.timestampComputeAndGraphics) {
        VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
        qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
        qi.queryCount = 2 * kSlots;
        queries_ = vk::create_handle<vk::UniqueQueryPool>(device.device(), vkCreateQueryPool, qi);
    }
}

void SceneRenderer::begin_frame() {
    slot_ = 0;
    pass_.release_framebuffers();  // the previous frame's commands have completed
}

double SceneRenderer::gpu_ms() const {
    const uint32_t views = std::min(slot_, kSlots);
    if (!queries_ || views == 0) return 0.0;
    std::vector<uint64_t> ts(2 * views);
    if (vkGetQueryPoolResults(device_->device(), queries_.get(), 0, 2 * views,
                              ts.size() * sizeof(uint64_t), ts.data(), sizeof(uint64_t),
                              VK_QUERY_RESULT_64_BIT) != VK_SUCCESS)
        return 0.0;
    uint64_t ticks = 0;
    for (uint32_t i = 0; i < views; ++i) ticks += ts[2 * i + 1] - ts[2 * i];
    return static_cast<double>(ticks) * device_->properties().limits.timestampPeriod * 1e-6;
}

void SceneRenderer::record(VkCommandBuffer cmd, const vk::GBufferRefs& g, SceneKind scene,
                           const Camera& cam, const Camera& prev, double time_s,
                           std::array<float, 4> crop, std::array<float, 2> jitter) {
    const uint32_t slot = slot_++ % kSlots;
    DemoView v{};
    put(v.pos, cam.pos, static_cast<float>(time_s));
    put(v.right, cam.right, cam.tan_x);
    put(v.up, cam.up, cam.tan_y);
    put(v.fwd, cam.fwd, static_cast<float>(static_cast<int>(scene)));
    std::memcpy(v.crop, crop.data(), sizeof(v.crop));
    v.jitter[0] = jitter[0];
    v.jitter[1] = jitter[1];
    v.jitter[2] = static_cast<float>(g.extent.width);
    v.jitter[3] = static_cast<float>(g.extent.height);
    put(v.prev_pos, prev.pos, 0.f);
    put(v.prev_right, prev.right, prev.tan_x);
    put(v.prev_up, prev.up, prev.tan_y);
    put(v.prev_fwd, prev.fwd, 0.f);
    const uint32_t offset = slot * view_stride_;
    std::memcpy(static_cast<char*>(views_.data()) + offset, &v, sizeof(v));
    auto depth = depth_.find({g.extent.width, g.extent.height});
    if (depth == depth_.end())
        depth =
            depth_
                .emplace(std::pair{g.extent.width, g.extent.height}, DepthImage(*device_, g.extent))
                .first;
    if (queries_) {
        if (slot == 0) vkCmdResetQueryPool(cmd, queries_.get(), 0, 2 * kSlots);
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_.get(), 2 * slot);
    }
    pass_.begin(cmd, g, depth->second.view());
    const VkDescriptorSet set = layout_.set();
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.layout(), 0, 1, &set, 1,
                            &offset);
    const auto draw = [&](const GraphicsPipeline& p, uint32_t vertices) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p.get());
        vkCmdDraw(cmd, vertices, 1, 0, 0);
    };
    if (scene == SceneKind::kDemo) {
        // Objects first: the terrain behind them then fails the early depth test instead of
        // being shaded and overwritten.
        draw(objects_, kObjectVertices);
        draw(terrain_, kTerrainVertices);
        draw(sky_, 3);  // last: only where nothing else was drawn (depth still far)
    } else {
        draw(target_, 3);
    }
    pass_.end(cmd);
    if (queries_)
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_.get(),
                            2 * slot + 1);
}

}  // namespace fovea::demo
