#include "gltf_viewer/vk_util.hpp"

#include <cstring>

namespace gltfv {

void vk_fail(VkResult r, const char* call) {
    throw std::runtime_error(std::string(call) + " failed: VkResult " + std::to_string(r));
}

uint32_t Gpu::memory_type(uint32_t bits, VkMemoryPropertyFlags flags) const {
    VkPhysicalDeviceMemoryProperties mem;
    vkGetPhysicalDeviceMemoryProperties(physical, &mem);
    for (uint32_t i = 0; i < mem.memoryTypeCount; ++i)
        if ((bits & (1u << i)) && (mem.memoryTypes[i].propertyFlags & flags) == flags) return i;
    throw std::runtime_error("no Vulkan memory type with the wanted properties");
}

Buffer make_buffer(const Gpu& gpu, VkDeviceSize size, VkBufferUsageFlags usage, bool host_visible) {
    Buffer b;
    b.size = size;
    VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bci.size = size;
    bci.usage = usage;
    VkBuffer raw = VK_NULL_HANDLE;
    GLTFV_CHECK(vkCreateBuffer(gpu.device, &bci, nullptr, &raw));
    b.buffer = BufferHandle(gpu.device, raw);
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(gpu.device, raw, &req);
    VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    mai.allocationSize = req.size;
    mai.memoryTypeIndex =
        gpu.memory_type(req.memoryTypeBits, host_visible ? VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                                               VK_MEMORY_PROPERTY_HOST_COHERENT_BIT
                                                         : VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    VkDeviceMemory mem = VK_NULL_HANDLE;
    GLTFV_CHECK(vkAllocateMemory(gpu.device, &mai, nullptr, &mem));
    b.memory = Memory(gpu.device, mem);
    GLTFV_CHECK(vkBindBufferMemory(gpu.device, raw, mem, 0));
    if (host_visible) GLTFV_CHECK(vkMapMemory(gpu.device, mem, 0, VK_WHOLE_SIZE, 0, &b.mapped));
    return b;
}

Image make_image(const Gpu& gpu, VkExtent2D extent, VkFormat format, VkImageUsageFlags usage,
                 uint32_t mips, VkImageAspectFlags aspect) {
    Image im;
    im.extent = extent;
    im.format = format;
    im.mips = mips;
    VkImageCreateInfo ici{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    ici.imageType = VK_IMAGE_TYPE_2D;
    ici.format = format;
    ici.extent = {extent.width, extent.height, 1};
    ici.mipLevels = mips;
    ici.arrayLayers = 1;
    ici.samples = VK_SAMPLE_COUNT_1_BIT;
    ici.usage = usage;
    VkImage raw = VK_NULL_HANDLE;
    GLTFV_CHECK(vkCreateImage(gpu.device, &ici, nullptr, &raw));
    im.image = ImageHandle(gpu.device, raw);
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(gpu.device, raw, &req);
    VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    mai.allocationSize = req.size;
    mai.memoryTypeIndex = gpu.memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    VkDeviceMemory mem = VK_NULL_HANDLE;
    GLTFV_CHECK(vkAllocateMemory(gpu.device, &mai, nullptr, &mem));
    im.memory = Memory(gpu.device, mem);
    GLTFV_CHECK(vkBindImageMemory(gpu.device, raw, mem, 0));
    constexpr VkImageUsageFlags kViewed = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT |
                                          VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT |
                                          VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
    if (!(usage & kViewed)) return im;  // transfer-only images have no view
    VkImageViewCreateInfo vci{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    vci.image = raw;
    vci.viewType = VK_IMAGE_VIEW_TYPE_2D;
    vci.format = format;
    vci.subresourceRange = {aspect, 0, mips, 0, 1};
    VkImageView view = VK_NULL_HANDLE;
    GLTFV_CHECK(vkCreateImageView(gpu.device, &vci, nullptr, &view));
    im.view = ImageView(gpu.device, view);
    return im;
}

Submitter::Submitter(const Gpu& gpu) : gpu_(&gpu) {
    VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pci.queueFamilyIndex = gpu.queue_family;
    VkCommandPool pool = VK_NULL_HANDLE;
    GLTFV_CHECK(vkCreateCommandPool(gpu.device, &pci, nullptr, &pool));
    pool_ = CommandPool(gpu.device, pool);
    VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkFence fence = VK_NULL_HANDLE;
    GLTFV_CHECK(vkCreateFence(gpu.device, &fci, nullptr, &fence));
    fence_ = Fence(gpu.device, fence);
}

void Submitter::run(const std::function<void(VkCommandBuffer)>& record) {
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = pool_.get();
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    GLTFV_CHECK(vkAllocateCommandBuffers(gpu_->device, &ai, &cmd));
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    GLTFV_CHECK(vkBeginCommandBuffer(cmd, &bi));
    record(cmd);
    GLTFV_CHECK(vkEndCommandBuffer(cmd));
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cmd;
    const VkFence fence = fence_.get();
    GLTFV_CHECK(vkResetFences(gpu_->device, 1, &fence));
    GLTFV_CHECK(vkQueueSubmit(gpu_->queue, 1, &si, fence));
    GLTFV_CHECK(vkWaitForFences(gpu_->device, 1, &fence, VK_TRUE, UINT64_MAX));
    vkFreeCommandBuffers(gpu_->device, pool_.get(), 1, &cmd);
}

ShaderModule make_shader(VkDevice device, std::span<const uint32_t> spirv) {
    VkShaderModuleCreateInfo smi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    smi.codeSize = spirv.size() * sizeof(uint32_t);
    smi.pCode = spirv.data();
    VkShaderModule m = VK_NULL_HANDLE;
    GLTFV_CHECK(vkCreateShaderModule(device, &smi, nullptr, &m));
    return ShaderModule(device, m);
}

void image_barrier(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to,
                   uint32_t base_mip, uint32_t mips, VkImageAspectFlags aspect) {
    VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    b.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
    b.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    b.oldLayout = from;
    b.newLayout = to;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange = {aspect, base_mip, mips, 0, 1};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                         VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 0, nullptr, 0, nullptr, 1, &b);
}

std::vector<uint8_t> read_back(const Gpu& gpu, Submitter& submit, VkImage image, VkExtent2D extent,
                               uint32_t texel_bytes) {
    const VkDeviceSize bytes = VkDeviceSize{extent.width} * extent.height * texel_bytes;
    Buffer staging = make_buffer(gpu, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, true);
    submit.run([&](VkCommandBuffer cmd) {
        VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        mb.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
        mb.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                             VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &mb, 0, nullptr, 0, nullptr);
        VkBufferImageCopy region{};
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.imageExtent = {extent.width, extent.height, 1};
        vkCmdCopyImageToBuffer(cmd, image, VK_IMAGE_LAYOUT_GENERAL, staging.get(), 1, &region);
        mb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1,
                             &mb, 0, nullptr, 0, nullptr);
    });
    std::vector<uint8_t> out(bytes);
    std::memcpy(out.data(), staging.mapped, bytes);
    return out;
}

}  // namespace gltfv
