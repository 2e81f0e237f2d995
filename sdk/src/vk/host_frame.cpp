#include "host_frame.hpp"

#include "shaders.hpp"

namespace fovea::vk {
namespace {

struct IngestPush {  // shaders/host_ingest.comp
    float motion_scale[2];
    int32_t depth_reversed;
    int32_t has_motion;
};
static_assert(sizeof(IngestPush) == 16);

}  // namespace

HostTargetImages::HostTargetImages(const Device& device, VkExtent2D extent)
    : color_(device, extent, kHostColorFormat, kHostTargetUsage),
      depth_(device, extent, kHostDepthFormat, kHostTargetUsage),
      motion_(device, extent, kHostMotionFormat, kHostTargetUsage) {
    refs_ = {extent, color_.ref(), depth_.ref(), motion_.ref()};
}

HostIngest::HostIngest(const Device& device, uint32_t frame_slots, uint32_t max_views)
    : device_(device.device()), sampler_(device) {
    const Binding tex{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER};
    const Binding img{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};
    const Binding b[] = {tex, tex, tex, img, img, img};
    pipeline_ = ComputePipeline(device, shader_spirv("host_ingest.comp"), VK_NULL_HANDLE, b,
                                sizeof(IngestPush), {}, frame_slots * max_views);
    sets_.resize(frame_slots);
    for (auto& slot : sets_)
        for (uint32_t i = 0; i < max_views; ++i) slot.push_back(pipeline_.allocate_set());
}

void HostIngest::begin_frame(uint32_t slot) {
    slot_ = slot;
    used_ = 0;
}

bool HostIngest::record(VkCommandBuffer cmd, const HostFrameImages& src, const HostTargets& dst) {
    if (src.extent.width != dst.extent.width || src.extent.height != dst.extent.height ||
        !src.color.view || !src.depth.view || used_ >= sets_[slot_].size())
        return false;
    const VkDescriptorSet set = sets_[slot_][used_++];
    // Without motion the colour view stands in for the binding (the shader does not read it).
    const HostImage motion = src.motion.view ? src.motion : src.color;
    DescriptorWriter(device_, set)
        .sampled_image(0, src.color.view, sampler_.get(), src.color.layout)
        .sampled_image(1, src.depth.view, sampler_.get(), src.depth.layout)
        .sampled_image(2, motion.view, sampler_.get(), motion.layout)
        .storage_image(3, dst.color.view)
        .storage_image(4, dst.depth.view)
        .storage_image(5, dst.motion.view)
        .commit();
    IngestPush p{};
    p.motion_scale[0] = src.motion_scale[0];
    p.motion_scale[1] = src.motion_scale[1];
    p.depth_reversed = src.depth_mapping == DepthMapping::kReversed ? 1 : 0;
    p.has_motion = src.motion.view ? 1 : 0;
    pipeline_.bind(cmd, VK_NULL_HANDLE, set, &p, sizeof(p));
    vkCmdDispatch(cmd, div_up(dst.extent.width, 8), div_up(dst.extent.height, 8), 1);
    return true;
}

}  // namespace fovea::vk
