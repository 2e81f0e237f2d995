// Rasterization building blocks of the demo host's G-buffer pass (demo-only, so not in the SDK):
// a depth attachment, the render pass over the module's G-buffer images plus depth, and a
// vertex + fragment pipeline without vertex buffers (geometry comes from gl_VertexIndex).
// Move-only RAII through sdk/src/vk/gpu.hpp's handle type. A VkRenderPass rather than dynamic
// rendering: the module's headless device is Vulkan 1.2 without VK_KHR_dynamic_rendering, and a
// host's device need not enable it either.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <vulkan/vulkan.h>

#include "fovea/vk/device.hpp"
#include "fovea/vk/gbuffer.hpp"
#include "gpu.hpp"

namespace fovea::demo {

inline constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;

class DepthImage {
public:
    DepthImage() = default;
    DepthImage(const vk::Device& device, VkExtent2D extent);
    void reset() { *this = DepthImage(); }
    VkImageView view() const { return view_.get(); }

private:
    vk::UniqueDeviceMemory memory_;  // destroyed in reverse: view, image, memory
    vk::UniqueImage image_;
    vk::UniqueImageView view_;
};

// The G-buffer images stay in VK_IMAGE_LAYOUT_GENERAL (the module's contract) and are fully
// overwritten (load op DONT_CARE); depth is cleared to 0 (reverse-Z far). Its dependencies order
// it after earlier compute, transfer and G-buffer passes and before later ones.
class GBufferRenderPass {
public:
    explicit GBufferRenderPass(const vk::Device& device);

    VkRenderPass get() const { return pass_.get(); }
    // Begins the pass over `gbuffer` and sets viewport and scissor to its extent. The framebuffer
    // lives until release_framebuffers(), to be called once the commands have completed.
    void begin(VkCommandBuffer cmd, const vk::GBufferRefs& gbuffer, VkImageView depth);
    void end(VkCommandBuffer cmd) const { vkCmdEndRenderPass(cmd); }
    void release_framebuffers();

private:
    vk::UniqueRenderPass pass_;
    std::vector<vk::UniqueFramebuffer> framebuffers_;  // destroyed before the pass
};

// One descriptor set with one uniform buffer visible to the vertex and fragment stages, bound
// with a dynamic offset (a draw's view is one `range`-byte block of the buffer): the layout every
// demo G-buffer pipeline shares. A uniform block at a constant offset, not a storage buffer
// indexed by a push constant: llvmpipe (Mesa 22.3) loads the former once per shader call, the
// latter lane by lane, which cost about a third of the G-buffer pass.
class BufferSetLayout {
public:
    BufferSetLayout(const vk::Device& device, VkBuffer buffer, VkDeviceSize range);

    VkPipelineLayout layout() const { return layout_.get(); }
    VkDescriptorSet set() const { return set_; }

private:
    vk::UniqueDescriptorSetLayout set_layout_;
    vk::UniquePipelineLayout layout_;
    vk::UniqueDescriptorPool pool_;
    VkDescriptorSet set_ = VK_NULL_HANDLE;  // freed with pool_
};

struct RasterState {
    VkCullModeFlags cull = VK_CULL_MODE_NONE;
    bool depth_test = true;  // reverse-Z: GREATER_OR_EQUAL
    bool depth_write = true;
};

class GraphicsPipeline {
public:
    GraphicsPipeline() = default;
    // Triangle lists, no vertex input, dynamic viewport and scissor, one colour blend state
    // (no blending) per colour attachment of `pass`. vert_spec: 32-bit specialization constants
    // 0..n-1 of the vertex stage.
    GraphicsPipeline(const vk::Device& device, VkPipelineLayout layout, VkRenderPass pass,
                     uint32_t color_attachments, std::span<const uint32_t> vert,
                     std::span<const uint32_t> frag, RasterState state,
                     std::span<const uint32_t> vert_spec = {});
    void reset() { pipeline_.reset(); }
    VkPipeline get() const { return pipeline_.get(); }

private:
    vk::UniquePipeline pipeline_;
};

}  // namespace fovea::demo
