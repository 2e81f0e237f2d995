// Method "layers": Guenter et al. 2012 eccentricity layers. Layer radii and sampling factors
// come from the §4.3 optimisation (layers_model.hpp) for the configured display and MAR slope.
// Each frame the host renders every layer due this frame (views(): a crop of its projection
// around the gaze, snapped to the layer's texel grid, plus a jitter of ±0.5 layer texel); the
// module shades each layer, resolves it onto its unjittered grid blended with its reprojected
// history, and composites all layers bilinearly with smoothstep circle masks.
// Options: layers.count (3), layers.slope (acuity.mar_slope), layers.omega0 (acuity.mar_omega0),
// layers.half_rate (0: every layer every frame; 1: outer layers on alternate frames,
// staggered), layers.alpha (0.5: weight of the current frame in the outer layers' blend),
// layers.fovea_deg (acuity.foveal_radius_deg: the inner layer alone covers that much around
// the gaze anywhere on the display; 0: pure §4.3 radii).
// The inner layer uses the frame's own jitter and no history, so the fovea is the full-rate
// image (s = 1, same samples).
// On the forward path (IntegrationPath::kForwardLayers) the host renders each layer's colour,
// depth and motion itself (ViewRequest::targets) and the shade pass is skipped; the module also
// writes full-resolution depth and motion from the layers for the post chain
// (shaders/layers_depth_motion.comp).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "../host_frame.hpp"
#include "../method.hpp"
#include "layers_model.hpp"

namespace fovea::vk {
namespace {

constexpr int kMaxLayers = 4;

struct ShadePush {  // shaders/layers_shade.shade.comp
    float origin[2];
    float jitter[2];
    float s;
    float pad[3];
};
struct ResolvePush {  // shaders/layers_resolve.comp
    float origin[2];
    float prev_origin[2];
    float jitter[2];
    float s;
    float alpha;
    int32_t has_history;
    float pad;
    float view_jitter[2];
};
struct LayerInfoGpu {  // shaders/layers_common.glsl LayerInfo
    float a[4];
    float b[4];
    float c[4];
};
struct LayerTable {
    int32_t count;
    int32_t pad[3];
    LayerInfoGpu layer[kMaxLayers];
};
struct DepthMotionPush {  // shaders/layers_depth_motion.comp
    float jitter[4][4];
};
static_assert(sizeof(ShadePush) == 32 && sizeof(ResolvePush) == 48, "push layouts");
static_assert(sizeof(LayerTable) == 16 + 48 * kMaxLayers, "std430 layout");

struct LayerState {
    double s = 1.0;
    VkExtent2D texels{};                            // layer image size
    double radius_px = 0.0;                         // mask radius; 0 for the outer layer
    std::array<Image, kGBufferImageCount> gbuffer;  // path 1
    GBufferRefs refs;
    HostTargetImages targets;  // path 2: the host's colour (read as `current`), depth, motion
    Image current;             // path 1: this frame's shading
    std::array<Image, 2> history;
    Image resolved;  // latest resolve, read by the composite (fixed binding)
    int which = 0;   // history image holding the latest resolve
    bool has_history = false;
    double origin[2]{0, 0};          // of this frame's request
    double prev_origin[2]{0, 0};     // of the latest resolve
    double centre[2]{0, 0};          // mask centre: the gaze of this frame's request
    double prev_centre[2]{0, 0};     // of the latest resolve
    float jitter[2]{0, 0};           // of this frame's request, layer texels
    float resolved_jitter[2]{0, 0};  // of the latest resolve (what its depth/motion hold)
    uint64_t planned_frame = UINT64_MAX;
    bool due = false;
    VkDescriptorSet shade_set = VK_NULL_HANDLE;
    std::array<VkDescriptorSet, 2> resolve_sets{};  // [i]: reads history[i], writes the other
};

class LayersMethod final : public Method {
public:
    Result<void> init(const ModuleContext& ctx) override {
        extent_ = ctx.extent;
        jitter_length_ = ctx.config.jitter_length;
        host_shaded_ = ctx.config.path == IntegrationPath::kForwardLayers;
        const EyeDisplay& d = ctx.config.display;
        // Measured along the longer axis (Guenter fn. 8): HMD eyes are portrait. Inner layers
        // are squares and the outer one covers the extent, so nothing else depends on it.
        const methods::LayerDisplay display = methods::layer_display_for(
            int(extent_.width), int(extent_.height), d.fov_h_deg, d.fov_v_deg);
        methods::LayerOptions o;
        o.layer_count = int(ctx.option_number("layers.count", 3));
        o.slope = ctx.option_number("layers.slope", ctx.config.acuity.mar_slope);
        o.omega0_deg = ctx.option_number("layers.omega0", ctx.config.acuity.mar_omega0);
        half_rate_ = ctx.option_number("layers.half_rate", 0.0) != 0.0;
        // The inner layer alone (inside the 60 % where its smoothstep blend starts) is the
        // full-rate frame, so by default it spans the stack's full-rate fovea. Pure §4.3 radii
        // (layers.fovea_deg=0) put the middle layer (s ~ 2) from 2.4 degrees on at m = 0.022:
        // 35.7 dB over the 5-degree fovea. The fovea's edge may reach 80 % of the inner radius
        // (blend weight 1/2) for a gaze in a corner, where a degree spans the most pixels; a
        // gaze nearer the centre keeps nearly all of it at full weight. Full weight everywhere
        // (60 %) would cost 39 % of the pixels instead of 25 % for no measurable gain.
        const double fovea_deg =
            ctx.option_number("layers.fovea_deg", ctx.config.acuity.foveal_radius_deg);
        if (!(fovea_deg >= 0.0)) return make_error("layers.fovea_deg must be >= 0");
        // A fovea wider than the display leaves one inner layer over (almost) all of it.
        o.min_inner_deg = std::min(methods::inner_radius_for_fovea(display, fovea_deg, 0.8),
                                   methods::display_radius_deg(display) * (o.steps - 1) / o.steps);
        o.half_rate_outer = half_rate_;
        alpha_ = float(ctx.option_number("layers.alpha", 0.5));
        if (!(alpha_ > 0.0f && alpha_ <= 1.0f)) return make_error("layers.alpha must be in (0, 1]");
        auto plan = methods::optimise_layers(display, o);
        if (!plan) return make_error("layers: " + plan.error().message);
        plan_ = *plan;

        count_ = int(plan_.layers.size());
        for (int i = 0; i < count_; ++i) {
            const methods::Layer& l = plan_.layers[std::size_t(i)];
            LayerState& st = layers_[std::size_t(i)];
            st.s = l.sampling_factor;
            if (i + 1 < count_) {
                const uint32_t n = std::max(1u, uint32_t(std::ceil(l.diameter_px)));
                st.texels = {n, n};
                st.radius_px = 0.5 * n * st.s;
            } else {
                st.texels = {std::max(1u, uint32_t(std::ceil(extent_.width / st.s))),
                             std::max(1u, uint32_t(std::ceil(extent_.height / st.s)))};
            }
            if (host_shaded_) {
                st.targets = HostTargetImages(ctx.device, st.texels);
            } else {
                for (int g = 0; g < kGBufferImageCount; ++g) {
                    st.gbuffer[std::size_t(g)] = Image(
                        ctx.device, st.texels, kGBufferFormats[std::size_t(g)], kGBufferUsage);
                    st.refs.images[std::size_t(g)] = st.gbuffer[std::size_t(g)].ref();
                }
                st.refs.extent = st.texels;
                st.current = Image(ctx.device, st.texels, kColorFormat, VK_IMAGE_USAGE_STORAGE_BIT);
            }
            for (Image& h : st.history)
                h = Image(ctx.device, st.texels, kColorFormat, VK_IMAGE_USAGE_STORAGE_BIT);
            st.resolved = Image(ctx.device, st.texels, kColorFormat,
                                VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT);
        }

        const Binding img{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};
        // The layer's G-buffer images (bindings 0..kGBufferImageCount-1), then its colour.
        std::array<Binding, kGBufferImageCount + 1> shade_b{};
        shade_b.fill(img);
        const Binding resolve_b[] = {img, img, img, img, img};
        const Binding tex{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER};
        const Binding composite_b[] = {img, tex, tex, tex, {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}};
        if (!host_shaded_) {
            auto shade =
                ctx.shading_pipeline("layers_shade.shade.comp", shade_b, sizeof(ShadePush));
            if (!shade) return shade.error();
            shade_ = std::move(*shade);
        }
        resolve_ =
            ctx.builtin_pipeline("layers_resolve.comp", resolve_b, sizeof(ResolvePush), false);
        const uint32_t spec[] = {uint32_t(count_)};  // LAYERS: straight-line composite code
        composite_ = ctx.builtin_pipeline("layers_composite.comp", composite_b, 0, true, spec);
        // Written by vkCmdUpdateBuffer in record(): no host copy per frame in flight.
        table_ =
            Buffer(ctx.device, sizeof(LayerTable),
                   VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, false);

        const VkDevice dev = ctx.device.device();
        // The composite upsamples the coarser layers with the sampler's bilinear filter: one
        // fetch per layer instead of four loads (the composite was a third of the method's time
        // on llvmpipe). Clamp to edge = the clamped taps of the resolve.
        sampler_ = LinearClampSampler(ctx.device);
        for (int i = 0; i < count_; ++i) {
            LayerState& st = layers_[std::size_t(i)];
            if (!host_shaded_) {
                st.shade_set = shade_.allocate_set();
                DescriptorWriter w(dev, st.shade_set);
                for (uint32_t g = 0; g < uint32_t(kGBufferImageCount); ++g)
                    w.storage_image(g, st.gbuffer[g].view());
                w.storage_image(uint32_t(kGBufferImageCount), st.current.view()).commit();
            }
            const VkImageView current =
                host_shaded_ ? st.targets.refs().color.view : st.current.view();
            const VkImageView motion =
                host_shaded_ ? st.targets.refs().motion.view
                             : st.gbuffer[static_cast<int>(GBufferImage::kMotion)].view();
            for (int k = 0; k < 2; ++k) {
                st.resolve_sets[std::size_t(k)] = resolve_.allocate_set();
                DescriptorWriter(dev, st.resolve_sets[std::size_t(k)])
                    .storage_image(0, current)
                    .storage_image(1, motion)
                    .storage_image(2, st.history[std::size_t(k)].view())
                    .storage_image(3, st.history[std::size_t(1 - k)].view())
                    .storage_image(4, st.resolved.view())
                    .commit();
            }
        }
        composite_set_ = composite_.allocate_set();
        DescriptorWriter w(dev, composite_set_);
        w.storage_image(0, layers_[0].resolved.view());  // the inner layer: one load per pixel
        for (int i = 1; i < 3; ++i)  // unused inner slots repeat the outer layer (valid image)
            w.sampled_image(uint32_t(i),
                            layers_[std::size_t(i < count_ - 1 ? i : count_ - 1)].resolved.view(),
                            sampler_.get());
        w.sampled_image(3, layers_[std::size_t(count_ - 1)].resolved.view(), sampler_.get());
        w.storage_buffer(4, table_).commit();
        if (host_shaded_) init_depth_motion(ctx);
        return {};
    }

    bool uses_full_gbuffer() const override { return false; }
    uint64_t host_rendered_samples() const override { return host_samples_; }
    bool has_views() const override { return true; }

    std::vector<ViewRequest> views(uint64_t frame_index, const ResolvedGaze& gaze) override {
        plan_frame(frame_index, gaze);
        std::vector<ViewRequest> out;
        for (int i = 0; i < count_; ++i) {
            const LayerState& st = layers_[std::size_t(i)];
            if (!st.due) continue;
            ViewRequest v;
            v.name = "layer" + std::to_string(i);
            v.extent = st.texels;
            if (host_shaded_)
                v.targets = st.targets.refs();
            else
                v.gbuffer = st.refs;
            const double w = st.texels.width * st.s;
            const double h = st.texels.height * st.s;
            v.crop = {float(st.origin[0] / extent_.width), float(st.origin[1] / extent_.height),
                      float((st.origin[0] + w) / extent_.width),
                      float((st.origin[1] + h) / extent_.height)};
            v.jitter_px = {st.jitter[0], st.jitter[1]};
            out.push_back(std::move(v));
        }
        return out;
    }

    void record(const MethodFrame& f) override {
        plan_frame(f.frame_index, f.gaze);  // no-op when views() already planned this frame
        host_samples_ = 0;
        for (int i = 0; i < count_; ++i) {
            LayerState& st = layers_[std::size_t(i)];
            if (!st.due) continue;
            if (host_shaded_) {  // the host rendered this layer: count its texels
                host_samples_ += uint64_t{st.texels.width} * st.texels.height;
                continue;
            }
            ShadePush sp{};
            sp.origin[0] = float(st.origin[0]);
            sp.origin[1] = float(st.origin[1]);
            // The inner layer's samples are the full-rate frame's own (same jitter, s = 1): they
            // land on their pixels unresampled, exactly like method "full" writes them.
            sp.jitter[0] = sp_jitter(i, 0);
            sp.jitter[1] = sp_jitter(i, 1);
            sp.s = float(st.s);
            shade_.bind(f.cmd, f.frame_set, st.shade_set, &sp, sizeof(sp));
            vkCmdDispatch(f.cmd, div_up(st.texels.width, 8), div_up(st.texels.height, 8), 1);
        }
        compute_barrier(f.cmd);
        for (int i = 0; i < count_; ++i) {
            LayerState& st = layers_[std::size_t(i)];
            if (!st.due) continue;
            ResolvePush rp{};
            rp.origin[0] = float(st.origin[0]);
            rp.origin[1] = float(st.origin[1]);
            rp.prev_origin[0] = float(st.prev_origin[0]);
            rp.prev_origin[1] = float(st.prev_origin[1]);
            rp.jitter[0] = sp_jitter(i, 0);
            rp.jitter[1] = sp_jitter(i, 1);
            rp.s = float(st.s);
            rp.alpha = i == 0 ? 1.0f : alpha_;
            rp.has_history = (st.has_history && !f.inputs.camera_cut) ? 1 : 0;
            rp.view_jitter[0] = st.jitter[0];
            rp.view_jitter[1] = st.jitter[1];
            resolve_.bind(f.cmd, VK_NULL_HANDLE, st.resolve_sets[std::size_t(st.which)], &rp,
                          sizeof(rp));
            vkCmdDispatch(f.cmd, div_up(st.texels.width, 8), div_up(st.texels.height, 8), 1);
            st.which = 1 - st.which;
            st.has_history = true;
            st.prev_origin[0] = st.origin[0];
            st.prev_origin[1] = st.origin[1];
            st.prev_centre[0] = st.centre[0];
            st.prev_centre[1] = st.centre[1];
            st.resolved_jitter[0] = st.jitter[0];
            st.resolved_jitter[1] = st.jitter[1];
        }
        LayerTable table{};
        table.count = count_;
        for (int i = 0; i < count_; ++i) {
            const LayerState& st = layers_[std::size_t(i)];
            LayerInfoGpu& g = table.layer[i];
            g.a[0] = float(st.prev_origin[0]);
            g.a[1] = float(st.prev_origin[1]);
            g.a[2] = float(st.s);

            g.b[0] = float(st.texels.width);
            g.b[1] = float(st.texels.height);
            g.b[2] = float(st.radius_px);
            g.c[0] = float(st.prev_centre[0]);
            g.c[1] = float(st.prev_centre[1]);
        }
        vkCmdUpdateBuffer(f.cmd, table_.get(), 0, sizeof(table), &table);
        compute_barrier(f.cmd);
        composite_.bind(f.cmd, f.frame_set, composite_set_);
        vkCmdDispatch(f.cmd, div_up(extent_.width, 8), div_up(extent_.height, 8), 1);
        if (host_shaded_ && f.depth_out) {
            // Each layer's jitter as of its latest render (the resolved image the composite
            // reads), in layer texels.
            DepthMotionPush dp{};
            for (int i = 0; i < count_; ++i) {
                dp.jitter[i][0] = layers_[std::size_t(i)].resolved_jitter[0];
                dp.jitter[i][1] = layers_[std::size_t(i)].resolved_jitter[1];
            }
            if (depth_motion_set_ == VK_NULL_HANDLE) write_depth_motion_set(*f.depth_out);
            depth_motion_.bind(f.cmd, f.frame_set, depth_motion_set_, &dp, sizeof(dp));
            vkCmdDispatch(f.cmd, div_up(extent_.width, 8), div_up(extent_.height, 8), 1);
        }
    }

    const methods::LayerPlan& plan() const { return plan_; }

private:
    float sp_jitter(int layer, int axis) const {
        return layer == 0 ? 0.0f : layers_[std::size_t(layer)].jitter[axis];
    }

    // Which layers update this frame, where their crops sit and their jitter.
    void plan_frame(uint64_t frame, const ResolvedGaze& gaze) {
        if (layers_[0].planned_frame == frame) return;
        // Keep the inner layers' crops on the display (a gaze off screen still foveates the edge).
        const double gx = std::clamp(double(gaze.x_px), 0.0, double(extent_.width));
        const double gy = std::clamp(double(gaze.y_px), 0.0, double(extent_.height));
        for (int i = 0; i < count_; ++i) {
            LayerState& st = layers_[std::size_t(i)];
            st.planned_frame = frame;
            // Half rate: the inner layer every frame, the others on alternate frames, staggered
            // so that each frame updates about the same number of pixels (Guenter §4).
            st.due = !half_rate_ || i == 0 || !st.has_history || (frame + uint64_t(i)) % 2 == 1;
            if (!st.due) continue;
            st.centre[0] = gx;
            st.centre[1] = gy;
            if (i + 1 < count_) {
                // Snap the crop to the layer's texel grid so the history stays aligned, then
                // keep it on the display (crops stay within 0..1): the on-screen part of the
                // mask circle around the gaze still lies inside the shifted square.
                const double size = st.texels.width * st.s;
                for (int a = 0; a < 2; ++a) {
                    const double extent = a == 0 ? extent_.width : extent_.height;
                    const double snapped =
                        std::round(((a == 0 ? gx : gy) - 0.5 * size) / st.s) * st.s;
                    st.origin[a] = std::clamp(snapped, std::min(0.0, extent - size),
                                              std::max(0.0, extent - size));
                }
            } else {
                st.origin[0] = st.origin[1] = 0.0;
            }
            if (i == 0) {  // the frame's own jitter: the fovea matches the full-rate frame
                halton_jitter(frame, jitter_length_, st.jitter[0], st.jitter[1]);
            } else {  // decorrelated per layer (Guenter Fig. 6: ±0.5 layer texel)
                halton_jitter(frame + 3 * uint64_t(i), std::max(jitter_length_, 8u), st.jitter[0],
                              st.jitter[1]);
            }
        }
    }

    void init_depth_motion(const ModuleContext& ctx) {
        const Binding img{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};
        const Binding b[] = {
            img, img, img, img, img, img, img, img, img, img, {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}};
        const uint32_t spec[] = {uint32_t(count_)};
        depth_motion_ = ctx.builtin_pipeline("layers_depth_motion.comp", b, sizeof(DepthMotionPush),
                                             true, spec);
        device_ = ctx.device.device();
    }

    // Full-resolution outputs are the Foveator's; they never change, so one set serves.
    void write_depth_motion_set(const HostTargets& out) {
        depth_motion_set_ = depth_motion_.allocate_set();
        DescriptorWriter w(device_, depth_motion_set_);
        for (int i = 0; i < 3; ++i) {  // unused inner slots repeat the outer layer (valid image)
            const HostTargets& t =
                layers_[std::size_t(i < count_ - 1 ? i : count_ - 1)].targets.refs();
            w.storage_image(uint32_t(i), t.depth.view)
                .storage_image(uint32_t(4 + i), t.motion.view);
        }
        const HostTargets& outer = layers_[std::size_t(count_ - 1)].targets.refs();
        w.storage_image(3, outer.depth.view).storage_image(7, outer.motion.view);
        w.storage_image(8, out.depth.view).storage_image(9, out.motion.view);
        w.storage_buffer(10, table_).commit();
    }

    VkExtent2D extent_{};
    uint32_t jitter_length_ = 8;
    bool host_shaded_ = false;   // IntegrationPath::kForwardLayers
    uint64_t host_samples_ = 0;  // layer texels the host rendered this frame
    VkDevice device_ = VK_NULL_HANDLE;
    ComputePipeline depth_motion_;
    VkDescriptorSet depth_motion_set_ = VK_NULL_HANDLE;
    bool half_rate_ = false;
    float alpha_ = 0.5f;
    methods::LayerPlan plan_;
    int count_ = 0;
    std::array<LayerState, kMaxLayers> layers_;
    ComputePipeline shade_, resolve_, composite_;
    VkDescriptorSet composite_set_ = VK_NULL_HANDLE;
    LinearClampSampler sampler_;
    Buffer table_;
};

}  // namespace

std::unique_ptr<Method> make_layers_method() { return std::make_unique<LayersMethod>(); }

}  // namespace fovea::vk
