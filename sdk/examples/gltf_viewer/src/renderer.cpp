#include "gltf_viewer/renderer.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "fovea/vk/projection.hpp"
#include "viewer_forward_frag.spv.h"
#include "viewer_gbuffer_frag.spv.h"
#include "viewer_mesh_vert.spv.h"
#include "viewer_shading_glsl.h"
#include "viewer_sky_forward_frag.spv.h"
#include "viewer_sky_gbuffer_frag.spv.h"
#include "viewer_sky_vert.spv.h"

namespace gltfv {
namespace {

constexpr uint32_t kMaxViews = 8;       // view-uniform slots per frame (full frame + layers)
constexpr uint32_t kMaxTexture = 2048;  // every texture is resampled to at most this size

struct SceneUniforms {  // std140 mirror of ViewerScene (shaders/viewer_scene.glsl)
    float lights[8][8];
    float sky[4], horizon[4], ground[4];
    int32_t counts[4];
};
static_assert(sizeof(SceneUniforms) == 8 * 32 + 64);

struct ViewUniforms {  // std140 mirror of ViewerView (shaders/viewer_view.glsl)
    Mat4 view_proj, prev_view_proj, inv_view_proj;
    float eye[4];
    float size[4];
    float scale[4];
};
static_assert(sizeof(ViewUniforms) == 240);

struct DrawPush {  // mirror of ViewerDraw
    Mat4 model;
    float normal_matrix[3][4];
    int32_t material;
    int32_t pad[3];
};
static_assert(sizeof(DrawPush) == 128);

Mat4 crop(const Mat4& proj, const ViewSpec& v, bool jitter) {
    return fovea::vk::crop_projection(
        proj, v.crop, jitter ? v.jitter_px : std::array<float, 2>{0.f, 0.f}, v.extent);
}

}  // namespace

Camera camera_for(const SceneFile& scene, double t) {
    const CameraKey k = scene.camera_at(t);
    Camera c;
    c.eye = k.position;
    c.view = look_at(k.position, k.target);
    constexpr float kRad = 0.017453292519943295f;
    const float tan_h = std::tan(scene.fov_h_deg * 0.5f * kRad);
    const float tan_v = std::tan(scene.fov_v_deg * 0.5f * kRad);
    c.projection = perspective(2.f * std::atan(tan_v), tan_h / tan_v, scene.near_z, scene.far_z);
    return c;
}

struct Renderer::Impl {
    const Gpu& gpu;
    Submitter submit;
    Buffer vertices, indices, materials, scene_ubo, view_ubo;
    Image srgb_array, linear_array;
    Sampler sampler;
    DescriptorPool pool;
    SetLayout view_layout;
    VkDescriptorSet view_set = VK_NULL_HANDLE;
    PipelineLayout layout;
    RenderPass forward_pass, gbuffer_pass;
    Pipeline forward_cull, forward_double, forward_sky;
    Pipeline gbuffer_cull, gbuffer_double, gbuffer_sky;
    std::vector<Primitive> draws;
    uint32_t view_stride = 0, slot = 0;
    // By colour views (the forward pass's fourth is null): a depth image and framebuffer.
    std::map<std::array<VkImageView, 4>, std::pair<Image, Framebuffer>> targets;
    QueryPool queries;
    uint32_t queries_used = 0;
    double timestamp_ms = 0.0;

    explicit Impl(const Gpu& g) : gpu(g), submit(g) {}

    template <typename T>
    Buffer upload_buffer(const std::vector<T>& data, VkBufferUsageFlags usage) {
        const VkDeviceSize bytes = std::max<VkDeviceSize>(data.size() * sizeof(T), 16);
        Buffer staging = make_buffer(gpu, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true);
        std::memcpy(staging.mapped, data.data(), data.size() * sizeof(T));
        Buffer dst = make_buffer(gpu, bytes, usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, false);
        submit.run([&](VkCommandBuffer cmd) {
            const VkBufferCopy region{0, 0, bytes};
            vkCmdCopyBuffer(cmd, staging.get(), dst.get(), 1, &region);
        });
        return dst;
    }

    // Every texture of one colour space as a layer of one mipmapped array of size x size: the
    // source is blitted (bilinear) to the layer size, then the mip chain is blitted down from it.
    Image texture_array(const std::vector<const TextureData*>& textures, VkFormat format,
                        uint32_t size) {
        const uint32_t layers = std::max<uint32_t>(1, uint32_t(textures.size()));
        const uint32_t mips = uint32_t(std::floor(std::log2(double(size)))) + 1;
        Image arr;
        arr.extent = {size, size};
        arr.format = format;
        arr.mips = mips;
        VkImageCreateInfo ici{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
        ici.imageType = VK_IMAGE_TYPE_2D;
        ici.format = format;
        ici.extent = {size, size, 1};
        ici.mipLevels = mips;
        ici.arrayLayers = layers;
        ici.samples = VK_SAMPLE_COUNT_1_BIT;
        ici.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                    VK_IMAGE_USAGE_TRANSFER_DST_BIT;
        VkImage raw = VK_NULL_HANDLE;
        GLTFV_CHECK(vkCreateImage(gpu.device, &ici, nullptr, &raw));
        arr.image = ImageHandle(gpu.device, raw);
        VkMemoryRequirements req;
        vkGetImageMemoryRequirements(gpu.device, raw, &req);
        VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        mai.allocationSize = req.size;
        mai.memoryTypeIndex =
            gpu.memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
        VkDeviceMemory mem = VK_NULL_HANDLE;
        GLTFV_CHECK(vkAllocateMemory(gpu.device, &mai, nullptr, &mem));
        arr.memory = Memory(gpu.device, mem);
        GLTFV_CHECK(vkBindImageMemory(gpu.device, raw, mem, 0));
        VkImageViewCreateInfo vci{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        vci.image = raw;
        vci.viewType = VK_IMAGE_VIEW_TYPE_2D_ARRAY;
        vci.format = format;
        vci.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, mips, 0, layers};
        VkImageView view = VK_NULL_HANDLE;
        GLTFV_CHECK(vkCreateImageView(gpu.device, &vci, nullptr, &view));
        arr.view = ImageView(gpu.device, view);

        const auto barrier = [&](VkCommandBuffer cmd, uint32_t layer, uint32_t mip, uint32_t n,
                                 VkImageLayout from, VkImageLayout to) {
            VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
            b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
            b.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT |
                              VK_ACCESS_SHADER_READ_BIT;
            b.oldLayout = from;
            b.newLayout = to;
            b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
            b.image = raw;
            b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, mip, n, layer, 1};
            vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_HOST_BIT,
                                 VK_PIPELINE_STAGE_TRANSFER_BIT |
                                     VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT |
                                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                                 0, 0, nullptr, 0, nullptr, 1, &b);
        };
        static const TextureData kWhite{1, 1, {255, 255, 255, 255}, false};
        for (uint32_t layer = 0; layer < layers; ++layer) {
            const TextureData& t = textures.empty() ? kWhite : *textures[layer];
            Image src =
                make_image(gpu, {t.width, t.height}, format,
                           VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT);
            Buffer staging =
                make_buffer(gpu, t.rgba.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true);
            std::memcpy(staging.mapped, t.rgba.data(), t.rgba.size());
            submit.run([&](VkCommandBuffer cmd) {
                image_barrier(cmd, src.get(), VK_IMAGE_LAYOUT_UNDEFINED,
                              VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
                VkBufferImageCopy region{};
                region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
                region.imageExtent = {t.width, t.height, 1};
                vkCmdCopyBufferToImage(cmd, staging.get(), src.get(),
                                       VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
                image_barrier(cmd, src.get(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                              VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
                barrier(cmd, layer, 0, mips, VK_IMAGE_LAYOUT_UNDEFINED,
                        VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
                VkImageBlit blit{};
                blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
                blit.srcOffsets[1] = {int32_t(t.width), int32_t(t.height), 1};
                blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, layer, 1};
                blit.dstOffsets[1] = {int32_t(size), int32_t(size), 1};
                vkCmdBlitImage(cmd, src.get(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, raw,
                               VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit, VK_FILTER_LINEAR);
                for (uint32_t m = 1; m < mips; ++m) {  // the mip chain, generated at load
                    barrier(cmd, layer, m - 1, 1, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                            VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
                    const int32_t from = int32_t(std::max(1u, size >> (m - 1)));
                    const int32_t to = int32_t(std::max(1u, size >> m));
                    VkImageBlit b{};
                    b.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, m - 1, layer, 1};
                    b.srcOffsets[1] = {from, from, 1};
                    b.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, m, layer, 1};
                    b.dstOffsets[1] = {to, to, 1};
                    vkCmdBlitImage(cmd, raw, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, raw,
                                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &b, VK_FILTER_LINEAR);
                    barrier(cmd, layer, m - 1, 1, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                            VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
                }
                barrier(cmd, layer, mips - 1, 1, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                        VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
            });
        }
        return arr;
    }

    Pipeline make_pipeline(std::span<const uint32_t> vert, std::span<const uint32_t> frag,
                           VkRenderPass pass, uint32_t color_count, VkCullModeFlags cull,
                           bool mesh) {
        ShaderModule vm = make_shader(gpu.device, vert), fm = make_shader(gpu.device, frag);
        VkPipelineShaderStageCreateInfo stages[2] = {
            {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO},
            {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO}};
        stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
        stages[0].module = vm.get();
        stages[0].pName = "main";
        stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
        stages[1].module = fm.get();
        stages[1].pName = "main";
        const VkVertexInputBindingDescription binding{0, sizeof(Vertex),
                                                      VK_VERTEX_INPUT_RATE_VERTEX};
        const VkVertexInputAttributeDescription attrs[4] = {
            {0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, position)},
            {1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, normal)},
            {2, 0, VK_FORMAT_R32G32B32A32_SFLOAT, offsetof(Vertex, tangent)},
            {3, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(Vertex, uv)}};
        VkPipelineVertexInputStateCreateInfo vin{
            VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
        if (mesh) {
            vin.vertexBindingDescriptionCount = 1;
            vin.pVertexBindingDescriptions = &binding;
            vin.vertexAttributeDescriptionCount = 4;
            vin.pVertexAttributeDescriptions = attrs;
        }
        VkPipelineInputAssemblyStateCreateInfo ia{
            VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
        ia.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
        VkPipelineViewportStateCreateInfo vps{
            VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
        vps.viewportCount = vps.scissorCount = 1;
        VkPipelineRasterizationStateCreateInfo rs{
            VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
        rs.polygonMode = VK_POLYGON_MODE_FILL;
        rs.cullMode = cull;
        rs.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
        rs.lineWidth = 1.f;
        VkPipelineMultisampleStateCreateInfo ms{
            VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
        ms.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
        VkPipelineDepthStencilStateCreateInfo ds{
            VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
        ds.depthTestEnable = VK_TRUE;
        ds.depthWriteEnable = mesh ? VK_TRUE : VK_FALSE;
        ds.depthCompareOp = VK_COMPARE_OP_LESS_OR_EQUAL;  // the sky: where the far plane is left
        std::vector<VkPipelineColorBlendAttachmentState> blend(color_count);
        for (auto& b : blend) b.colorWriteMask = 0xf;
        VkPipelineColorBlendStateCreateInfo cb{
            VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
        cb.attachmentCount = color_count;
        cb.pAttachments = blend.data();
        const VkDynamicState dyn[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
        VkPipelineDynamicStateCreateInfo dy{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
        dy.dynamicStateCount = 2;
        dy.pDynamicStates = dyn;
        VkGraphicsPipelineCreateInfo gpi{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
        gpi.stageCount = 2;
        gpi.pStages = stages;
        gpi.pVertexInputState = &vin;
        gpi.pInputAssemblyState = &ia;
        gpi.pViewportState = &vps;
        gpi.pRasterizationState = &rs;
        gpi.pMultisampleState = &ms;
        gpi.pDepthStencilState = &ds;
        gpi.pColorBlendState = &cb;
        gpi.pDynamicState = &dy;
        gpi.layout = layout.get();
        gpi.renderPass = pass;
        VkPipeline p = VK_NULL_HANDLE;
        GLTFV_CHECK(vkCreateGraphicsPipelines(gpu.device, VK_NULL_HANDLE, 1, &gpi, nullptr, &p));
        return Pipeline(gpu.device, p);
    }

    // Colour attachments in the module's GENERAL layout, fully written (geometry, then the sky
    // where the far plane is left); the depth attachment is the viewer's own.
    RenderPass make_pass(std::span<const VkFormat> colors) {
        std::vector<VkAttachmentDescription> att;
        std::vector<VkAttachmentReference> refs;
        for (VkFormat f : colors) {
            VkAttachmentDescription a{};
            a.format = f;
            a.samples = VK_SAMPLE_COUNT_1_BIT;
            a.loadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
            a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
            a.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
            a.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
            a.initialLayout = a.finalLayout = VK_IMAGE_LAYOUT_GENERAL;
            refs.push_back({uint32_t(att.size()), VK_IMAGE_LAYOUT_GENERAL});
            att.push_back(a);
        }
        VkAttachmentDescription d{};
        d.format = VK_FORMAT_D32_SFLOAT;
        d.samples = VK_SAMPLE_COUNT_1_BIT;
        d.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        d.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
        d.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
        d.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
        d.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
        d.finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
        const VkAttachmentReference dref{uint32_t(att.size()),
                                         VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
        att.push_back(d);
        VkSubpassDescription sub{};
        sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
        sub.colorAttachmentCount = uint32_t(refs.size());
        sub.pColorAttachments = refs.data();
        sub.pDepthStencilAttachment = &dref;
        // The module's compute passes read and write these images before (last frame) and
        // after (this frame); its record() orders the latter itself, the former is ours.
        constexpr VkPipelineStageFlags kOther =
            VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
        constexpr VkPipelineStageFlags kRaster = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                                                 VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |
                                                 VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
        constexpr VkAccessFlags kRasterAccess = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
                                                VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                                                VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
        const VkSubpassDependency deps[2] = {
            {VK_SUBPASS_EXTERNAL, 0, kOther | kRaster, kRaster,
             VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT |
                 kRasterAccess,
             kRasterAccess, 0},
            {0, VK_SUBPASS_EXTERNAL, kRaster, kOther | kRaster, kRasterAccess,
             VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT | kRasterAccess, 0}};
        VkRenderPassCreateInfo rpi{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
        rpi.attachmentCount = uint32_t(att.size());
        rpi.pAttachments = att.data();
        rpi.subpassCount = 1;
        rpi.pSubpasses = &sub;
        rpi.dependencyCount = 2;
        rpi.pDependencies = deps;
        VkRenderPass rp = VK_NULL_HANDLE;
        GLTFV_CHECK(vkCreateRenderPass(gpu.device, &rpi, nullptr, &rp));
        return RenderPass(gpu.device, rp);
    }

    // A depth attachment and framebuffer per set of colour views (targets are long-lived: the
    // module's own images), made on first use.
    VkFramebuffer framebuffer(VkRenderPass pass, std::array<VkImageView, 4> colors,
                              VkExtent2D extent) {
        auto it = targets.find(colors);
        if (it != targets.end()) return it->second.second.get();
        Image depth =
            make_image(gpu, extent, VK_FORMAT_D32_SFLOAT,
                       VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, 1, VK_IMAGE_ASPECT_DEPTH_BIT);
        std::vector<VkImageView> views;
        for (VkImageView v : colors)
            if (v) views.push_back(v);
        views.push_back(depth.view.get());
        VkFramebufferCreateInfo fci{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
        fci.renderPass = pass;
        fci.attachmentCount = uint32_t(views.size());
        fci.pAttachments = views.data();
        fci.width = extent.width;
        fci.height = extent.height;
        fci.layers = 1;
        VkFramebuffer fb = VK_NULL_HANDLE;
        GLTFV_CHECK(vkCreateFramebuffer(gpu.device, &fci, nullptr, &fb));
        auto& entry = targets[colors];
        entry.first = std::move(depth);
        entry.second = Framebuffer(gpu.device, fb);
        return fb;
    }

    uint32_t write_view(const Camera& cam, const Camera& prev, const ViewSpec& v) {
        if (slot >= kMaxViews) throw std::runtime_error("more than 8 views in one frame");
        ViewUniforms u{};
        u.view_proj = multiply(crop(cam.projection, v, true), cam.view);
        u.prev_view_proj = multiply(crop(prev.projection, v, false), prev.view);
        u.inv_view_proj = inverse(u.view_proj);
        u.eye[0] = cam.eye[0];
        u.eye[1] = cam.eye[1];
        u.eye[2] = cam.eye[2];
        u.size[0] = float(v.extent.width);
        u.size[1] = float(v.extent.height);
        u.size[2] = 1.f / u.size[0];
        u.size[3] = 1.f / u.size[1];
        u.scale[0] = v.output_px_per_view_px;
        const uint32_t offset = slot++ * view_stride;
        std::memcpy(static_cast<char*>(view_ubo.mapped) + offset, &u, sizeof(u));
        return offset;
    }

    void draw_scene(VkCommandBuffer cmd, VkPipeline cull_back, VkPipeline two_sided) {
        const VkDeviceSize zero = 0;
        vkCmdBindVertexBuffers(cmd, 0, 1, vertices.buffer.ptr(), &zero);
        vkCmdBindIndexBuffer(cmd, indices.get(), 0, VK_INDEX_TYPE_UINT32);
        VkPipeline bound = VK_NULL_HANDLE;
        for (const Primitive& p : draws) {
            const VkPipeline want = p.double_sided ? two_sided : cull_back;
            if (want != bound) {
                vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, want);
                bound = want;
            }
            DrawPush push{};
            push.model = p.world;
            const Mat4 nm = transpose(inverse(p.world));
            for (int c = 0; c < 3; ++c)
                for (int r = 0; r < 3; ++r) push.normal_matrix[c][r] = nm[size_t(c * 4 + r)];
            push.normal_matrix[0][3] = determinant3(p.world) < 0.f ? -1.f : 1.f;
            push.material = int32_t(p.material);
            vkCmdPushConstants(cmd, layout.get(),
                               VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                               sizeof(push), &push);
            vkCmdDrawIndexed(cmd, p.index_count, 1, p.first_index, 0, 0);
        }
    }
};

Renderer::Renderer(const Gpu& gpu, const SceneFile& scene, const CpuScene& content)
    : impl_(std::make_unique<Impl>(gpu)) {
    Impl& m = *impl_;
    m.draws = content.primitives;
    for (const Primitive& p : m.draws) triangles_ += p.index_count / 3;
    m.vertices = m.upload_buffer(content.vertices, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
    m.indices = m.upload_buffer(content.indices, VK_BUFFER_USAGE_INDEX_BUFFER_BIT);

    // Textures: base colour and emissive in an sRGB array, the others linear; each material's
    // texture index becomes the layer in its array.
    std::vector<const TextureData*> srgb, linear;
    std::vector<int32_t> layer_of(content.textures.size(), -1);
    uint32_t size = 1;
    for (size_t i = 0; i < content.textures.size(); ++i) {
        const TextureData& t = content.textures[i];
        auto& list = t.srgb ? srgb : linear;
        layer_of[i] = int32_t(list.size());
        list.push_back(&t);
        size = std::max({size, t.width, t.height});
    }
    size = std::min(size, kMaxTexture);
    std::vector<MaterialGpu> materials = content.materials;
    for (MaterialGpu& g : materials)
        for (int32_t* t :
             {&g.base_tex, &g.mr_tex, &g.normal_tex, &g.occlusion_tex, &g.emissive_tex})
            if (*t >= 0) *t = layer_of[size_t(*t)];
    m.materials = m.upload_buffer(materials, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    m.srgb_array = m.texture_array(srgb, VK_FORMAT_R8G8B8A8_SRGB, size);
    m.linear_array = m.texture_array(linear, VK_FORMAT_R8G8B8A8_UNORM, size);
    VkSamplerCreateInfo sci{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    sci.magFilter = sci.minFilter = VK_FILTER_LINEAR;
    sci.mipmapMode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
    sci.addressModeU = sci.addressModeV = sci.addressModeW = VK_SAMPLER_ADDRESS_MODE_REPEAT;
    sci.maxLod = VK_LOD_CLAMP_NONE;
    VkSampler smp = VK_NULL_HANDLE;
    GLTFV_CHECK(vkCreateSampler(gpu.device, &sci, nullptr, &smp));
    m.sampler = Sampler(gpu.device, smp);

    SceneUniforms su{};
    for (size_t i = 0; i < scene.lights.size() && i < 8; ++i) {
        const LightDesc& l = scene.lights[i];
        const Vec3 p = l.directional ? normalize(l.direction) : l.position;
        for (int k = 0; k < 3; ++k) {
            su.lights[i][k] = p[size_t(k)];
            su.lights[i][4 + k] = l.color[size_t(k)] * l.intensity;
        }
        su.lights[i][3] = l.directional ? 0.f : 1.f;
    }
    for (int k = 0; k < 3; ++k) {
        su.sky[k] = scene.sky[size_t(k)];
        su.horizon[k] = scene.horizon[size_t(k)];
        su.ground[k] = scene.ground[size_t(k)];
    }
    su.sky[3] = scene.env_intensity;
    su.counts[0] = int32_t(std::min<size_t>(scene.lights.size(), 8));
    su.counts[1] = int32_t(srgb.size() + linear.size());
    su.counts[2] = int32_t(size);
    m.scene_ubo = make_buffer(gpu, sizeof(su), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, true);
    std::memcpy(m.scene_ubo.mapped, &su, sizeof(su));

    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(gpu.physical, &props);
    const uint32_t align = uint32_t(props.limits.minUniformBufferOffsetAlignment);
    m.view_stride = (uint32_t(sizeof(ViewUniforms)) + align - 1) / align * align;
    m.view_ubo = make_buffer(gpu, VkDeviceSize{m.view_stride} * kMaxViews,
                             VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, true);

    // Set 0: the view (dynamic offset); set 1: the scene, also the module's host set, so its
    // stages include compute.
    const VkShaderStageFlags kRaster = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
    const VkShaderStageFlags kAll = kRaster | VK_SHADER_STAGE_COMPUTE_BIT;
    const VkDescriptorSetLayoutBinding vb{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC, 1, kRaster,
                                          nullptr};
    const VkDescriptorSetLayoutBinding sb[4] = {
        {0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, kAll, nullptr},
        {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, kAll, nullptr},
        {2, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, kAll, nullptr},
        {3, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, kAll, nullptr}};
    VkDescriptorSetLayoutCreateInfo li{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    li.bindingCount = 1;
    li.pBindings = &vb;
    VkDescriptorSetLayout raw = VK_NULL_HANDLE;
    GLTFV_CHECK(vkCreateDescriptorSetLayout(gpu.device, &li, nullptr, &raw));
    m.view_layout = SetLayout(gpu.device, raw);
    li.bindingCount = 4;
    li.pBindings = sb;
    GLTFV_CHECK(vkCreateDescriptorSetLayout(gpu.device, &li, nullptr, &raw));
    scene_layout_ = SetLayout(gpu.device, raw);
    const VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC, 1},
                                          {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1},
                                          {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1},
                                          {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 2}};
    VkDescriptorPoolCreateInfo pi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pi.maxSets = 2;
    pi.poolSizeCount = 4;
    pi.pPoolSizes = sizes;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    GLTFV_CHECK(vkCreateDescriptorPool(gpu.device, &pi, nullptr, &pool));
    m.pool = DescriptorPool(gpu.device, pool);
    const VkDescriptorSetLayout layouts[2] = {m.view_layout.get(), scene_layout_.get()};
    VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    ai.descriptorPool = pool;
    ai.descriptorSetCount = 2;
    ai.pSetLayouts = layouts;
    VkDescriptorSet sets[2];
    GLTFV_CHECK(vkAllocateDescriptorSets(gpu.device, &ai, sets));
    m.view_set = sets[0];
    scene_set_ = sets[1];
    const VkDescriptorBufferInfo view_info{m.view_ubo.get(), 0, sizeof(ViewUniforms)};
    const VkDescriptorBufferInfo scene_info{m.scene_ubo.get(), 0, sizeof(SceneUniforms)};
    const VkDescriptorBufferInfo mat_info{m.materials.get(), 0, VK_WHOLE_SIZE};
    const VkDescriptorImageInfo srgb_info{m.sampler.get(), m.srgb_array.view.get(),
                                          VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    const VkDescriptorImageInfo linear_info{m.sampler.get(), m.linear_array.view.get(),
                                            VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    VkWriteDescriptorSet w[5] = {};
    for (auto& x : w) {
        x.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
        x.descriptorCount = 1;
        x.dstSet = scene_set_;
    }
    w[0].dstSet = m.view_set;
    w[0].descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC;
    w[0].pBufferInfo = &view_info;
    w[1].dstBinding = 0;
    w[1].descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    w[1].pBufferInfo = &scene_info;
    w[2].dstBinding = 1;
    w[2].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    w[2].pBufferInfo = &mat_info;
    w[3].dstBinding = 2;
    w[3].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    w[3].pImageInfo = &srgb_info;
    w[4].dstBinding = 3;
    w[4].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    w[4].pImageInfo = &linear_info;
    vkUpdateDescriptorSets(gpu.device, 5, w, 0, nullptr);

    const VkPushConstantRange pcr{kRaster, 0, sizeof(DrawPush)};
    VkPipelineLayoutCreateInfo pl{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    pl.setLayoutCount = 2;
    pl.pSetLayouts = layouts;
    pl.pushConstantRangeCount = 1;
    pl.pPushConstantRanges = &pcr;
    VkPipelineLayout plo = VK_NULL_HANDLE;
    GLTFV_CHECK(vkCreatePipelineLayout(gpu.device, &pl, nullptr, &plo));
    m.layout = PipelineLayout(gpu.device, plo);

    const VkFormat forward[3] = {fovea::vk::kHostColorFormat, fovea::vk::kHostDepthFormat,
                                 fovea::vk::kHostMotionFormat};
    m.forward_pass = m.make_pass(forward);
    m.forward_cull = m.make_pipeline(viewer_mesh_vert, viewer_forward_frag, m.forward_pass.get(), 3,
                                     VK_CULL_MODE_BACK_BIT, true);
    m.forward_double = m.make_pipeline(viewer_mesh_vert, viewer_forward_frag, m.forward_pass.get(),
                                       3, VK_CULL_MODE_NONE, true);
    m.forward_sky = m.make_pipeline(viewer_sky_vert, viewer_sky_forward_frag, m.forward_pass.get(),
                                    3, VK_CULL_MODE_NONE, false);
    const auto& g = fovea::vk::kGBufferFormats;
    m.gbuffer_pass = m.make_pass(g);
    m.gbuffer_cull = m.make_pipeline(viewer_mesh_vert, viewer_gbuffer_frag, m.gbuffer_pass.get(),
                                     uint32_t(g.size()), VK_CULL_MODE_BACK_BIT, true);
    m.gbuffer_double = m.make_pipeline(viewer_mesh_vert, viewer_gbuffer_frag, m.gbuffer_pass.get(),
                                       uint32_t(g.size()), VK_CULL_MODE_NONE, true);
    m.gbuffer_sky = m.make_pipeline(viewer_sky_vert, viewer_sky_gbuffer_frag, m.gbuffer_pass.get(),
                                    uint32_t(g.size()), VK_CULL_MODE_NONE, false);
    if (props.limits.timestampComputeAndGraphics) {
        VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
        qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
        qi.queryCount = 2 * kMaxViews;
        VkQueryPool query_pool = VK_NULL_HANDLE;
        GLTFV_CHECK(vkCreateQueryPool(gpu.device, &qi, nullptr, &query_pool));
        m.queries = QueryPool(gpu.device, query_pool);
    }
}

Renderer::~Renderer() = default;

void Renderer::begin_frame() {
    Impl& m = *impl_;
    m.timestamp_ms = 0.0;
    if (m.queries.get() && m.queries_used > 0) {
        std::vector<uint64_t> ts(m.queries_used);
        if (vkGetQueryPoolResults(m.gpu.device, m.queries.get(), 0, m.queries_used,
                                  ts.size() * sizeof(uint64_t), ts.data(), sizeof(uint64_t),
                                  VK_QUERY_RESULT_64_BIT) == VK_SUCCESS) {
            VkPhysicalDeviceProperties props;
            vkGetPhysicalDeviceProperties(m.gpu.physical, &props);
            for (uint32_t i = 0; i + 1 < m.queries_used; i += 2)
                m.timestamp_ms += double(ts[i + 1] - ts[i]) * props.limits.timestampPeriod * 1e-6;
        }
    }
    m.slot = 0;
    m.queries_used = 0;
}

double Renderer::gpu_ms() const { return impl_->timestamp_ms; }

void Renderer::record_pass(VkCommandBuffer cmd, bool gbuffer, std::array<VkImageView, 4> colors,
                           VkExtent2D extent, const Camera& cam, const Camera& prev,
                           const ViewSpec& view) {
    Impl& m = *impl_;
    ViewSpec v = view;
    v.extent = extent;
    const uint32_t offset = m.write_view(cam, prev, v);
    const VkRenderPass pass = gbuffer ? m.gbuffer_pass.get() : m.forward_pass.get();
    const VkFramebuffer fb = m.framebuffer(pass, colors, extent);
    const uint32_t q = m.queries_used;
    if (m.queries.get() && q + 2 <= 2 * kMaxViews) {
        vkCmdResetQueryPool(cmd, m.queries.get(), q, 2);
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, m.queries.get(), q);
    }
    const uint32_t n_colors = gbuffer ? 4 : 3;
    VkClearValue clear[5] = {};
    clear[n_colors].depthStencil = {1.f, 0};
    VkRenderPassBeginInfo bi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    bi.renderPass = pass;
    bi.framebuffer = fb;
    bi.renderArea = {{0, 0}, extent};
    bi.clearValueCount = n_colors + 1;
    bi.pClearValues = clear;
    vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
    const VkViewport vp{0.f, 0.f, float(extent.width), float(extent.height), 0.f, 1.f};
    vkCmdSetViewport(cmd, 0, 1, &vp);
    const VkRect2D sc{{0, 0}, extent};
    vkCmdSetScissor(cmd, 0, 1, &sc);
    const VkDescriptorSet sets[2] = {m.view_set, scene_set_};
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, m.layout.get(), 0, 2, sets, 1,
                            &offset);
    if (gbuffer) {
        m.draw_scene(cmd, m.gbuffer_cull.get(), m.gbuffer_double.get());
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, m.gbuffer_sky.get());
    } else {
        m.draw_scene(cmd, m.forward_cull.get(), m.forward_double.get());
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, m.forward_sky.get());
    }
    vkCmdDraw(cmd, 3, 1, 0, 0);
    vkCmdEndRenderPass(cmd);
    if (m.queries.get() && q + 2 <= 2 * kMaxViews) {
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, m.queries.get(), q + 1);
        m.queries_used = q + 2;
    }
}

void Renderer::record_forward(VkCommandBuffer cmd, const fovea::vk::HostTargets& t,
                              const Camera& cam, const Camera& prev, const ViewSpec& view) {
    record_pass(cmd, false, {t.color.view, t.depth.view, t.motion.view, VK_NULL_HANDLE}, t.extent,
                cam, prev, view);
}

void Renderer::record_gbuffer(VkCommandBuffer cmd, const fovea::vk::GBufferRefs& g,
                              const Camera& cam, const Camera& prev, const ViewSpec& view) {
    using fovea::vk::GBufferImage;
    record_pass(cmd, true,
                {g[GBufferImage::kPosition].view, g[GBufferImage::kSurface].view,
                 g[GBufferImage::kDepth].view, g[GBufferImage::kMotion].view},
                g.extent, cam, prev, view);
}

const std::string& Renderer::shading_glsl() {
    static const std::string glsl = kViewerShadingGlsl;
    return glsl;
}

}  // namespace gltfv
