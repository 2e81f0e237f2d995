// The viewer's own Vulkan plumbing, as any host has it (the SDK's internals are not installed):
// one owning handle type for every object, buffers and images with their memory, one-shot
// command submission, and the layout barrier a texture upload needs. Move-only RAII.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <vulkan/vulkan.h>

namespace gltfv {

[[noreturn]] void vk_fail(VkResult r, const char* call);
#define GLTFV_CHECK(call)                                              \
    do {                                                               \
        const VkResult gltfv_r_ = (call);                              \
        if (gltfv_r_ != VK_SUCCESS) ::gltfv::vk_fail(gltfv_r_, #call); \
    } while (0)

// An owned VkDevice child object destroyed with `Destroy`.
template <typename T, void (*Destroy)(VkDevice, T, const VkAllocationCallbacks*)>
class Handle {
public:
    Handle() = default;
    Handle(VkDevice device, T handle) : device_(device), handle_(handle) {}
    Handle(Handle&& o) noexcept
        : device_(o.device_), handle_(std::exchange(o.handle_, VK_NULL_HANDLE)) {}
    Handle& operator=(Handle&& o) noexcept {
        if (this != &o) {
            reset();
            device_ = o.device_;
            handle_ = std::exchange(o.handle_, VK_NULL_HANDLE);
        }
        return *this;
    }
    Handle(const Handle&) = delete;
    Handle& operator=(const Handle&) = delete;
    ~Handle() { reset(); }
    void reset() {
        if (handle_ != VK_NULL_HANDLE) Destroy(device_, handle_, nullptr);
        handle_ = VK_NULL_HANDLE;
    }
    T get() const { return handle_; }
    const T* ptr() const { return &handle_; }

private:
    VkDevice device_ = VK_NULL_HANDLE;
    T handle_ = VK_NULL_HANDLE;
};

using Memory = Handle<VkDeviceMemory, vkFreeMemory>;
using BufferHandle = Handle<VkBuffer, vkDestroyBuffer>;
using ImageHandle = Handle<VkImage, vkDestroyImage>;
using ImageView = Handle<VkImageView, vkDestroyImageView>;
using Sampler = Handle<VkSampler, vkDestroySampler>;
using ShaderModule = Handle<VkShaderModule, vkDestroyShaderModule>;
using Pipeline = Handle<VkPipeline, vkDestroyPipeline>;
using PipelineLayout = Handle<VkPipelineLayout, vkDestroyPipelineLayout>;
using SetLayout = Handle<VkDescriptorSetLayout, vkDestroyDescriptorSetLayout>;
using DescriptorPool = Handle<VkDescriptorPool, vkDestroyDescriptorPool>;
using RenderPass = Handle<VkRenderPass, vkDestroyRenderPass>;
using Framebuffer = Handle<VkFramebuffer, vkDestroyFramebuffer>;
using CommandPool = Handle<VkCommandPool, vkDestroyCommandPool>;
using Fence = Handle<VkFence, vkDestroyFence>;
using QueryPool = Handle<VkQueryPool, vkDestroyQueryPool>;

// The device objects the viewer's helpers need.
struct Gpu {
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    uint32_t queue_family = 0;
    uint32_t memory_type(uint32_t bits, VkMemoryPropertyFlags flags) const;
};

struct Buffer {
    BufferHandle buffer;
    Memory memory;
    void* mapped = nullptr;  // host-visible buffers stay mapped
    VkDeviceSize size = 0;
    VkBuffer get() const { return buffer.get(); }
};
Buffer make_buffer(const Gpu& gpu, VkDeviceSize size, VkBufferUsageFlags usage, bool host_visible);

struct Image {
    ImageHandle image;
    Memory memory;
    ImageView view;
    VkExtent2D extent{0, 0};
    VkFormat format = VK_FORMAT_UNDEFINED;
    uint32_t mips = 1;
    VkImage get() const { return image.get(); }
};
Image make_image(const Gpu& gpu, VkExtent2D extent, VkFormat format, VkImageUsageFlags usage,
                 uint32_t mips = 1, VkImageAspectFlags aspect = VK_IMAGE_ASPECT_COLOR_BIT);

// Records with `record` into a one-time command buffer, submits and waits.
class Submitter {
public:
    explicit Submitter(const Gpu& gpu);
    void run(const std::function<void(VkCommandBuffer)>& record);

private:
    const Gpu* gpu_;
    CommandPool pool_;
    Fence fence_;
};

ShaderModule make_shader(VkDevice device, std::span<const uint32_t> spirv);

// Full pipeline barrier for a one-image layout change (uploads, mip generation).
void image_barrier(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to,
                   uint32_t base_mip = 0, uint32_t mips = VK_REMAINING_MIP_LEVELS,
                   VkImageAspectFlags aspect = VK_IMAGE_ASPECT_COLOR_BIT);

// Copies an image (GENERAL layout, one mip, colour) to host memory, tightly packed.
std::vector<uint8_t> read_back(const Gpu& gpu, Submitter& submit, VkImage image, VkExtent2D extent,
                               uint32_t texel_bytes);

}  // namespace gltfv
