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

// Matches DemoView in shaders/demo_gbuffer.comp (std430: ten vec4).
struct DemoView {
    float pos[4], right[4], up[4], fwd[4], crop[4], jitter[4];
    float prev_pos[4], prev_right[4], prev_up[4], prev_fwd[4];
};
constexpr uint32_t kSlots = 64;

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
      views_(device, sizeof(DemoView) * kSlots, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true) {
    const vk::Binding img{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};
    const vk::Binding b[] = {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}, img, img, img, img, img, img};
    pipeline_ = vk::ComputePipeline(device, vk::shader_spirv("demo_gbuffer.comp"), VK_NULL_HANDLE,
                                    b, 4);
    if (device.properties().limits.timestampComputeAndGraphics) {
        VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
        qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
        qi.queryCount = 2 * kSlots;
        VK_CHECK(vkCreateQueryPool(device.device(), &qi, nullptr, &queries_));
    }
}

SceneRenderer::~SceneRenderer() {
    if (queries_) vkDestroyQueryPool(device_->device(), queries_, nullptr);
}

void SceneRenderer::begin_frame() { slot_ = 0; }

double SceneRenderer::gpu_ms() const {
    const uint32_t views = std::min(slot_, kSlots);
    if (!queries_ || views == 0) return 0.0;
    std::vector<uint64_t> ts(2 * views);
    if (vkGetQueryPoolResults(device_->device(), queries_, 0, 2 * views,
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
    std::memcpy(static_cast<DemoView*>(views_.data()) + slot, &v, sizeof(v));
    const VkImageView key = g.images[0].view;
    auto it = sets_.find(key);
    if (it == sets_.end()) {
        VkDescriptorSet set = pipeline_.allocate_set();
        vk::DescriptorWriter w(device_->device(), set);
        w.storage_buffer(0, views_);
        for (uint32_t i = 0; i < vk::kGBufferImageCount; ++i)
            w.storage_image(1 + i, g.images[i].view);
        w.commit();
        it = sets_.emplace(key, set).first;
    }
    if (queries_) {
        if (slot == 0) vkCmdResetQueryPool(cmd, queries_, 0, 2 * kSlots);
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_, 2 * slot);
    }
    pipeline_.bind(cmd, VK_NULL_HANDLE, it->second, &slot, sizeof(slot));
    vkCmdDispatch(cmd, vk::div_up(g.extent.width, 8), vk::div_up(g.extent.height, 8), 1);
    if (queries_)
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, queries_, 2 * slot + 1);
    vk::compute_barrier(cmd);
}

}  // namespace fovea::demo
