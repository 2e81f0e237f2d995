#include "gpu.hpp"

#include <algorithm>
#include <cassert>
#include <cstring>

namespace fovea::vk {

Buffer::Buffer(const Device& device, VkDeviceSize size, VkBufferUsageFlags usage, bool host_visible)
    : size_(size) {
    const VkDevice d = device.device();
    VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bci.size = size;
    bci.usage = usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    buffer_ = create_handle<UniqueBuffer>(d, vkCreateBuffer, bci);
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(d, buffer_.get(), &req);
    VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    mai.allocationSize = req.size;
    mai.memoryTypeIndex = device.memory_type(
        req.memoryTypeBits,
        host_visible ? VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT
                     : VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    memory_ = create_handle<UniqueDeviceMemory>(d, vkAllocateMemory, mai);
    VK_CHECK(vkBindBufferMemory(d, buffer_.get(), memory_.get(), 0));
    if (host_visible) {
        VK_CHECK(vkMapMemory(d, memory_.get(), 0, VK_WHOLE_SIZE, 0, &mapped_));
        std::memset(mapped_, 0, size);
    }
}

Buffer& Buffer::operator=(Buffer&& o) noexcept {
    if (this != &o) {
        buffer_ = std::move(o.buffer_);
        memory_ = std::move(o.memory_);
        size_ = std::exchange(o.size_, 0);
        mapped_ = std::exchange(o.mapped_, nullptr);
    }
    return *this;
}

Image::Image(const Device& device, VkExtent2D extent, VkFormat format, VkImageUsageFlags usage,
             uint32_t mip_levels)
    : mips_(mip_levels) {
    assert(extent.width > 0 && extent.height > 0);
    const VkDevice d = device.device();
    VkImageCreateInfo ici{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    ici.imageType = VK_IMAGE_TYPE_2D;
    ici.format = format;
    ici.extent = {extent.width, extent.height, 1};
    ici.mipLevels = mip_levels;
    ici.arrayLayers = 1;
    ici.samples = VK_SAMPLE_COUNT_1_BIT;
    ici.tiling = VK_IMAGE_TILING_OPTIMAL;
    ici.usage = usage | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    ici.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    image_ = create_handle<UniqueImage>(d, vkCreateImage, ici);
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(d, image_.get(), &req);
    VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    mai.allocationSize = req.size;
    mai.memoryTypeIndex =
        device.memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    memory_ = create_handle<UniqueDeviceMemory>(d, vkAllocateMemory, mai);
    VK_CHECK(vkBindImageMemory(d, image_.get(), memory_.get(), 0));
    VkImageViewCreateInfo vci{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    vci.image = image_.get();
    vci.viewType = VK_IMAGE_VIEW_TYPE_2D;
    vci.format = format;
    vci.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, mip_levels, 0, 1};
    view_ = create_handle<UniqueImageView>(d, vkCreateImageView, vci);
    if (mip_levels > 1) {
        for (uint32_t m = 0; m < mip_levels; ++m) {
            vci.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, m, 1, 0, 1};
            mip_views_.push_back(create_handle<UniqueImageView>(d, vkCreateImageView, vci));
        }
    }
    const VkImage img = image_.get();
    device.submit_and_wait([&](VkCommandBuffer cmd) {
        VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
        b.srcAccessMask = 0;
        b.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        b.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
        b.newLayout = VK_IMAGE_LAYOUT_GENERAL;
        b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        b.image = img;
        b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, mip_levels, 0, 1};
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                             0, 0, nullptr, 0, nullptr, 1, &b);
        VkClearColorValue zero{};
        VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, mip_levels, 0, 1};
        vkCmdClearColorImage(cmd, img, VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &range);
        VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        mb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        mb.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                             VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &mb, 0, nullptr, 0,
                             nullptr);
    });
    ref_ = {image_.get(), view_.get(), format, extent};
}

Image& Image::operator=(Image&& o) noexcept {
    if (this != &o) {
        mip_views_.clear();
        view_ = std::move(o.view_);
        image_ = std::move(o.image_);
        memory_ = std::move(o.memory_);
        mip_views_ = std::exchange(o.mip_views_, {});
        ref_ = std::exchange(o.ref_, ImageRef{});
        mips_ = std::exchange(o.mips_, 1);
    }
    return *this;
}

VkImageView Image::mip_view(uint32_t level) const {
    if (mips_ == 1 && level == 0) return view_.get();
    return mip_views_.at(level).get();
}

LinearClampSampler::LinearClampSampler(const Device& device, uint32_t mip_levels) {
    VkSamplerCreateInfo sci{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    sci.magFilter = sci.minFilter = VK_FILTER_LINEAR;
    sci.mipmapMode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
    sci.addressModeU = sci.addressModeV = sci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    sci.maxLod = float(std::max(1u, mip_levels) - 1);
    sampler_ = create_handle<UniqueSampler>(device.device(), vkCreateSampler, sci);
}

NearestClampSampler::NearestClampSampler(const Device& device) {
    VkSamplerCreateInfo sci{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    sci.magFilter = sci.minFilter = VK_FILTER_NEAREST;
    sci.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    sci.addressModeU = sci.addressModeV = sci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    sampler_ = create_handle<UniqueSampler>(device.device(), vkCreateSampler, sci);
}

ComputePipeline::ComputePipeline(const Device& device, std::span<const uint32_t> spirv,
                                 VkDescriptorSetLayout frame_set_layout,
                                 std::span<const Binding> bindings, uint32_t push_bytes,
                                 std::span<const uint32_t> spec_constants, uint32_t max_sets,
                                 VkDescriptorSetLayout host_set_layout,
                                 const VkDescriptorSet* host_set)
    : push_bytes_(push_bytes) {
    const VkDevice d = device.device();
    std::vector<VkDescriptorSetLayoutBinding> lb;
    std::vector<VkDescriptorPoolSize> sizes;
    for (uint32_t i = 0; i < bindings.size(); ++i) {
        VkDescriptorSetLayoutBinding b{};
        b.binding = i;
        b.descriptorType = bindings[i].type;
        b.descriptorCount = bindings[i].count;
        b.stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
        lb.push_back(b);
        sizes.push_back({bindings[i].type, bindings[i].count * max_sets});
    }
    VkDescriptorSetLayoutCreateInfo dl{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    dl.bindingCount = static_cast<uint32_t>(lb.size());
    dl.pBindings = lb.data();
    set_layout_ = create_handle<UniqueDescriptorSetLayout>(d, vkCreateDescriptorSetLayout, dl);
    std::vector<VkDescriptorSetLayout> sets;
    if (frame_set_layout) sets.push_back(frame_set_layout);
    own_set_ = static_cast<uint32_t>(sets.size());
    sets.push_back(set_layout_.get());
    if (host_set_layout) {
        sets.push_back(host_set_layout);
        host_set_ = host_set;
    }
    VkPushConstantRange pcr{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes};
    VkPipelineLayoutCreateInfo pl{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    pl.setLayoutCount = static_cast<uint32_t>(sets.size());
    pl.pSetLayouts = sets.data();
    pl.pushConstantRangeCount = push_bytes ? 1 : 0;
    pl.pPushConstantRanges = &pcr;
    layout_ = create_handle<UniquePipelineLayout>(d, vkCreatePipelineLayout, pl);
    VkShaderModuleCreateInfo smi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    smi.codeSize = spirv.size() * sizeof(uint32_t);
    smi.pCode = spirv.data();
    const UniqueShaderModule module =
        create_handle<UniqueShaderModule>(d, vkCreateShaderModule, smi);
    std::vector<VkSpecializationMapEntry> entries;
    for (uint32_t i = 0; i < spec_constants.size(); ++i) entries.push_back({i, i * 4u, 4});
    VkSpecializationInfo spec{static_cast<uint32_t>(entries.size()), entries.data(),
                              spec_constants.size() * 4, spec_constants.data()};
    VkComputePipelineCreateInfo cpi{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    cpi.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    cpi.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    cpi.stage.module = module.get();
    cpi.stage.pName = "main";
    cpi.stage.pSpecializationInfo = entries.empty() ? nullptr : &spec;
    cpi.layout = layout_.get();
    pipeline_ = create_pipeline(d, vkCreateComputePipelines, cpi);
    if (!sizes.empty()) {
        VkDescriptorPoolCreateInfo dpi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        dpi.maxSets = max_sets;
        dpi.poolSizeCount = static_cast<uint32_t>(sizes.size());
        dpi.pPoolSizes = sizes.data();
        pool_ = create_handle<UniqueDescriptorPool>(d, vkCreateDescriptorPool, dpi);
    }
}

VkDescriptorSet ComputePipeline::allocate_set() {
    assert(pool_ && "pipeline has no own bindings");
    const VkDescriptorSetLayout layout = set_layout_.get();
    VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    ai.descriptorPool = pool_.get();
    ai.descriptorSetCount = 1;
    ai.pSetLayouts = &layout;
    VkDescriptorSet set = VK_NULL_HANDLE;  // freed with the pool
    VK_CHECK(vkAllocateDescriptorSets(pool_.parent(), &ai, &set));
    return set;
}

void ComputePipeline::bind(VkCommandBuffer cmd, VkDescriptorSet frame_set, VkDescriptorSet own,
                           const void* push, uint32_t push_bytes) const {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.get());
    if (own_set_ == 1) {
        assert(frame_set);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.get(), 0, 1,
                                &frame_set, 0, nullptr);
    }
    if (own)
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.get(), own_set_, 1,
                                &own, 0, nullptr);
    if (host_set_ && *host_set_)
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.get(), own_set_ + 1, 1,
                                host_set_, 0, nullptr);
    if (push && push_bytes) {
        assert(push_bytes <= push_bytes_);
        vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes, push);
    }
}

DescriptorWriter& DescriptorWriter::storage_image(uint32_t binding, VkImageView view) {
    images_.push_back({VK_NULL_HANDLE, view, VK_IMAGE_LAYOUT_GENERAL});
    pending_.push_back({binding, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, images_.size() - 1});
    return *this;
}

DescriptorWriter& DescriptorWriter::sampled_image(uint32_t binding, VkImageView view,
                                                  VkSampler sampler, VkImageLayout layout) {
    images_.push_back({sampler, view, layout});
    pending_.push_back({binding, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, images_.size() - 1});
    return *this;
}

DescriptorWriter& DescriptorWriter::storage_buffer(uint32_t binding, const Buffer& buffer) {
    buffers_.push_back(buffer.info());
    pending_.push_back({binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, buffers_.size() - 1});
    return *this;
}

DescriptorWriter& DescriptorWriter::uniform_buffer(uint32_t binding, const Buffer& buffer) {
    buffers_.push_back(buffer.info());
    pending_.push_back({binding, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, buffers_.size() - 1});
    return *this;
}

DescriptorWriter& DescriptorWriter::uniform_texel_buffer(uint32_t binding, VkBufferView view) {
    texel_views_.push_back(view);
    pending_.push_back({binding, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, texel_views_.size() - 1});
    return *this;
}

DescriptorWriter& DescriptorWriter::storage_texel_buffer(uint32_t binding, VkBufferView view) {
    texel_views_.push_back(view);
    pending_.push_back({binding, VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER, texel_views_.size() - 1});
    return *this;
}

void DescriptorWriter::commit() {
    std::vector<VkWriteDescriptorSet> writes;
    for (const Pending& p : pending_) {
        VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w.dstSet = set_;
        w.dstBinding = p.binding;
        w.descriptorCount = 1;
        w.descriptorType = p.type;
        switch (p.type) {
            case VK_DESCRIPTOR_TYPE_STORAGE_IMAGE:
            case VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER: w.pImageInfo = &images_[p.index]; break;
            case VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER:
            case VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER:
                w.pTexelBufferView = &texel_views_[p.index];
                break;
            case VK_DESCRIPTOR_TYPE_STORAGE_BUFFER:
            case VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER: w.pBufferInfo = &buffers_[p.index]; break;
            default: assert(false && "DescriptorWriter: no writer for this descriptor type");
        }
        writes.push_back(w);
    }
    vkUpdateDescriptorSets(device_, static_cast<uint32_t>(writes.size()), writes.data(), 0,
                           nullptr);
    pending_.clear();
}

UniqueBufferView texel_view(const Device& device, const Buffer& buffer, VkFormat format,
                            VkDeviceSize texel_bytes) {
    VkBufferViewCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
    bi.buffer = buffer.get();
    bi.format = format;
    bi.range = buffer.size() / texel_bytes * texel_bytes;
    return create_handle<UniqueBufferView>(device.device(), vkCreateBufferView, bi);
}

void compute_barrier(VkCommandBuffer cmd) {
    VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    mb.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                       VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0,
                         1, &mb, 0, nullptr, 0, nullptr);
}

void indirect_barrier(VkCommandBuffer cmd) {
    VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    mb.dstAccessMask = VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_SHADER_READ_BIT |
                       VK_ACCESS_SHADER_WRITE_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                         0, 1, &mb, 0, nullptr, 0, nullptr);
}

}  // namespace fovea::vk

namespace fovea::vk {

void upload_image(const Device& device, const ImageRef& image, std::span<const uint8_t> texels) {
    const VkDeviceSize bytes =
        VkDeviceSize{image.extent.width} * image.extent.height * format_bytes(image.format);
    assert(texels.size() == bytes);
    Buffer staging(device, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true);
    std::memcpy(staging.data(), texels.data(), bytes);
    device.submit_and_wait([&](VkCommandBuffer cmd) {
        VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        mb.srcAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
        mb.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                             VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &mb, 0, nullptr, 0, nullptr);
        VkBufferImageCopy region{};
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.imageExtent = {image.extent.width, image.extent.height, 1};
        vkCmdCopyBufferToImage(cmd, staging.get(), image.image, VK_IMAGE_LAYOUT_GENERAL, 1,
                               &region);
        VkMemoryBarrier after{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        after.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        after.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                             VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 1, &after, 0, nullptr, 0,
                             nullptr);
    });
}

}  // namespace fovea::vk
