// Internal Vulkan building blocks of the module (not installed): the owning handle type, RAII
// buffers, images, compute pipelines and barriers. Methods (sdk/src/vk/methods/), post passes, the
// demo host and the tools use these; no Vulkan object is held in a raw handle with a hand-written
// destroy, so every error path (a constructor throwing half-way) releases what it made.
#pragma once

#include <cstdint>
#include <source_location>
#include <span>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <vulkan/vulkan.h>

#include "fovea/vk/check.hpp"
#include "fovea/vk/device.hpp"

namespace fovea::vk {

// Owns one Vulkan object and destroys it with `Destroy` (vkDestroyImage, vkFreeMemory, ...) as
// Destroy(parent, handle, nullptr), or Destroy(handle, nullptr) for an instance or device.
// Move-only; a default or moved-from handle is null and destroys nothing. Khronos Vulkan-Samples'
// VulkanResource (framework/core/vulkan_resource.h) without the debug names. Threads: like the
// handle it owns (Vulkan's external synchronization rules apply to reset()).
template <typename T, auto Destroy, typename Parent = VkDevice>
class Unique {
    static constexpr bool kHasParent =
        !std::is_invocable_v<decltype(Destroy), T, const VkAllocationCallbacks*>;

public:
    using Handle = T;

    Unique() = default;
    Unique(Parent parent, T handle) noexcept : parent_(parent), handle_(handle) {
        static_assert(kHasParent, "an instance or device has no parent: Unique(handle)");
    }
    explicit Unique(T handle) noexcept : handle_(handle) {
        static_assert(!kHasParent, "a device child needs its parent: Unique(parent, handle)");
    }
    Unique(Unique&& o) noexcept
        : parent_(std::exchange(o.parent_, Parent{})),
          handle_(std::exchange(o.handle_, T{VK_NULL_HANDLE})) {}
    Unique& operator=(Unique&& o) noexcept {
        if (this != &o) {
            reset();
            parent_ = std::exchange(o.parent_, Parent{});
            handle_ = std::exchange(o.handle_, T{VK_NULL_HANDLE});
        }
        return *this;
    }
    Unique(const Unique&) = delete;
    Unique& operator=(const Unique&) = delete;
    ~Unique() { reset(); }

    void reset() noexcept {
        if (handle_ != VK_NULL_HANDLE) {
            if constexpr (kHasParent)
                Destroy(parent_, handle_, nullptr);
            else
                Destroy(handle_, nullptr);
        }
        parent_ = Parent{};
        handle_ = VK_NULL_HANDLE;
    }
    // Gives up ownership: the caller destroys the handle.
    [[nodiscard]] T release() noexcept {
        parent_ = Parent{};
        return std::exchange(handle_, T{VK_NULL_HANDLE});
    }

    T get() const { return handle_; }
    Parent parent() const { return parent_; }
    explicit operator bool() const { return handle_ != VK_NULL_HANDLE; }

private:
    Parent parent_{};
    T handle_ = VK_NULL_HANDLE;
};

using UniqueBuffer = Unique<VkBuffer, vkDestroyBuffer>;
using UniqueBufferView = Unique<VkBufferView, vkDestroyBufferView>;
using UniqueDeviceMemory = Unique<VkDeviceMemory, vkFreeMemory>;
using UniqueImage = Unique<VkImage, vkDestroyImage>;
using UniqueImageView = Unique<VkImageView, vkDestroyImageView>;
using UniqueSampler = Unique<VkSampler, vkDestroySampler>;
using UniqueShaderModule = Unique<VkShaderModule, vkDestroyShaderModule>;
using UniquePipeline = Unique<VkPipeline, vkDestroyPipeline>;
using UniquePipelineLayout = Unique<VkPipelineLayout, vkDestroyPipelineLayout>;
using UniqueDescriptorSetLayout = Unique<VkDescriptorSetLayout, vkDestroyDescriptorSetLayout>;
using UniqueDescriptorPool = Unique<VkDescriptorPool, vkDestroyDescriptorPool>;
using UniqueQueryPool = Unique<VkQueryPool, vkDestroyQueryPool>;
using UniqueRenderPass = Unique<VkRenderPass, vkDestroyRenderPass>;
using UniqueFramebuffer = Unique<VkFramebuffer, vkDestroyFramebuffer>;
using UniqueFence = Unique<VkFence, vkDestroyFence>;
using UniqueSemaphore = Unique<VkSemaphore, vkDestroySemaphore>;
using UniqueCommandPool = Unique<VkCommandPool, vkDestroyCommandPool>;
using UniqueDevice = Unique<VkDevice, vkDestroyDevice>;
using UniqueInstance = Unique<VkInstance, vkDestroyInstance>;

// Makes a device child with a call shaped like vkCreateImage(device, info, allocator, out) (every
// vkCreate* of one object, vkAllocateMemory) and owns it; throws VkError naming the caller and the
// place when the call fails, so nothing is ever held half-made.
template <typename U, typename Info>
U create_handle(VkDevice device,
                VkResult(VKAPI_PTR* call)(VkDevice, const Info*, const VkAllocationCallbacks*,
                                          typename U::Handle*),
                const Info& info, std::source_location where = std::source_location::current()) {
    typename U::Handle handle = VK_NULL_HANDLE;
    const VkResult r = call(device, &info, nullptr, &handle);
    if (r != VK_SUCCESS)
        throw_vk_error(r, (std::string("create in ") + where.function_name()).c_str(),
                       where.file_name(), static_cast<int>(where.line()));
    return U(device, handle);
}

// One compute or graphics pipeline from vkCreate{Compute,Graphics}Pipelines, owned; throws like
// create_handle().
template <typename Info>
UniquePipeline create_pipeline(VkDevice device,
                               VkResult(VKAPI_PTR* call)(VkDevice, VkPipelineCache, uint32_t,
                                                         const Info*, const VkAllocationCallbacks*,
                                                         VkPipeline*),
                               const Info& info,
                               std::source_location where = std::source_location::current()) {
    VkPipeline pipeline = VK_NULL_HANDLE;
    const VkResult r = call(device, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline);
    if (r != VK_SUCCESS)
        throw_vk_error(r, (std::string("create pipeline in ") + where.function_name()).c_str(),
                       where.file_name(), static_cast<int>(where.line()));
    return UniquePipeline(device, pipeline);
}

class Buffer {
public:
    Buffer() = default;
    // Host-visible buffers are persistently mapped (data()).
    Buffer(const Device& device, VkDeviceSize size, VkBufferUsageFlags usage, bool host_visible);
    Buffer(Buffer&& o) noexcept { *this = std::move(o); }
    Buffer& operator=(Buffer&& o) noexcept;
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;
    ~Buffer() = default;
    void reset() { *this = Buffer(); }

    VkBuffer get() const { return buffer_.get(); }
    VkDeviceSize size() const { return size_; }
    void* data() const { return mapped_; }
    VkDescriptorBufferInfo info() const { return {buffer_.get(), 0, VK_WHOLE_SIZE}; }

private:
    UniqueDeviceMemory memory_;  // declared first: freed after the buffer (unmaps implicitly)
    UniqueBuffer buffer_;
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
    ~Image() = default;
    void reset() { *this = Image(); }

    const ImageRef& ref() const { return ref_; }
    VkImage get() const { return ref_.image; }
    VkImageView view() const { return ref_.view; }
    VkExtent2D extent() const { return ref_.extent; }
    VkFormat format() const { return ref_.format; }
    uint32_t mip_levels() const { return mips_; }
    // A view of one mip level (made in the constructor for mip_levels > 1; level 0 of a single
    // mip image is view()). Throws std::out_of_range past the last level.
    VkImageView mip_view(uint32_t level) const;

private:
    UniqueDeviceMemory memory_;  // members are destroyed in reverse: views, image, memory
    UniqueImage image_;
    UniqueImageView view_;
    std::vector<UniqueImageView> mip_views_;
    ImageRef ref_;  // the handles above, as the module hands them out
    uint32_t mips_ = 1;
};

// The filtered reads of the passes: bilinear within a level, linear between the `mip_levels`
// levels (trilinear), clamp to edge (the CPU models' fetch()). Move-only.
class LinearClampSampler {
public:
    LinearClampSampler() = default;
    LinearClampSampler(const Device& device, uint32_t mip_levels = 1);
    void reset() { sampler_.reset(); }

    VkSampler get() const { return sampler_.get(); }

private:
    UniqueSampler sampler_;
};

// Unfiltered reads (texelFetch) of images whose formats need not support linear filtering (a
// host's depth buffer): nearest, clamp to edge. Move-only.
class NearestClampSampler {
public:
    NearestClampSampler() = default;
    explicit NearestClampSampler(const Device& device);
    VkSampler get() const { return sampler_.get(); }

private:
    UniqueSampler sampler_;
};

// One descriptor binding of a compute pipeline's own set.
struct Binding {
    VkDescriptorType type;  // STORAGE_IMAGE, STORAGE_BUFFER, UNIFORM_BUFFER, COMBINED_IMAGE_SAMPLER
    uint32_t count = 1;
};

// A compute pipeline with its layout: set 0 = the frame set (shaders/fovea_frame.glsl) when
// frame_set_layout is given, then one own set described by `bindings` (set 1, or set 0 when no
// frame set), and a push-constant range of push_bytes. Its pool holds max_sets own sets.
// host_set_layout: the host's set (FoveatorConfig::host_set_layout) after the own set; bind()
// then also binds *host_set, the frame's set, which the Foveator updates before each record.
class ComputePipeline {
public:
    ComputePipeline() = default;
    ComputePipeline(const Device& device, std::span<const uint32_t> spirv,
                    VkDescriptorSetLayout frame_set_layout, std::span<const Binding> bindings,
                    uint32_t push_bytes, std::span<const uint32_t> spec_constants = {},
                    uint32_t max_sets = 8, VkDescriptorSetLayout host_set_layout = VK_NULL_HANDLE,
                    const VkDescriptorSet* host_set = nullptr);
    void reset() { *this = ComputePipeline(); }

    VkPipeline get() const { return pipeline_.get(); }
    VkPipelineLayout layout() const { return layout_.get(); }
    VkDescriptorSetLayout set_layout() const { return set_layout_.get(); }
    uint32_t own_set_index() const { return own_set_; }

    // Allocates one set of the own layout from this pipeline's private pool (max_sets total).
    VkDescriptorSet allocate_set();

    // Binds the pipeline, the frame set (if any) and `own` set, pushes constants.
    void bind(VkCommandBuffer cmd, VkDescriptorSet frame_set, VkDescriptorSet own,
              const void* push = nullptr, uint32_t push_bytes = 0) const;

private:
    UniqueDescriptorSetLayout set_layout_;  // destroyed in reverse: pool, pipeline, layouts
    UniquePipelineLayout layout_;
    UniquePipeline pipeline_;
    UniqueDescriptorPool pool_;
    uint32_t own_set_ = 0;
    uint32_t push_bytes_ = 0;
    const VkDescriptorSet* host_set_ = nullptr;  // bound at own_set_ + 1 when set
};

// Writes descriptors of a set: chain storage_image()/.../uniform_buffer() calls, then commit().
class DescriptorWriter {
public:
    DescriptorWriter(VkDevice device, VkDescriptorSet set) : device_(device), set_(set) {}
    DescriptorWriter& storage_image(uint32_t binding, VkImageView view);
    DescriptorWriter& sampled_image(uint32_t binding, VkImageView view, VkSampler sampler,
                                    VkImageLayout layout = VK_IMAGE_LAYOUT_GENERAL);
    DescriptorWriter& storage_buffer(uint32_t binding, const Buffer& buffer);
    DescriptorWriter& uniform_buffer(uint32_t binding, const Buffer& buffer);
    // A texel buffer view (texel_view()): uniform = samplerBuffer (texelFetch), storage =
    // imageBuffer (imageLoad / imageStore).
    DescriptorWriter& uniform_texel_buffer(uint32_t binding, VkBufferView view);
    DescriptorWriter& storage_texel_buffer(uint32_t binding, VkBufferView view);
    void commit();

private:
    VkDevice device_;
    VkDescriptorSet set_;
    std::vector<VkDescriptorImageInfo> images_;
    std::vector<VkDescriptorBufferInfo> buffers_;
    std::vector<VkBufferView> texel_views_;
    struct Pending {
        uint32_t binding;
        VkDescriptorType type;
        size_t index;  // into images_, buffers_ or texel_views_, by type
    };
    std::vector<Pending> pending_;
};

// A view of all of `buffer` as texels of `format` (texel_bytes each), for a texel buffer
// descriptor; the buffer needs the matching *_TEXEL_BUFFER usage. Why texel buffers: on llvmpipe a
// texelFetch is one vector gather, while an SSBO or shared-memory load with an index that differs
// between lanes is a loop of scalar loads, lane by lane.
UniqueBufferView texel_view(const Device& device, const Buffer& buffer,
                            VkFormat format = VK_FORMAT_R32G32B32A32_SFLOAT,
                            VkDeviceSize texel_bytes = 16);

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
