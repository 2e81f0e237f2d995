#include "fovea/vk/foveator.hpp"

#include <chrono>
#include <cmath>
#include <cstring>
#include <map>

#include "fovea/vk/check.hpp"
#include "frame_uniforms.hpp"
#include "gpu.hpp"
#include "method.hpp"
#include "module_context.hpp"
#include "post_pass.hpp"

namespace fovea::vk {

struct Foveator::Impl {
    const Device* device = nullptr;
    FoveatorConfig config;
    GBufferRefs gbuffer_refs;
    std::array<Image, kGBufferImageCount> gbuffer;
    Image shaded, rate, rate_tiles;
    std::array<Image, 2> post;
    Buffer uniforms, stats;
    VkDescriptorSetLayout frame_layout = VK_NULL_HANDLE;
    VkDescriptorPool frame_pool = VK_NULL_HANDLE;
    VkDescriptorSet frame_set = VK_NULL_HANDLE;
    VkQueryPool queries = VK_NULL_HANDLE;
    std::unique_ptr<ModuleContext> ctx;
    std::map<std::string, std::unique_ptr<Method>, std::less<>> methods;
    Method* method = nullptr;
    std::string method_name;
    std::vector<std::unique_ptr<PostPass>> post_chain;
    // Post passes keep history (TAA): each method owns its chain instance, so a host that
    // alternates methods frame by frame (fovea bench, demo) never blends one method's frame into
    // another's history. The active method's chain is `post_chain`; the others wait here.
    std::map<std::string, std::vector<std::unique_ptr<PostPass>>, std::less<>> parked_chains;
    const ImageRef* output = nullptr;
    FrameUniforms cpu_uniforms{};
    std::array<float, 64> host_params{};
    uint64_t frame_index = 0;
    ResolvedGaze gaze;
    bool warned_fallback = false;

    ~Impl() {
        if (!device) return;
        VkDevice d = device->device();
        vkDeviceWaitIdle(d);
        methods.clear();
        post_chain.clear();
        parked_chains.clear();
        if (queries) vkDestroyQueryPool(d, queries, nullptr);
        if (frame_pool) vkDestroyDescriptorPool(d, frame_pool, nullptr);
        if (frame_layout) vkDestroyDescriptorSetLayout(d, frame_layout, nullptr);
    }

    void create_frame_set() {
        VkDevice d = device->device();
        std::array<VkDescriptorSetLayoutBinding, 10> b{};
        for (uint32_t i = 0; i < b.size(); ++i) {
            b[i].binding = i;
            b[i].descriptorCount = 1;
            b[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
            b[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
        }
        b[0].descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
        b[9].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        VkDescriptorSetLayoutCreateInfo li{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
        li.bindingCount = static_cast<uint32_t>(b.size());
        li.pBindings = b.data();
        VK_CHECK(vkCreateDescriptorSetLayout(d, &li, nullptr, &frame_layout));
        const VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1},
                                              {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 8},
                                              {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1}};
        VkDescriptorPoolCreateInfo pi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        pi.maxSets = 1;
        pi.poolSizeCount = 3;
        pi.pPoolSizes = sizes;
        VK_CHECK(vkCreateDescriptorPool(d, &pi, nullptr, &frame_pool));
        VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
        ai.descriptorPool = frame_pool;
        ai.descriptorSetCount = 1;
        ai.pSetLayouts = &frame_layout;
        VK_CHECK(vkAllocateDescriptorSets(d, &ai, &frame_set));
        DescriptorWriter w(d, frame_set);
        w.uniform_buffer(0, uniforms);
        for (int i = 0; i < kGBufferImageCount; ++i)
            w.storage_image(static_cast<uint32_t>(1 + i), gbuffer[i].view());
        w.storage_image(7, shaded.view()).storage_image(8, rate.view()).storage_buffer(9, stats);
        w.commit();
    }

    Result<Method*> get_method(std::string_view name) {
        if (auto it = methods.find(name); it != methods.end()) return it->second.get();
        for (const MethodEntry& e : method_registry()) {
            if (name != e.name) continue;
            std::unique_ptr<Method> m = e.make();
            try {
                if (auto r = m->init(*ctx); !r)
                    return make_error("method '" + std::string(name) + "': " + r.error().message);
            } catch (const VkError& err) {
                return make_error("method '" + std::string(name) + "': " + err.what());
            }
            Method* raw = m.get();
            methods.emplace(std::string(name), std::move(m));
            return raw;
        }
        std::string known;
        for (const MethodEntry& e : method_registry()) known += std::string(" ") + e.name;
        return make_error("unknown method '" + std::string(name) + "'; known:" + known);
    }

    using PostChain = std::vector<std::unique_ptr<PostPass>>;

    Result<PostChain> make_post_chain(const std::vector<std::string>& names) {
        PostChain chain;
        if (!names.empty() && !post[0].get())  // ping-pong images only when a chain exists
            for (auto& p : post)
                p = Image(*device, config.extent, kColorFormat,
                          VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT);
        for (const std::string& n : names) {
            const PostPassEntry* found = nullptr;
            for (const PostPassEntry& e : post_pass_registry())
                if (n == e.name) found = &e;
            if (!found) return make_error("unknown post pass '" + n + "'");
            auto p = found->make();
            try {
                if (auto r = p->init(*ctx); !r)
                    return make_error("post pass '" + n + "': " + r.error().message);
            } catch (const VkError& err) {
                return make_error("post pass '" + n + "': " + err.what());
            }
            chain.push_back(std::move(p));
        }
        return chain;
    }

    Result<void> build_post_chain(const std::vector<std::string>& names) {
        auto chain = make_post_chain(names);
        if (!chain) return chain.error();
        post_chain = std::move(*chain);
        parked_chains.clear();  // built for the previous chain's names
        config.post_chain = names;
        return {};
    }

    void fill_uniforms(uint64_t index, const FrameInputs& in) {
        FrameUniforms& u = cpu_uniforms;
        const EyeDisplay& d = config.display;
        u.extent[0] = static_cast<float>(config.extent.width);
        u.extent[1] = static_cast<float>(config.extent.height);
        u.inv_extent[0] = 1.0f / u.extent[0];
        u.inv_extent[1] = 1.0f / u.extent[1];
        // The rate model works in display pixels; scale when the render extent differs.
        const float sx = u.extent[0] / static_cast<float>(d.width_px);
        const float sy = u.extent[1] / static_cast<float>(d.height_px);
        u.gaze_px[0] = gaze.x_px * sx;
        u.gaze_px[1] = gaze.y_px * sy;
        halton_jitter(index, config.jitter_length, u.jitter_px[0], u.jitter_px[1]);
        u.display_size_px[0] = u.extent[0];
        u.display_size_px[1] = u.extent[1];
        constexpr double kDegToRad = 0.017453292519943295;
        u.display_half_tan[0] = static_cast<float>(std::tan(d.fov_h_deg * 0.5 * kDegToRad));
        u.display_half_tan[1] = static_cast<float>(std::tan(d.fov_v_deg * 0.5 * kDegToRad));
        const AcuityParams& a = config.acuity;
        u.mar_slope = a.mar_slope;
        u.mar_omega0 = a.mar_omega0;
        u.foveal_radius_deg = a.foveal_radius_deg;
        u.transition_deg = a.transition_deg;
        u.margin_deg = gaze.margin_deg;
        u.max_rate = a.max_rate;
        u.tile_size = static_cast<float>(a.tile_size);
        u.acuity_reserved = 0.f;
        for (int i = 0; i < 3; ++i) u.camera_pos[i] = in.camera_pos[i];
        u.camera_pos[3] = in.radians_per_pixel;
        u.time[0] = static_cast<float>(in.time_s);
        u.time[1] = static_cast<float>(index);
        u.time[2] = 0.f;
        u.time[3] = 0.f;
        std::memcpy(u.host, host_params.data(), sizeof(u.host));
        std::memcpy(uniforms.data(), &u, sizeof(u));
    }

    ResolvedGaze resolve(const FrameInputs& in) {
        ResolvedGaze g = resolve_gaze(in.gaze, config.display, config.acuity);
        if (g.fell_back && !warned_fallback)
            device->log(LogLevel::kWarning,
                        "gaze is not finite (NaN/inf): foveating around the screen centre");
        warned_fallback = g.fell_back;
        return g;
    }
};

Foveator::Foveator(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Foveator::Foveator(Foveator&&) noexcept = default;
Foveator& Foveator::operator=(Foveator&&) noexcept = default;
Foveator::~Foveator() = default;

std::vector<std::string> Foveator::methods() {
    std::vector<std::string> out;
    for (const MethodEntry& e : method_registry()) out.emplace_back(e.name);
    return out;
}

std::vector<std::string> Foveator::post_passes() {
    std::vector<std::string> out;
    for (const PostPassEntry& e : post_pass_registry()) out.emplace_back(e.name);
    return out;
}

Result<Foveator> Foveator::create(const Device& device, FoveatorConfig config) {
    if (config.extent.width == 0 || config.extent.height == 0)
        return make_error("Foveator: extent must be at least 1x1");
    if (config.acuity.tile_size == 0 || config.acuity.tile_size % 4 != 0)
        return make_error("Foveator: acuity.tile_size must be a positive multiple of 4");
    if (config.display.width_px == 0 || config.display.height_px == 0)
        return make_error("Foveator: display size must be at least 1x1");
    if (!(config.display.fov_h_deg > 0.f && config.display.fov_h_deg < 180.f &&
          config.display.fov_v_deg > 0.f && config.display.fov_v_deg < 180.f))
        return make_error("Foveator: display field of view must be in (0, 180) degrees");
    if (config.shading_glsl.find("fovea_shade") == std::string::npos)
        return make_error("Foveator: shading_glsl must define vec3 fovea_shade(FoveaGSample, "
                          "FoveaFootprint)");
    try {
        auto impl = std::make_unique<Impl>();
        impl->device = &device;
        impl->config = std::move(config);
        Impl& m = *impl;
        const VkExtent2D ext = m.config.extent;
        for (int i = 0; i < kGBufferImageCount; ++i) {
            m.gbuffer[i] = Image(device, ext, kGBufferFormats[i], kGBufferUsage);
            m.gbuffer_refs.images[i] = m.gbuffer[i].ref();
        }
        m.gbuffer_refs.extent = ext;
        const VkImageUsageFlags out_usage =
            VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
        m.shaded = Image(device, ext, kColorFormat, out_usage);
        m.rate = Image(device, ext, kRateFormat, out_usage);
        const uint32_t t = m.config.acuity.tile_size;
        m.rate_tiles = Image(device, {div_up(ext.width, t), div_up(ext.height, t)},
                             VK_FORMAT_R8_UINT, VK_IMAGE_USAGE_STORAGE_BIT);
        m.uniforms = Buffer(device, sizeof(FrameUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                            true);
        m.stats = Buffer(device, sizeof(FrameStatsGpu), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true);
        m.create_frame_set();
        if (device.properties().limits.timestampComputeAndGraphics) {
            VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
            qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
            qi.queryCount = 3;
            VK_CHECK(vkCreateQueryPool(device.device(), &qi, nullptr, &m.queries));
        }
        m.ctx = std::unique_ptr<ModuleContext>(new ModuleContext{
            device, m.config, ext, m.frame_layout, m.gbuffer_refs, m.rate_tiles.ref(), m.stats});
        auto method = m.get_method(m.config.method);
        if (!method) return method.error();
        m.method = *method;
        m.method_name = m.config.method;
        if (auto r = m.build_post_chain(m.config.post_chain); !r) return r.error();
        m.output = &m.shaded.ref();
        return Foveator(std::move(impl));
    } catch (const VkError& e) {
        return make_error(std::string("Foveator: ") + e.what(), static_cast<int>(e.result()));
    }
}

Result<void> Foveator::set_method(std::string_view name) {
    auto m = impl_->get_method(name);
    if (!m) return m.error();
    Impl& i = *impl_;
    if (name != i.method_name) {  // park this method's post chain, take (or build) the new one's
        Impl::PostChain next;
        if (auto own = i.parked_chains.find(name); own != i.parked_chains.end()) {
            next = std::move(own->second);
            i.parked_chains.erase(own);
        } else {
            auto built = i.make_post_chain(i.config.post_chain);
            if (!built) return built.error();
            next = std::move(*built);
        }
        i.parked_chains[i.method_name] = std::move(i.post_chain);
        i.post_chain = std::move(next);
    }
    impl_->method = *m;
    impl_->method_name = std::string(name);
    impl_->config.method = impl_->method_name;
    return {};
}

const std::string& Foveator::method() const { return impl_->method_name; }
Result<void> Foveator::set_post_chain(const std::vector<std::string>& names) {
    return impl_->build_post_chain(names);
}
const FoveatorConfig& Foveator::config() const { return impl_->config; }
const GBufferRefs& Foveator::gbuffer() const { return impl_->gbuffer_refs; }
const ImageRef& Foveator::output() const { return *impl_->output; }
const ImageRef& Foveator::shaded() const { return impl_->shaded.ref(); }
const ImageRef& Foveator::rate() const { return impl_->rate.ref(); }
const ImageRef& Foveator::rate_tiles() const { return impl_->rate_tiles.ref(); }

std::vector<ViewRequest> Foveator::views(uint64_t frame_index, const FrameInputs& inputs) {
    return impl_->method->views(frame_index, impl_->resolve(inputs));
}
bool Foveator::needs_full_gbuffer() const { return impl_->method->uses_full_gbuffer(); }

std::array<float, 2> Foveator::jitter(uint64_t frame_index) const {
    std::array<float, 2> j{};
    halton_jitter(frame_index, impl_->config.jitter_length, j[0], j[1]);
    return j;
}

void Foveator::set_host_params(const std::array<float, 64>& params) {
    impl_->host_params = params;
}

void Foveator::record(VkCommandBuffer cmd, uint64_t frame_index, const FrameInputs& inputs) {
    Impl& m = *impl_;
    m.frame_index = frame_index;
    m.gaze = m.resolve(inputs);
    m.fill_uniforms(frame_index, inputs);
    if (m.queries) vkCmdResetQueryPool(cmd, m.queries, 0, 3);
    // Host G-buffer writes (compute or transfer) -> our reads; zero the counters.
    VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    mb.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
    mb.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                         VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0,
                         1, &mb, 0, nullptr, 0, nullptr);
    vkCmdFillBuffer(cmd, m.stats.get(), 0, VK_WHOLE_SIZE, 0);
    compute_barrier(cmd);
    if (m.queries)
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, m.queries, 0);
    const MethodFrame mf{cmd,         m.frame_set,         frame_index, m.cpu_uniforms,
                         inputs,      m.gaze,              m.shaded.ref(), m.rate.ref()};
    m.method->record(mf);
    compute_barrier(cmd);
    if (m.queries)
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, m.queries, 1);
    const ImageRef* in = &m.shaded.ref();
    for (size_t i = 0; i < m.post_chain.size(); ++i) {
        const ImageRef* out = &m.post[i % 2].ref();
        const PostFrame pf{cmd,
                           m.frame_set,
                           frame_index,
                           m.cpu_uniforms,
                           inputs,
                           m.gaze,
                           *in,
                           *out,
                           m.gbuffer_refs[GBufferImage::kDepth],
                           m.gbuffer_refs[GBufferImage::kMotion],
                           m.rate.ref(),
                           {m.cpu_uniforms.jitter_px[0], m.cpu_uniforms.jitter_px[1]}};
        m.post_chain[i]->record(pf);
        compute_barrier(cmd);
        in = out;
    }
    m.output = in;
    if (m.queries)
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, m.queries, 2);
    VkMemoryBarrier hb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    hb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
    hb.dstAccessMask = VK_ACCESS_HOST_READ_BIT | VK_ACCESS_MEMORY_READ_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                         VK_PIPELINE_STAGE_HOST_BIT | VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 1,
                         &hb, 0, nullptr, 0, nullptr);
}

FrameStats Foveator::stats() const {
    const Impl& m = *impl_;
    FrameStatsGpu g;
    std::memcpy(&g, m.stats.data(), sizeof(g));
    FrameStats s;
    s.frame_index = m.frame_index;
    s.shaded_samples = g.shaded_samples;
    s.edge_samples = g.edge_samples;
    for (int i = 0; i < 4; ++i) s.tiles[i] = g.tiles[i];
    s.skipped_tiles = g.tiles[3];
    s.reused_tiles = g.reused_tiles;
    s.background_tiles = g.background_tiles;
    s.flat_tiles = g.flat_tiles;
    s.no_detail_tiles = g.no_detail_tiles;
    s.shaded_fraction = static_cast<double>(g.shaded_samples) /
                        (static_cast<double>(m.config.extent.width) * m.config.extent.height);
    s.gaze = m.gaze;
    if (m.queries) {
        uint64_t ts[3] = {};
        if (vkGetQueryPoolResults(m.device->device(), m.queries, 0, 3, sizeof(ts), ts,
                                  sizeof(uint64_t), VK_QUERY_RESULT_64_BIT) == VK_SUCCESS) {
            const double period_ms = m.device->properties().limits.timestampPeriod * 1e-6;
            s.method_gpu_ms = static_cast<double>(ts[1] - ts[0]) * period_ms;
            s.post_gpu_ms = static_cast<double>(ts[2] - ts[1]) * period_ms;
        }
    }
    return s;
}

double Foveator::render_blocking(uint64_t frame_index, const FrameInputs& inputs,
                                 const std::function<void(VkCommandBuffer)>& before) {
    const auto t0 = std::chrono::steady_clock::now();
    impl_->device->submit_and_wait([&](VkCommandBuffer cmd) {
        if (before) before(cmd);
        record(cmd, frame_index, inputs);
    });
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
        .count();
}

}  // namespace fovea::vk
