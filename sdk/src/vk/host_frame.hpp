// Host-rendered frames (paths 2-4): the module's colour/depth/motion targets a host renders into,
// and the ingest pass that reads a host's own images into them (shaders/host_ingest.comp).
#pragma once

#include <vector>

#include "fovea/vk/host_images.hpp"
#include "gpu.hpp"

namespace fovea::vk {

// Colour, depth and motion images of one view (HostTargets formats and usage).
class HostTargetImages {
public:
    HostTargetImages() = default;
    HostTargetImages(const Device& device, VkExtent2D extent);
    const HostTargets& refs() const { return refs_; }

private:
    Image color_, depth_, motion_;
    HostTargets refs_;
};

// Copies HostFrameImages into HostTargets. Descriptor sets are rewritten per use from a pool
// per frame slot: the host's views may change every frame, and a slot's sets are only touched
// once that slot's previous frame completed (frames in flight).
class HostIngest {
public:
    HostIngest() = default;
    HostIngest(const Device& device, uint32_t frame_slots, uint32_t max_views);
    // Before the frame's first record(): slot = frame index % frames in flight.
    void begin_frame(uint32_t slot);
    // Fails (false, nothing recorded) when the sizes differ or a view is missing.
    bool record(VkCommandBuffer cmd, const HostFrameImages& src, const HostTargets& dst);

private:
    VkDevice device_ = VK_NULL_HANDLE;
    ComputePipeline pipeline_;
    NearestClampSampler sampler_;
    std::vector<std::vector<VkDescriptorSet>> sets_;  // [slot][use]
    uint32_t slot_ = 0, used_ = 0;
};

}  // namespace fovea::vk
