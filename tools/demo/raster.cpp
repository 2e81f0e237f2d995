#include "fovea/demo/raster.hpp"

#include <array>
#include <utility>

#include "fovea/vk/check.hpp"

namespace fovea::demo {

DepthImage::DepthImage(const vk::Device& device, VkExtent2D extent) {
    const VkDevice d = device.device();
    VkImageCreateInfo ici{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    ici.imageType = VK_IMAGE_TYPE_2D;
    ici.format = kDepthFormat;
    ici.extent = {extent.width, extent.height, 1};
    ici.mipLevels = 1;
    ici.arrayLayers = 1;
    ici.samples = VK_SAMPLE_COUNT_1_BIT;
    ici.tiling = VK_IMAGE_TILING_OPTIMAL;
    ici.usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
    ici.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    image_ = vk::create_handle<vk::UniqueImage>(d, vkCreateImage, ici);
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(d, image_.get(), &req);
    VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    mai.allocationSize = req.size;
    mai.memoryTypeIndex =
        device.memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    memory_ = vk::create_handle<vk::UniqueDeviceMemory>(d, vkAllocateMemory, mai);
    VK_CHECK(vkBindImageMemory(d, image_.get(), memory_.get(), 0));
    VkImageViewCreateInfo vci{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    vci.image = image_.get();
    vci.viewType = VK_IMAGE_VIEW_TYPE_2D;
    vci.format = kDepthFormat;
    vci.subresourceRange = {VK_IMAGE_ASPECT_DEPTH_BIT, 0, 1, 0, 1};
    view_ = vk::create_handle<vk::UniqueImageView>(d, vkCreateImageView, vci);
}

GBufferRenderPass::GBufferRenderPass(const vk::Device& device) {
    std::array<VkAttachmentDescription, vk::kGBufferImageCount + 1> att{};
    std::array<VkAttachmentReference, vk::kGBufferImageCount> color{};
    for (int i = 0; i < vk::kGBufferImageCount; ++i) {
        att[i].format = vk::kGBufferFormats[i];
        att[i].samples = VK_SAMPLE_COUNT_1_BIT;
        att[i].loadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;  // every pixel is written (sky last)
        att[i].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
        att[i].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
        att[i].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
        att[i].initialLayout = VK_IMAGE_LAYOUT_GENERAL;
        att[i].finalLayout = VK_IMAGE_LAYOUT_GENERAL;
        color[i] = {static_cast<uint32_t>(i), VK_IMAGE_LAYOUT_GENERAL};
    }
    VkAttachmentDescription& depth = att[vk::kGBufferImageCount];
    depth.format = kDepthFormat;
    depth.samples = VK_SAMPLE_COUNT_1_BIT;
    depth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    depth.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    depth.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    depth.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    depth.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    depth.finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    const VkAttachmentReference depth_ref{vk::kGBufferImageCount,
                                          VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkSubpassDescription sub{};
    sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    sub.colorAttachmentCount = vk::kGBufferImageCount;
    sub.pColorAttachments = color.data();
    sub.pDepthStencilAttachment = &depth_ref;
    // Before: the previous frame's compute/transfer reads of the G-buffer and an earlier view's
    // use of the same depth image. After: the module's compute passes and copies.
    constexpr VkPipelineStageFlags kCompute =
        VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
    constexpr VkPipelineStageFlags kRaster = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                                             VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |
                                             VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
    constexpr VkAccessFlags kComputeAccess =
        VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT |
        VK_ACCESS_TRANSFER_WRITE_BIT;
    constexpr VkAccessFlags kRasterAccess = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
                                            VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                                            VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    const std::array<VkSubpassDependency, 2> deps{{
        {VK_SUBPASS_EXTERNAL, 0, kCompute | kRaster, kRaster, kComputeAccess | kRasterAccess,
         kRasterAccess, 0},
        {0, VK_SUBPASS_EXTERNAL, kRaster, kCompute | kRaster, kRasterAccess,
         kComputeAccess | kRasterAccess, 0},
    }};
    VkRenderPassCreateInfo rpi{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    rpi.attachmentCount = static_cast<uint32_t>(att.size());
    rpi.pAttachments = att.data();
    rpi.subpassCount = 1;
    rpi.pSubpasses = &sub;
    rpi.dependencyCount = static_cast<uint32_t>(deps.size());
    rpi.pDependencies = deps.data();
    pass_ = vk::create_handle<vk::UniqueRenderPass>(device.device(), vkCreateRenderPass, rpi);
}

void GBufferRenderPass::release_framebuffers() { framebuffers_.clear(); }

void GBufferRenderPass::begin(VkCommandBuffer cmd, const vk::GBufferRefs& g, VkImageView depth) {
    std::array<VkImageView, vk::kGBufferImageCount + 1> views{};
    for (int i = 0; i < vk::kGBufferImageCount; ++i) views[i] = g.images[i].view;
    views[vk::kGBufferImageCount] = depth;
    // A framebuffer per use: the module may recreate its images between frames (method switch).
    VkFramebufferCreateInfo fci{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    fci.renderPass = pass_.get();
    fci.attachmentCount = static_cast<uint32_t>(views.size());
    fci.pAttachments = views.data();
    fci.width = g.extent.width;
    fci.height = g.extent.height;
    fci.layers = 1;
    framebuffers_.push_back(
        vk::create_handle<vk::UniqueFramebuffer>(pass_.parent(), vkCreateFramebuffer, fci));
    const VkFramebuffer fb = framebuffers_.back().get();
    std::array<VkClearValue, vk::kGBufferImageCount + 1> clear{};
    clear[vk::kGBufferImageCount].depthStencil = {0.0f, 0};  // reverse-Z: far
    VkRenderPassBeginInfo bi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    bi.renderPass = pass_.get();
    bi.framebuffer = fb;
    bi.renderArea = {{0, 0}, g.extent};
    bi.clearValueCount = static_cast<uint32_t>(clear.size());
    bi.pClearValues = clear.data();
    vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
    const VkViewport vp{
        0.f, 0.f, static_cast<float>(g.extent.width), static_cast<float>(g.extent.height),
        0.f, 1.f};
    vkCmdSetViewport(cmd, 0, 1, &vp);
    const VkRect2D scissor{{0, 0}, g.extent};
    vkCmdSetScissor(cmd, 0, 1, &scissor);
}

BufferSetLayout::BufferSetLayout(const vk::Device& device, VkBuffer buffer, VkDeviceSize range) {
    const VkDevice d = device.device();
    constexpr VkShaderStageFlags kStages =
        VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
    constexpr VkDescriptorType kType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC;
    const VkDescriptorSetLayoutBinding b{0, kType, 1, kStages, nullptr};
    VkDescriptorSetLayoutCreateInfo dl{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    dl.bindingCount = 1;
    dl.pBindings = &b;
    set_layout_ =
        vk::create_handle<vk::UniqueDescriptorSetLayout>(d, vkCreateDescriptorSetLayout, dl);
    const VkDescriptorSetLayout set_layout = set_layout_.get();
    VkPipelineLayoutCreateInfo pl{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    pl.setLayoutCount = 1;
    pl.pSetLayouts = &set_layout;
    layout_ = vk::create_handle<vk::UniquePipelineLayout>(d, vkCreatePipelineLayout, pl);
    const VkDescriptorPoolSize size{kType, 1};
    VkDescriptorPoolCreateInfo dpi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    dpi.maxSets = 1;
    dpi.poolSizeCount = 1;
    dpi.pPoolSizes = &size;
    pool_ = vk::create_handle<vk::UniqueDescriptorPool>(d, vkCreateDescriptorPool, dpi);
    VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    ai.descriptorPool = pool_.get();
    ai.descriptorSetCount = 1;
    ai.pSetLayouts = &set_layout;
    VK_CHECK(vkAllocateDescriptorSets(d, &ai, &set_));
    const VkDescriptorBufferInfo info{buffer, 0, range};
    VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstSet = set_;
    w.descriptorCount = 1;
    w.descriptorType = kType;
    w.pBufferInfo = &info;
    vkUpdateDescriptorSets(d, 1, &w, 0, nullptr);
}

namespace {

vk::UniqueShaderModule make_module(VkDevice device, std::span<const uint32_t> spirv) {
    VkShaderModuleCreateInfo smi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    smi.codeSize = spirv.size() * sizeof(uint32_t);
    smi.pCode = spirv.data();
    return vk::create_handle<vk::UniqueShaderModule>(device, vkCreateShaderModule, smi);
}

}  // namespace

GraphicsPipeline::GraphicsPipeline(const vk::Device& device, VkPipelineLayout layout,
                                   VkRenderPass pass, uint32_t color_attachments,
                                   std::span<const uint32_t> vert, std::span<const uint32_t> frag,
                                   RasterState state, std::span<const uint32_t> vert_spec) {
    const VkDevice d = device.device();
    std::vector<VkSpecializationMapEntry> entries;
    for (uint32_t i = 0; i < vert_spec.size(); ++i) entries.push_back({i, i * 4u, 4});
    const VkSpecializationInfo spec{static_cast<uint32_t>(entries.size()), entries.data(),
                                    vert_spec.size() * 4, vert_spec.data()};
    const vk::UniqueShaderModule vm = make_module(d, vert);
    const vk::UniqueShaderModule fm = make_module(d, frag);
    std::array<VkPipelineShaderStageCreateInfo, 2> stages{};
    stages[0] = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
    stages[0].module = vm.get();
    stages[0].pName = "main";
    stages[0].pSpecializationInfo = entries.empty() ? nullptr : &spec;
    stages[1] = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
    stages[1].module = fm.get();
    stages[1].pName = "main";
    VkPipelineVertexInputStateCreateInfo vin{
        VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    VkPipelineInputAssemblyStateCreateInfo ia{
        VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    ia.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    VkPipelineViewportStateCreateInfo vps{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    vps.viewportCount = 1;
    vps.scissorCount = 1;
    VkPipelineRasterizationStateCreateInfo rs{
        VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    rs.polygonMode = VK_POLYGON_MODE_FILL;
    rs.cullMode = state.cull;
    rs.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    rs.lineWidth = 1.f;
    VkPipelineMultisampleStateCreateInfo ms{
        VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    ms.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    VkPipelineDepthStencilStateCreateInfo ds{
        VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    ds.depthTestEnable = state.depth_test;
    ds.depthWriteEnable = state.depth_write;
    ds.depthCompareOp = VK_COMPARE_OP_GREATER_OR_EQUAL;
    std::vector<VkPipelineColorBlendAttachmentState> blend(color_attachments);
    for (auto& b : blend)
        b.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT |
                           VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
    VkPipelineColorBlendStateCreateInfo cb{
        VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    cb.attachmentCount = color_attachments;
    cb.pAttachments = blend.data();
    const std::array<VkDynamicState, 2> dyn{VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dy{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    dy.dynamicStateCount = static_cast<uint32_t>(dyn.size());
    dy.pDynamicStates = dyn.data();
    VkGraphicsPipelineCreateInfo gpi{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
    gpi.stageCount = static_cast<uint32_t>(stages.size());
    gpi.pStages = stages.data();
    gpi.pVertexInputState = &vin;
    gpi.pInputAssemblyState = &ia;
    gpi.pViewportState = &vps;
    gpi.pRasterizationState = &rs;
    gpi.pMultisampleState = &ms;
    gpi.pDepthStencilState = &ds;
    gpi.pColorBlendState = &cb;
    gpi.pDynamicState = &dy;
    gpi.layout = layout;
    gpi.renderPass = pass;
    pipeline_ = vk::create_pipeline(d, vkCreateGraphicsPipelines, gpi);
}

}  // namespace fovea::demo
