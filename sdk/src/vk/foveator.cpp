#include "fovea/vk/foveator.hpp"

#include <cassert>
#include <chrono>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>
#include <set>

#include "fovea/vk/check.hpp"
#include "frame_uniforms.hpp"
#include "gpu.hpp"
#include "host_frame.hpp"
#include "method.hpp"
#include "module_context.hpp"
#include "post_pass.hpp"

namespace fovea::vk {
namespace {
constexpr uint32_t kQueriesPerSlot = 3;  // frame start, method done, post chain done
constexpr uint32_t kMaxHostViews = 4;    // forward layers: at most this many views a frame

const char* path_name(IntegrationPath p) {
    switch (p) {
        case IntegrationPath::kDeferred: return "deferred";
        case IntegrationPath::kForwardLayers: return "forward layers";
        case IntegrationPath::kRateImage: return "rate image";
        case IntegrationPath::kPostOnly: return "post only";
    }
    return "?";
}
}  // namespace

std::unique_ptr<Method> make_host_rendered_method(bool rate_image);

struct Foveator::Impl {
    const Device* device = nullptr;
    FoveatorConfig config;
    GBufferRefs gbuffer_refs;                       // what gbuffer() hands out (path 1)
    std::array<Image, kGBufferImageCount> gbuffer;  // 1x1 placeholders on paths 2-4
    Image shaded, rate, rate_tiles;                 // shaded: 1x1 on paths 3 and 4
    // Paths 3 and 4: the host's full view. Path 2: full-resolution depth and motion the layers
    // write for the post chain (colour unused).
    HostTargetImages host_targets;
    HostTargets host_targets_refs;  // what host_targets() hands out: empty except paths 3, 4
    HostIngest ingest;              // paths 2-4: the host's own images into the targets
    std::vector<ViewRequest> requested_views;  // path 2: of the last views() call
    std::optional<VrsAttachment> vrs;          // path 3, RateImageKind::kShadingRate
    std::optional<DensityMap> density_map;     // path 3, RateImageKind::kDensityMap
    ImageRef no_image;
    VkDescriptorSet host_set = VK_NULL_HANDLE;  // FrameInputs::host_set of the frame recording
    std::array<Image, 2> post;
    // What the CPU writes or reads per frame, one per frame in flight (frame index % count).
    struct Slot {
        Buffer uniforms, stats;
        VkDescriptorSet frame_set = VK_NULL_HANDLE;  // freed with frame_pool
        uint64_t frame_index = UINT64_MAX;           // recorded into this slot last
        ResolvedGaze gaze;
        uint64_t host_samples = 0;  // samples the host rendered itself (added to the counters)
    };
    std::vector<Slot> slots;
    UniqueDescriptorSetLayout frame_layout;
    UniqueDescriptorPool frame_pool;
    UniqueQueryPool queries;  // kQueriesPerSlot timestamps per slot
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
    uint64_t frame_index = 0;  // of the last record()
    ResolvedGaze gaze;
    std::optional<GazeResolver> gaze_resolver;  // holds the last valid gaze through blinks
    bool warned_fallback = false;
    uint64_t views_frame = UINT64_MAX;  // frame index of the last views() call
    std::set<std::string, std::less<>> warned_no_views, warned_ingest;

    // Members go in reverse order once the GPU is idle: post chains, methods, then the frame set
    // and the images and buffers they read.
    ~Impl() {
        if (device) device->wait_idle();
    }

    void create_frame_set() {
        VkDevice d = device->device();
        // 0 uniforms, 1..kGBufferImageCount the G-buffer, then colour out, S_t out, stats.
        constexpr uint32_t kColorOut = 1 + kGBufferImageCount, kRateOut = kColorOut + 1,
                           kStats = kRateOut + 1;
        std::array<VkDescriptorSetLayoutBinding, kStats + 1> b{};
        for (uint32_t i = 0; i < b.size(); ++i) {
            b[i].binding = i;
            b[i].descriptorCount = 1;
            b[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
            b[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
        }
        b[0].descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
        b[kStats].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        VkDescriptorSetLayoutCreateInfo li{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
        li.bindingCount = static_cast<uint32_t>(b.size());
        li.pBindings = b.data();
        frame_layout = create_handle<UniqueDescriptorSetLayout>(d, vkCreateDescriptorSetLayout, li);
        const uint32_t n = static_cast<uint32_t>(slots.size());
        const VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, n},
                                              {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, (kStats - 1) * n},
                                              {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, n}};
        VkDescriptorPoolCreateInfo pi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        pi.maxSets = n;
        pi.poolSizeCount = 3;
        pi.pPoolSizes = sizes;
        frame_pool = create_handle<UniqueDescriptorPool>(d, vkCreateDescriptorPool, pi);
        const VkDescriptorSetLayout layout = frame_layout.get();
        for (Slot& slot : slots) {
            VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
            ai.descriptorPool = frame_pool.get();
            ai.descriptorSetCount = 1;
            ai.pSetLayouts = &layout;
            VK_CHECK(vkAllocateDescriptorSets(d, &ai, &slot.frame_set));
            DescriptorWriter w(d, slot.frame_set);
            w.uniform_buffer(0, slot.uniforms);
            for (int i = 0; i < kGBufferImageCount; ++i)
                w.storage_image(static_cast<uint32_t>(1 + i), gbuffer[i].view());
            w.storage_image(kColorOut, shaded.view())
                .storage_image(kRateOut, rate.view())
                .storage_buffer(kStats, slot.stats);
            w.commit();
        }
    }

    // What the post chain starts from and reads: the method's output and the G-buffer (path 1),
    // the composite and the layers' depth and motion (path 2), the host's frame (paths 3, 4).
    const ImageRef& shaded_image() const {
        return host_rendered() ? host_targets.refs().color : shaded.ref();
    }
    const ImageRef& post_depth() const {
        return config.path == IntegrationPath::kDeferred ? gbuffer_refs[GBufferImage::kDepth]
                                                         : host_targets.refs().depth;
    }
    const ImageRef& post_motion() const {
        return config.path == IntegrationPath::kDeferred ? gbuffer_refs[GBufferImage::kMotion]
                                                         : host_targets.refs().motion;
    }

    // The host's own images into the module's targets (FrameInputs::host_images/view_images).
    void ingest_host_images(VkCommandBuffer cmd, uint64_t index, const FrameInputs& in) {
        if (config.path == IntegrationPath::kDeferred) return;
        ingest.begin_frame(static_cast<uint32_t>(index % slots.size()));
        const auto warn = [&](const std::string& what) {
            if (warned_ingest.insert(what).second) device->log(LogLevel::kWarning, what);
        };
        if (host_rendered() && in.host_images &&
            !ingest.record(cmd, *in.host_images, host_targets.refs()))
            warn("FrameInputs::host_images: extent must be " + std::to_string(config.extent.width) +
                 "x" + std::to_string(config.extent.height) +
                 " with colour and depth views; the targets were read instead");
        if (config.path != IntegrationPath::kForwardLayers) return;
        if (!in.view_images.empty() && in.view_images.size() != requested_views.size())
            warn("FrameInputs::view_images holds " + std::to_string(in.view_images.size()) +
                 " views, views() asked for " + std::to_string(requested_views.size()) +
                 "; the extra or missing ones were read from ViewRequest::targets");
        for (size_t i = 0; i < in.view_images.size() && i < requested_views.size(); ++i)
            if (!ingest.record(cmd, in.view_images[i], requested_views[i].targets))
                warn("FrameInputs::view_images[" + std::to_string(i) +
                     "]: extent must equal its ViewRequest::extent, with colour and depth views");
    }

    Slot& slot_of(uint64_t index) { return slots[index % slots.size()]; }
    const Slot& slot_of(uint64_t index) const { return slots[index % slots.size()]; }

    bool host_rendered() const {
        return config.path == IntegrationPath::kRateImage ||
               config.path == IntegrationPath::kPostOnly;
    }

    Result<Method*> get_method(std::string_view name) {
        if (auto it = methods.find(name); it != methods.end()) return it->second.get();
        if (host_rendered()) {
            std::unique_ptr<Method> m =
                make_host_rendered_method(config.path == IntegrationPath::kRateImage);
            if (auto r = m->init(*ctx); !r) return r.error();
            Method* raw = m.get();
            methods.emplace(std::string(name), std::move(m));
            return raw;
        }
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
        // The chain ping-pongs: the last pass writes post[(n - 1) % 2].
        output = post_chain.empty() ? &shaded_image() : &post[(post_chain.size() - 1) % 2].ref();
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
        std::memcpy(slot_of(index).uniforms.data(), &u, sizeof(u));
    }

    ResolvedGaze resolve(const FrameInputs& in) {
        ResolvedGaze g = gaze_resolver->resolve(in.gaze, in.time_s);
        if (g.fell_back && !warned_fallback)
            device->log(LogLevel::kWarning,
                        "gaze is not finite (NaN/inf) and no valid gaze came before: foveating "
                        "around the screen centre");
        warned_fallback = g.fell_back;
        return g;
    }

    // A method that renders from views() shows stale images when the host skipped them.
    void check_views_requested(uint64_t index) {
        if (!method->has_views() || views_frame == index) return;
        if (!warned_no_views.insert(method_name).second) return;
        device->log(LogLevel::kWarning,
                    "Foveator::record(frame " + std::to_string(index) + ") without views(" +
                        std::to_string(index) + "): method '" + method_name +
                        "' shades the views the host renders each frame (Foveator::views); "
                        "this frame shows whatever those images last held");
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
    if (config.frames_in_flight < 1 || config.frames_in_flight > kMaxFramesInFlight)
        return make_error("Foveator: frames_in_flight must be 1.." +
                          std::to_string(kMaxFramesInFlight));
    if (config.display.width_px == 0 || config.display.height_px == 0)
        return make_error("Foveator: display size must be at least 1x1");
    if (!(config.display.fov_h_deg > 0.f && config.display.fov_h_deg < 180.f &&
          config.display.fov_v_deg > 0.f && config.display.fov_v_deg < 180.f))
        return make_error("Foveator: display field of view must be in (0, 180) degrees");
    const IntegrationPath path = config.path;
    if (path == IntegrationPath::kDeferred &&
        config.shading_glsl.find("fovea_shade") == std::string::npos)
        return make_error(
            "Foveator: shading_glsl must define vec3 fovea_shade(FoveaGSample, "
            "FoveaFootprint)");
    if (config.shading_glsl.find("FOVEA_HOST_SET") != std::string::npos && !config.host_set_layout)
        return make_error(
            "Foveator: shading_glsl declares bindings in set FOVEA_HOST_SET but "
            "FoveatorConfig::host_set_layout is null");
    if (path == IntegrationPath::kForwardLayers) config.method = "layers";
    if (path == IntegrationPath::kRateImage || path == IntegrationPath::kPostOnly)
        config.method = "host";  // internal: the host rendered the frame
    try {
        auto impl = std::make_unique<Impl>();
        impl->device = &device;
        impl->config = std::move(config);
        Impl& m = *impl;
        m.gaze_resolver.emplace(m.config.display, m.config.acuity);
        const VkExtent2D ext = m.config.extent;
        // The frame set binds every G-buffer image; only path 1 reads them at full size.
        const bool deferred = path == IntegrationPath::kDeferred;
        const VkExtent2D gext = deferred ? ext : VkExtent2D{1, 1};
        for (int i = 0; i < kGBufferImageCount; ++i) {
            m.gbuffer[i] = Image(device, gext, kGBufferFormats[i], kGBufferUsage);
            if (deferred) m.gbuffer_refs.images[i] = m.gbuffer[i].ref();
        }
        if (deferred) m.gbuffer_refs.extent = ext;
        const VkImageUsageFlags out_usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
        m.shaded =
            Image(device, m.host_rendered() ? VkExtent2D{1, 1} : ext, kColorFormat, out_usage);
        m.rate = Image(device, ext, kRateFormat, out_usage);
        if (!deferred) {
            m.host_targets = HostTargetImages(device, ext);
            if (m.host_rendered()) m.host_targets_refs = m.host_targets.refs();
            m.ingest = HostIngest(device, m.config.frames_in_flight,
                                  path == IntegrationPath::kForwardLayers ? kMaxHostViews : 1);
        }
        if (path == IntegrationPath::kRateImage) {
            if (m.config.rate_image == RateImageKind::kShadingRate) {
                auto v = VrsAttachment::create(device, m.config.display);
                if (!v) return make_error("Foveator (rate-image path): " + v.error().message);
                m.vrs.emplace(std::move(*v));
            } else {
                auto d = DensityMap::create(device, m.config.display);
                if (!d) return make_error("Foveator (rate-image path): " + d.error().message);
                m.density_map.emplace(std::move(*d));
            }
        }
        const uint32_t t = m.config.acuity.tile_size;
        m.rate_tiles = Image(device, {div_up(ext.width, t), div_up(ext.height, t)},
                             VK_FORMAT_R8_UINT, VK_IMAGE_USAGE_STORAGE_BIT);
        m.slots.resize(m.config.frames_in_flight);
        for (Impl::Slot& slot : m.slots) {
            slot.uniforms =
                Buffer(device, sizeof(FrameUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, true);
            slot.stats =
                Buffer(device, sizeof(FrameStatsGpu), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true);
        }
        m.create_frame_set();
        if (device.properties().limits.timestampComputeAndGraphics) {
            VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
            qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
            qi.queryCount = kQueriesPerSlot * m.config.frames_in_flight;
            m.queries = create_handle<UniqueQueryPool>(device.device(), vkCreateQueryPool, qi);
        }
        m.ctx = std::unique_ptr<ModuleContext>(
            new ModuleContext{device, m.config, ext, m.frame_layout.get(), m.gbuffer_refs,
                              m.rate_tiles.ref(), &m.host_set});
        auto method = m.get_method(m.config.method);
        if (!method) return method.error();
        m.method = *method;
        m.method_name = m.config.method;
        if (auto r = m.build_post_chain(m.config.post_chain); !r) return r.error();
        return Foveator(std::move(impl));
    } catch (const VkError& e) {
        return make_error(std::string("Foveator: ") + e.what(), static_cast<int>(e.result()));
    }
}

Result<void> Foveator::set_method(std::string_view name) {
    if (impl_->config.path != IntegrationPath::kDeferred)
        return make_error(std::string("Foveator::set_method: the ") +
                          path_name(impl_->config.path) +
                          " path has a fixed method; only the deferred path switches");
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
const ImageRef& Foveator::shaded() const { return impl_->shaded_image(); }
const HostTargets& Foveator::host_targets() const { return impl_->host_targets_refs; }

const ImageRef& Foveator::rate_image() const {
    const Impl& m = *impl_;
    return m.vrs ? m.vrs->image() : m.density_map ? m.density_map->image() : m.no_image;
}

uint32_t Foveator::rate_image_texel() const {
    const Impl& m = *impl_;
    return m.vrs ? m.vrs->texel_width() : m.density_map ? m.density_map->texel_size() : 0;
}

void Foveator::record_rate_image(VkCommandBuffer cmd, const FrameInputs& inputs) {
    Impl& m = *impl_;
    const ResolvedGaze g = m.resolve(inputs);
    if (m.vrs) m.vrs->record(cmd, m.config.acuity, g);
    if (m.density_map) m.density_map->record(cmd, m.config.acuity, g);
}
const ImageRef& Foveator::rate() const { return impl_->rate.ref(); }
const ImageRef& Foveator::rate_tiles() const { return impl_->rate_tiles.ref(); }

std::vector<ViewRequest> Foveator::views(uint64_t frame_index, const FrameInputs& inputs) {
    impl_->views_frame = frame_index;
    std::vector<ViewRequest> v = impl_->method->views(frame_index, impl_->resolve(inputs));
    impl_->requested_views = v;
    return v;
}
bool Foveator::needs_full_gbuffer() const { return impl_->method->uses_full_gbuffer(); }

std::array<float, 2> Foveator::jitter(uint64_t frame_index) const {
    std::array<float, 2> j{};
    halton_jitter(frame_index, impl_->config.jitter_length, j[0], j[1]);
    return j;
}

void Foveator::set_host_params(const std::array<float, 64>& params) { impl_->host_params = params; }

void Foveator::record(VkCommandBuffer cmd, uint64_t frame_index, const FrameInputs& inputs) {
    Impl& m = *impl_;
    m.frame_index = frame_index;
    m.gaze = m.resolve(inputs);
    m.check_views_requested(frame_index);
    m.fill_uniforms(frame_index, inputs);
    m.host_set = inputs.host_set;
    if (m.config.host_set_layout && !m.host_set && m.warned_ingest.insert("host_set").second)
        m.device->log(LogLevel::kWarning,
                      "FrameInputs::host_set is null while FoveatorConfig::host_set_layout is "
                      "set: the shading passes run without the host's set");
    Impl::Slot& slot = m.slot_of(frame_index);
    slot.frame_index = frame_index;
    slot.gaze = m.gaze;
    const uint32_t q0 = kQueriesPerSlot * static_cast<uint32_t>(frame_index % m.slots.size());
    if (m.queries) vkCmdResetQueryPool(cmd, m.queries.get(), q0, kQueriesPerSlot);
    // Host G-buffer writes (compute or transfer) -> our reads; zero the counters.
    VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    mb.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
    mb.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                         VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0,
                         1, &mb, 0, nullptr, 0, nullptr);
    vkCmdFillBuffer(cmd, slot.stats.get(), 0, VK_WHOLE_SIZE, 0);
    m.ingest_host_images(cmd, frame_index, inputs);
    compute_barrier(cmd);
    if (m.queries) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, m.queries.get(), q0);
    MethodFrame mf{cmd,    slot.frame_set, frame_index,    m.cpu_uniforms,
                   inputs, m.gaze,         m.shaded.ref(), m.rate.ref()};
    if (m.config.path == IntegrationPath::kForwardLayers) mf.depth_out = &m.host_targets.refs();
    m.method->record(mf);
    slot.host_samples = m.method->host_rendered_samples();
    compute_barrier(cmd);
    if (m.queries)
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, m.queries.get(), q0 + 1);
    const ImageRef* in = &m.shaded_image();
    bool luma_ready = false;
    for (size_t i = 0; i < m.post_chain.size(); ++i) {
        const ImageRef* out = &m.post[i % 2].ref();
        const VkImageView luma_out =
            i + 1 < m.post_chain.size() && m.post_chain[i]->writes_display_luma()
                ? m.post_chain[i + 1]->display_luma_target()
                : VK_NULL_HANDLE;
        const PostFrame pf{cmd,
                           slot.frame_set,
                           frame_index,
                           m.cpu_uniforms,
                           inputs,
                           m.gaze,
                           *in,
                           *out,
                           m.post_depth(),
                           m.post_motion(),
                           m.rate.ref(),
                           {m.cpu_uniforms.jitter_px[0], m.cpu_uniforms.jitter_px[1]},
                           luma_out,
                           luma_ready};
        m.post_chain[i]->record(pf);
        compute_barrier(cmd);
        in = out;
        luma_ready = luma_out != VK_NULL_HANDLE;
    }
    assert(in == m.output);
    if (m.queries)
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, m.queries.get(), q0 + 2);
    VkMemoryBarrier hb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    hb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
    hb.dstAccessMask = VK_ACCESS_HOST_READ_BIT | VK_ACCESS_MEMORY_READ_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                         VK_PIPELINE_STAGE_HOST_BIT | VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 1, &hb,
                         0, nullptr, 0, nullptr);
}

FrameStats Foveator::stats() const { return stats(impl_->frame_index); }

FrameStats Foveator::stats(uint64_t frame_index) const {
    const Impl& m = *impl_;
    const Impl::Slot& slot = m.slot_of(frame_index);
    FrameStatsGpu g;
    std::memcpy(&g, slot.stats.data(), sizeof(g));
    FrameStats s;
    s.frame_index = slot.frame_index;
    s.shaded_samples = g.shaded_samples + slot.host_samples;
    s.edge_samples = g.edge_samples;
    for (int i = 0; i < 4; ++i) s.tiles[i] = g.tiles[i];
    s.skipped_tiles = g.tiles[3];
    s.reused_tiles = g.reused_tiles;
    s.background_tiles = g.background_tiles;
    s.flat_tiles = g.flat_tiles;
    s.no_detail_tiles = g.no_detail_tiles;
    s.shaded_fraction = static_cast<double>(s.shaded_samples) /
                        (static_cast<double>(m.config.extent.width) * m.config.extent.height);
    s.gaze = slot.gaze;
    if (m.queries) {
        const uint32_t q0 = kQueriesPerSlot * static_cast<uint32_t>(frame_index % m.slots.size());
        uint64_t ts[kQueriesPerSlot] = {};
        if (vkGetQueryPoolResults(m.device->device(), m.queries.get(), q0, kQueriesPerSlot,
                                  sizeof(ts), ts, sizeof(uint64_t),
                                  VK_QUERY_RESULT_64_BIT) == VK_SUCCESS) {
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
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace fovea::vk
