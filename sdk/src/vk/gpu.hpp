// Internal Vulkan building blocks of the module (not installed): move-only RAII buffers, images,
// compute pipelines and barriers. Methods (sdk/src/vk/methods/) and post passes use these.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <vulkan/vulkan.h>

#include "fovea/vk/check.hpp"
#include "fovea/vk/device.hpp"

namespace fovea::vk {

class Buffer {
public:
    Buffer() = default;
    // Host-visible buffers are persistently mapped (data()).
    Buffer(const Device& device, VkDeviceSize size, VkBufferUsageFlags usage, bool host_visible);
    Buffer(Buffer&& o) noexcept { *this = std::move(o); }
    Buffer& operator=(Buffer&& o) noexcept;
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;
    ~Buffer() { reset(); }
    void reset();

    VkBuffer get() const { return buffer_; }
    VkDeviceSize size() const { return size_; }
    void* data() const { return mapped_; }
    VkDescriptorBufferInfo info() const { return {buffer_, 0, VK_WHOLE_SIZE}; }

private:
    VkDevice device_ = VK_NULL_HANDLE;
    VkBuffer buffer_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    VkDeviceSize size_ = 0;
    void* mapped_ = nullptr;
};

class Image {
public:
    Image() = default;
    // A 2D single-mip image with a view, transitioned to VK_IMAGE_LAYOUT_GENERAL and cleared.
    Image(const Device& device, VkExtent2D extent, VkFormat format, VkImageUsageFlags usage,
          uint32_t mip_levels = 1);
    Image(Image&& o) noexcept { *this = std::move(o); }
    Image& operator=(Image&& o) noexcept;
    Image(const Image&) = delete;
    Image& operator=(const Image&) = delete;
    ~Image() { reset(); }
    void reset();

    const ImageRef& ref() const { return ref_; }
    VkImage get() const { return ref_.image; }
    VkImageView view() const { return ref_.view; }
    VkExtent2D extent() const { return ref_.extent; }
    VkFormat format() const { return ref_.format; }
    uint32_t mip_levels() const { return mips_; }
    // A view of one mip level (created on demand in the constructor for mip_levels > 1).
    VkImageView mip_view(uint32_t level) const { return mip_views_.at(level); }

private:
    VkDevice device_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    ImageRef ref_;
    uint32_t mips_ = 1;
    std::vector<VkImageView> mip_views_;
};

// The filtered reads of the passes: bilinear within a level, linear between the `mip_levels`
// levels (trilinear), clamp to edge (the CPU models' fetch()). Move-only.
class LinearClampSampler {
public:
    LinearClampSampler() = default;
    LinearClampSampler(const Device& device, uint32_t mip_levels = 1);
    LinearClampSampler(LinearClampSampler&& o) noexcept { *this = std::move(o); }
    LinearClampSampler& operator=(LinearClampSampler&& o) noexcept;
    LinearClampSampler(const LinearClampSampler&) = delete;
    LinearClampSampler& operator=(const LinearClampSampler&) = delete;
    ~LinearClampSampler() { reset(); }
    void reset();

    VkSampler get() const { return sampler_; }

private:
    VkDevice device_ = VK_NULL_HANDLE;
    VkSampler sampler_ = VK_NULL_HANDLE;
};

// One descriptor binding of a compute pipeline's own set.
struct Binding {
    VkDescriptorType type;  // STORAGE_IMAGE, STORAGE_BUFFER, UNIFORM_BUFFER, COMBINED_IMAGE_SAMPLER
    uint32_t count = 1;
};

// A compute pipeline with its layout: set 0 = the frame set (shaders/fovea_frame.glsl) when
// frame_set_layout is given, then one own set described by `bindings` (set 1, or set 0 when no
// frame set), and a push-constant range of push_bytes.
class ComputePipeline {
public:
    ComputePipeline() = default;
    ComputePipeline(const Device& device, std::span<const uint32_t> spirv,
                    VkDescriptorSetLayout frame_set_layout, std::span<const Binding> bindings,
                    uint32_t push_bytes, std::span<const uint32_t> spec_constants = {});
    ComputePipeline(ComputePipeline&& o) noexcept { *this = std::move(o); }
    ComputePipeline& operator=(ComputePipeline&& o) noexcept;
    ComputePipeline(const ComputePipeline&) = delete;
    ComputePipeline& operator=(const ComputePipeline&) = delete;
    ~ComputePipeline() { reset(); }
    void reset();

    VkPipeline get() const { return pipeline_; }
    VkPipelineLayout layout() const { return layout_; }
    VkDescriptorSetLayout set_layout() const { return set_layout_; }
    uint32_t own_set_index() const { return own_set_; }

    // Allocates one set of the own layout from this pipeline's private pool (max_sets total).
    VkDescriptorSet allocate_set();

    // Binds the pipeline, the frame set (if any) and `own` set, pushes constants.
    void bind(VkCommandBuffer cmd, VkDescriptorSet frame_set, VkDescriptorSet own,
              const void* push = nullptr, uint32_t push_bytes = 0) const;

private:
    VkDevice device_ = VK_NULL_HANDLE;
    VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
    VkPipelineLayout layout_ = VK_NULL_HANDLE;
    VkPipeline pipeline_ = VK_NULL_HANDLE;
    VkDescriptorPool pool_ = VK_NULL_HANDLE;
    uint32_t own_set_ = 0;
    uint32_t push_bytes_ = 0;
    VkShaderStageFlags stages_ = VK_SHADER_STAGE_COMPUTE_BIT;
};

// Writes descriptors of a set: chain image()/buffer() calls, then the destructor... no: commit().
class DescriptorWriter {
public:
    DescriptorWriter(VkDevice device, VkDescriptorSet set) : device_(device), set_(set) {}
    DescriptorWriter& storage_image(uint32_t binding, VkImageView view);
    DescriptorWriter& sampled_image(uint32_t binding, VkImageView view, VkSampler sampler);
    DescriptorWriter& storage_buffer(uint32_t binding, const Buffer& buffer);
    DescriptorWriter& uniform_buffer(uint32_t binding, const Buffer& buffer);
    void commit();

private:
    VkDevice device_;
    VkDescriptorSet set_;
    std::vector<VkDescriptorImageInfo> images_;
    std::vector<VkDescriptorBufferInfo> buffers_;
    struct Pending { uint32_t binding; VkDescriptorType type; size_t index; bool image; };
    std::vector<Pending> pending_;
};

// Full compute->compute (and transfer) memory barrier: simple and correct for a chain of
// compute passes over storage images/buffers in GENERAL layout.
void compute_barrier(VkCommandBuffer cmd);
// Compute writes -> indirect dispatch arguments + compute reads.
void indirect_barrier(VkCommandBuffer cmd);

inline uint32_t div_up(uint32_t a, uint32_t b) { return (a + b - 1) / b; }

}  // namespace fovea::vk

namespace fovea::vk {
// Copies tightly packed texels into an image (GENERAL layout, one mip). Blocking; for tests,
// tools and one-time uploads.
void upload_image(const Device& device, const ImageRef& image, std::span<const uint8_t> texels);
}  // namespace fovea::vk
