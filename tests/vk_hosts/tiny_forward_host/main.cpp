// tiny_forward_host: the forward-layers path alone through the installed SDK. Renders a static
// scene with its own pipeline into every layer views() asks for, lets the SDK composite them,
// and compares the fovea with its own full-rate render (the same pass into the post-only path's
// targets). Prints "tiny_forward_host ok <foveal PSNR> <shaded fraction>"; exits 1 on failure.
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <stdexcept>
#include <vector>

#include "fovea/half.hpp"
#include "fovea/vk/foveator.hpp"
#include "fovea/vk/projection.hpp"
#include "scene_frag.h"
#include "scene_vert.h"

using namespace fovea::vk;

#define CHECK(x)                                                        \
    do {                                                                \
        if ((x) != VK_SUCCESS) throw std::runtime_error("failed: " #x); \
    } while (0)

struct Host {
    VkInstance instance = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    uint32_t family = 0;
    VkRenderPass pass = VK_NULL_HANDLE;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkPipeline pipeline = VK_NULL_HANDLE;
    // Per view size: a depth attachment; per target set: a framebuffer.
    std::map<std::pair<uint32_t, uint32_t>, std::pair<VkImage, VkDeviceMemory>> depth_images;
    std::map<std::pair<uint32_t, uint32_t>, VkImageView> depth_views;
    std::map<VkImageView, VkFramebuffer> framebuffers;

    void create() {
        VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
        app.apiVersion = VK_API_VERSION_1_1;
        VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
        ici.pApplicationInfo = &app;
        CHECK(vkCreateInstance(&ici, nullptr, &instance));
        uint32_t n = 1;  // the first device; VK_INCOMPLETE when there are more
        vkEnumeratePhysicalDevices(instance, &n, &physical);
        if (!physical) throw std::runtime_error("no Vulkan device");
        const float prio = 1.f;
        VkDeviceQueueCreateInfo q{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
        q.queueFamilyIndex = family;  // family 0: graphics + compute on common drivers
        q.queueCount = 1;
        q.pQueuePriorities = &prio;
        const VkPhysicalDeviceFeatures features = Device::requirements().features;
        VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
        dci.queueCreateInfoCount = 1;
        dci.pQueueCreateInfos = &q;
        dci.pEnabledFeatures = &features;
        CHECK(vkCreateDevice(physical, &dci, nullptr, &device));
        vkGetDeviceQueue(device, family, 0, &queue);
        make_pipeline();
    }

    void make_pipeline() {
        VkAttachmentDescription att[4] = {};
        const VkFormat formats[3] = {kHostColorFormat, kHostDepthFormat, kHostMotionFormat};
        VkAttachmentReference refs[3];
        for (int i = 0; i < 3; ++i) {
            att[i].format = formats[i];
            att[i].samples = VK_SAMPLE_COUNT_1_BIT;
            att[i].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
            att[i].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
            att[i].initialLayout = att[i].finalLayout = VK_IMAGE_LAYOUT_GENERAL;
            refs[i] = {uint32_t(i), VK_IMAGE_LAYOUT_GENERAL};
        }
        att[3].format = VK_FORMAT_D32_SFLOAT;
        att[3].samples = VK_SAMPLE_COUNT_1_BIT;
        att[3].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        att[3].finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
        const VkAttachmentReference dref{3, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
        VkSubpassDescription sub{};
        sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
        sub.colorAttachmentCount = 3;
        sub.pColorAttachments = refs;
        sub.pDepthStencilAttachment = &dref;
        // After the SDK's previous reads of the targets (its record() orders what follows).
        const VkSubpassDependency dep{
            VK_SUBPASS_EXTERNAL,
            0,
            VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
            VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT,
            VK_ACCESS_SHADER_READ_BIT,
            VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
            0};
        VkRenderPassCreateInfo rpi{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
        rpi.attachmentCount = 4;
        rpi.pAttachments = att;
        rpi.subpassCount = 1;
        rpi.pSubpasses = &sub;
        rpi.dependencyCount = 1;
        rpi.pDependencies = &dep;
        CHECK(vkCreateRenderPass(device, &rpi, nullptr, &pass));
        const VkPushConstantRange pcr{VK_SHADER_STAGE_VERTEX_BIT, 0, 64};
        VkPipelineLayoutCreateInfo pli{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
        pli.pushConstantRangeCount = 1;
        pli.pPushConstantRanges = &pcr;
        CHECK(vkCreatePipelineLayout(device, &pli, nullptr, &layout));
        VkShaderModule mods[2];
        const std::pair<const uint32_t*, size_t> code[2] = {{scene_vert, sizeof(scene_vert)},
                                                            {scene_frag, sizeof(scene_frag)}};
        VkPipelineShaderStageCreateInfo stages[2] = {};
        for (int i = 0; i < 2; ++i) {
            VkShaderModuleCreateInfo smi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
            smi.codeSize = code[i].second;
            smi.pCode = code[i].first;
            CHECK(vkCreateShaderModule(device, &smi, nullptr, &mods[i]));
            stages[i].sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
            stages[i].stage = i == 0 ? VK_SHADER_STAGE_VERTEX_BIT : VK_SHADER_STAGE_FRAGMENT_BIT;
            stages[i].module = mods[i];
            stages[i].pName = "main";
        }
        VkPipelineVertexInputStateCreateInfo vin{
            VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
        VkPipelineInputAssemblyStateCreateInfo ia{
            VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
        ia.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
        VkPipelineViewportStateCreateInfo vp{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
        vp.viewportCount = vp.scissorCount = 1;
        VkPipelineRasterizationStateCreateInfo rs{
            VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
        rs.lineWidth = 1.f;
        VkPipelineMultisampleStateCreateInfo ms{
            VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
        ms.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
        VkPipelineDepthStencilStateCreateInfo ds{
            VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
        ds.depthTestEnable = ds.depthWriteEnable = VK_TRUE;
        ds.depthCompareOp = VK_COMPARE_OP_LESS;
        VkPipelineColorBlendAttachmentState blend[3] = {};
        for (auto& b : blend) b.colorWriteMask = 0xf;
        VkPipelineColorBlendStateCreateInfo cb{
            VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
        cb.attachmentCount = 3;
        cb.pAttachments = blend;
        const VkDynamicState dyn[2] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
        VkPipelineDynamicStateCreateInfo dy{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
        dy.dynamicStateCount = 2;
        dy.pDynamicStates = dyn;
        VkGraphicsPipelineCreateInfo gp{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
        gp.stageCount = 2;
        gp.pStages = stages;
        gp.pVertexInputState = &vin;
        gp.pInputAssemblyState = &ia;
        gp.pViewportState = &vp;
        gp.pRasterizationState = &rs;
        gp.pMultisampleState = &ms;
        gp.pDepthStencilState = &ds;
        gp.pColorBlendState = &cb;
        gp.pDynamicState = &dy;
        gp.layout = layout;
        gp.renderPass = pass;
        CHECK(vkCreateGraphicsPipelines(device, VK_NULL_HANDLE, 1, &gp, nullptr, &pipeline));
        for (VkShaderModule m : mods) vkDestroyShaderModule(device, m, nullptr);
    }

    VkImageView depth_view(VkExtent2D e) {
        const auto key = std::make_pair(e.width, e.height);
        if (auto it = depth_views.find(key); it != depth_views.end()) return it->second;
        VkImageCreateInfo ici{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
        ici.imageType = VK_IMAGE_TYPE_2D;
        ici.format = VK_FORMAT_D32_SFLOAT;
        ici.extent = {e.width, e.height, 1};
        ici.mipLevels = ici.arrayLayers = 1;
        ici.samples = VK_SAMPLE_COUNT_1_BIT;
        ici.usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
        VkImage image;
        CHECK(vkCreateImage(device, &ici, nullptr, &image));
        VkMemoryRequirements req;
        vkGetImageMemoryRequirements(device, image, &req);
        VkPhysicalDeviceMemoryProperties mp;
        vkGetPhysicalDeviceMemoryProperties(physical, &mp);
        uint32_t type = 0;
        while (!(req.memoryTypeBits & (1u << type))) ++type;
        VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        mai.allocationSize = req.size;
        mai.memoryTypeIndex = type;
        VkDeviceMemory mem;
        CHECK(vkAllocateMemory(device, &mai, nullptr, &mem));
        CHECK(vkBindImageMemory(device, image, mem, 0));
        VkImageViewCreateInfo vci{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        vci.image = image;
        vci.viewType = VK_IMAGE_VIEW_TYPE_2D;
        vci.format = VK_FORMAT_D32_SFLOAT;
        vci.subresourceRange = {VK_IMAGE_ASPECT_DEPTH_BIT, 0, 1, 0, 1};
        VkImageView view;
        CHECK(vkCreateImageView(device, &vci, nullptr, &view));
        depth_images[key] = {image, mem};
        return depth_views[key] = view;
    }

    // The host's forward pass into one set of module targets with its projection.
    void render(VkCommandBuffer cmd, const HostTargets& t, const Mat4& view_proj) {
        VkFramebuffer& fb = framebuffers[t.color.view];
        if (!fb) {
            const VkImageView views[4] = {t.color.view, t.depth.view, t.motion.view,
                                          depth_view(t.extent)};
            VkFramebufferCreateInfo fci{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
            fci.renderPass = pass;
            fci.attachmentCount = 4;
            fci.pAttachments = views;
            fci.width = t.extent.width;
            fci.height = t.extent.height;
            fci.layers = 1;
            CHECK(vkCreateFramebuffer(device, &fci, nullptr, &fb));
        }
        VkClearValue clear[4] = {};
        clear[0].color = {{0.05f, 0.05f, 0.1f, 1.f}};
        clear[1].color = {{1.f, 0.f, 0.f, 0.f}};  // background depth: far
        clear[3].depthStencil = {1.f, 0};
        VkRenderPassBeginInfo bi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
        bi.renderPass = pass;
        bi.framebuffer = fb;
        bi.renderArea = {{0, 0}, t.extent};
        bi.clearValueCount = 4;
        bi.pClearValues = clear;
        vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
        const VkViewport vpt{0, 0, float(t.extent.width), float(t.extent.height), 0, 1};
        const VkRect2D sc{{0, 0}, t.extent};
        vkCmdSetViewport(cmd, 0, 1, &vpt);
        vkCmdSetScissor(cmd, 0, 1, &sc);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
        vkCmdPushConstants(cmd, layout, VK_SHADER_STAGE_VERTEX_BIT, 0, 64, view_proj.data());
        vkCmdDraw(cmd, 6 * 12 * 4, 1, 0, 0);
        vkCmdEndRenderPass(cmd);
    }

    void destroy() {
        vkDeviceWaitIdle(device);
        for (auto& [k, fb] : framebuffers) vkDestroyFramebuffer(device, fb, nullptr);
        for (auto& [k, v] : depth_views) vkDestroyImageView(device, v, nullptr);
        for (auto& [k, im] : depth_images) {
            vkDestroyImage(device, im.first, nullptr);
            vkFreeMemory(device, im.second, nullptr);
        }
        vkDestroyPipeline(device, pipeline, nullptr);
        vkDestroyPipelineLayout(device, layout, nullptr);
        vkDestroyRenderPass(device, pass, nullptr);
        vkDestroyDevice(device, nullptr);
        vkDestroyInstance(instance, nullptr);
    }
};

// 8-bit PSNR of the red channel within `radius_px` of the gaze.
double foveal_psnr(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, VkExtent2D e,
                   float gx, float gy, float radius_px) {
    double se = 0, n = 0;
    for (uint32_t y = 0; y < e.height; ++y)
        for (uint32_t x = 0; x < e.width; ++x) {
            if (std::hypot(x + 0.5f - gx, y + 0.5f - gy) > radius_px) continue;
            const auto to8 = [&](const std::vector<uint8_t>& img) {
                const float f = fovea::half_from_bytes(&img[(size_t(y) * e.width + x) * 8]);
                return std::round(std::fmin(f, 1.f) * 255.f);
            };
            const double d = to8(a) - to8(b);
            se += d * d;
            ++n;
        }
    const double mse = n ? se / n : 0;
    return mse <= 0 ? 100.0 : 10.0 * std::log10(255.0 * 255.0 / mse);
}

// Both paths' frames from the same pass; returns the foveal PSNR and the layers' shaded fraction.
std::pair<double, double> run(Host& h) {
    ExternalDevice ext{h.instance,
                       h.physical,
                       h.device,
                       h.queue,
                       h.family,
                       VK_API_VERSION_1_1,
                       Device::requirements().features};
    auto device = Device::wrap(ext);
    if (!device) throw std::runtime_error(device.error().message);
    const VkExtent2D size{640, 360};
    FoveatorConfig c;
    c.path = IntegrationPath::kForwardLayers;
    c.extent = size;
    c.display = EyeDisplay::from_fov(size.width, size.height, 60.0, 36.0);
    auto layers = Foveator::create(*device, c);
    c.path = IntegrationPath::kPostOnly;  // the full-rate render of the same pass
    auto full = Foveator::create(*device, c);
    if (!layers || !full) throw std::runtime_error("Foveator::create failed");
    if (layers->gbuffer().extent.width != 0) throw std::runtime_error("a G-buffer exists");
    const float tan_y = std::tan(18.f * 3.14159265f / 180.f);
    const float tan_x = tan_y * float(size.width) / float(size.height);
    Mat4 proj{};  // looking down -z from the origin, Vulkan clip space, depth 0 near .. 1 far
    proj[0] = 1.f / tan_x;
    proj[5] = -1.f / tan_y;
    proj[10] = 100.f / (0.1f - 100.f);
    proj[11] = -1.f;
    proj[14] = 0.1f * 100.f / (0.1f - 100.f);
    FrameInputs in;
    in.gaze.x = 0.45f;
    in.gaze.y = 0.55f;
    for (uint64_t frame = 0; frame < 2; ++frame) {
        in.camera_cut = frame == 0;
        device->submit_and_wait([&](VkCommandBuffer cmd) {
            for (const ViewRequest& v : layers->views(frame, in))
                h.render(cmd, v.targets, crop_projection(proj, v.crop, v.jitter_px, v.extent));
            layers->record(cmd, frame, in);
            h.render(cmd, full->host_targets(),
                     jittered_projection(proj, full->jitter(frame), size));
            full->record(cmd, frame, in);
        });
    }
    const ResolvedGaze g = layers->stats().gaze;
    const float radius = c.acuity.foveal_radius_deg * c.display.pixels_per_degree();
    const double db = foveal_psnr(device->read_image(layers->output()),
                                  device->read_image(full->output()), size, g.x_px, g.y_px, radius);
    return {db, layers->stats().shaded_fraction};
}

int main() {
    Host h;
    try {
        h.create();
        const auto [db, shaded] = run(h);  // the SDK's objects are gone before the device
        h.destroy();
        std::printf("tiny_forward_host %s %.1f dB %.3f\n", db >= 40.0 ? "ok" : "FAILED", db,
                    shaded);
        return db >= 40.0 ? 0 : 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "tiny_forward_host: %s\n", e.what());
        return 1;
    }
}
