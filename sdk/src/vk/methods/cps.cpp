// Method "cps": coarse pixel shading (Vaidyanathan 2014 as used by Patney 2016) in compute.
// Pass 1 classifies every tile before shading (shaders/cps_classify.comp): reused from last
// frame (still and converged), background only (the host's environment function), flat or
// saturated (coarsest rate), else the acuity model's 1x1 / 2x2 / 4x4 rate; each tile goes to one
// compacted list. Pass 2 shades one sample per coarse pixel of the listed tiles (indirect
// dispatches sized by the lists, so the work is proportional to the samples shaded); pass 3
// re-shades the pixels at surface discontinuities inside coarse pixels (indirect, sized by the
// edge list). The shading lands in colour images the method owns, one per jitter phase (up to
// kMaxPhases, memory permitting): a reused tile keeps the shading of the frame with the same
// sub-pixel jitter, so on a still scene reuse is exact even under jitter, and costs no thread even
// when another method wrote the frame output in between; it is copied to the output.
// Options (FoveatorConfig::options), see shaders/cps_classify.comp for the classes:
//   cps.skip=1               0 disables reuse, background and flat classes (plain CPS)
//   cps.skip.reuse=1         0 disables only the reuse of still tiles
//   cps.skip.still_px=0.01   max |motion + jitter| of a still tile, pixels
//   cps.skip.converge=2      still frames shaded at the same rate before a tile is reused (at
//                            least the jitter phases with their own image: 8 by default)
//   cps.skip.refresh=30      a reused tile is re-shaded every this many frames (0: never)
//   cps.skip.ecc_deg=5       max eccentricity change of a reused tile since it was shaded
//   cps.skip.flat=0.02       luminance contrast (max - min) / (max + min) of a flat tile
//   cps.skip.saturated=6     luminance at or above which every pixel of a tile is saturated
#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include "../method.hpp"

namespace fovea::vk {
namespace {

// Matches CpsPush in shaders/cps_common.glsl.
struct CpsPush {
    uint32_t tiles_x, tiles_y, capacity, edge_capacity, list;
    uint32_t flags, frame, refresh_frames, converge_frames;
    float still_px, ecc_deg, flat_contrast, saturated;
};

// Matches CpsArgs in shaders/cps_common.glsl: lists 0-2 shade, 3 edges, 4-6 background.
struct CpsArgs {
    uint32_t cmd[8][4];
    uint32_t count[8];
    uint32_t dropped;
    uint32_t pad[3];
};
constexpr uint32_t kEdgeList = 3, kBackgroundList = 4, kTileLists = 6;
// Jitter phases with their own colour image (a pipeline's pool holds 8 sets), and the memory
// those images may take; beyond either, phases share images and reuse is approximate.
constexpr uint32_t kMaxPhases = 8;
constexpr uint64_t kMaxPhaseBytes = uint64_t{256} << 20;

// CpsPush.flags, as in shaders/cps_common.glsl.
constexpr uint32_t kSkip = 1, kHistory = 2, kCameraStill = 4, kHostBackground = 8, kReuse = 16;

class CpsMethod final : public Method {
public:
    Result<void> init(const ModuleContext& ctx) override {
        const uint32_t ts = ctx.config.acuity.tile_size;
        tiles_x_ = div_up(ctx.extent.width, ts);
        tiles_y_ = div_up(ctx.extent.height, ts);
        capacity_ = tiles_x_ * tiles_y_;
        const uint64_t pixels = uint64_t{ctx.extent.width} * ctx.extent.height;
        edge_capacity_ = static_cast<uint32_t>(pixels / 4 + 64);
        skip_ = ctx.option_number("cps.skip", 1.0) != 0.0;
        reuse_ = ctx.option_number("cps.skip.reuse", 1.0) != 0.0;
        // GLSL cannot ask whether a function exists: the host's source names it or not.
        host_background_ = ctx.config.shading_glsl.find("fovea_background") != std::string::npos;
        push_.still_px = static_cast<float>(ctx.option_number("cps.skip.still_px", 0.01));
        push_.converge_frames =
            static_cast<uint32_t>(std::max(1.0, ctx.option_number("cps.skip.converge", 2.0)));
        push_.refresh_frames =
            static_cast<uint32_t>(std::max(0.0, ctx.option_number("cps.skip.refresh", 30.0)));
        push_.ecc_deg = static_cast<float>(ctx.option_number("cps.skip.ecc_deg", 5.0));
        push_.flat_contrast = static_cast<float>(ctx.option_number("cps.skip.flat", 0.02));
        push_.saturated = static_cast<float>(ctx.option_number("cps.skip.saturated", 6.0));

        const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
        lists_ = Buffer(ctx.device, uint64_t{capacity_} * kTileLists * 4, storage, false);
        args_ = Buffer(ctx.device, sizeof(CpsArgs), storage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                       false);
        edges_ = Buffer(ctx.device, uint64_t{edge_capacity_} * 4, storage, false);
        state_ = Buffer(ctx.device, uint64_t{capacity_} * 16, storage, false);
        no_detail_ = Buffer(ctx.device, uint64_t{capacity_} * 4, storage, false);
        luminance_ = Buffer(ctx.device, uint64_t{capacity_} * 8, storage, false);
        const uint32_t jitter = std::max(ctx.config.jitter_length, 1u);
        phases_ = skip_ && reuse_ && jitter <= kMaxPhases && pixels * 8 * jitter <= kMaxPhaseBytes
                      ? jitter
                      : 1u;
        // A tile is reused only once every phase image holds its still shading.
        push_.converge_frames = std::max(push_.converge_frames, phases_);
        for (uint32_t i = 0; i < phases_; ++i)
            colors_.emplace_back(ctx.device, ctx.extent, kColorFormat, VK_IMAGE_USAGE_STORAGE_BIT);
        rate_ = Image(ctx.device, ctx.extent, kRateFormat, VK_IMAGE_USAGE_STORAGE_BIT);

        const Binding sb{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};
        const Binding si{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};
        const Binding classify_bindings[] = {sb, sb, sb, si, sb, sb, sb, si};
        const Binding shade_bindings[] = {sb, sb, sb, si, sb};
        classify_ =
            ctx.builtin_pipeline("cps_classify.comp", classify_bindings, sizeof(CpsPush), true);
        for (uint32_t list = 0; list < 3; ++list) {  // rate class = list
            auto shade =
                ctx.shading_pipeline("cps_shade.shade.comp", shade_bindings, sizeof(CpsPush),
                                     {"CPS_RATE_CLASS=" + std::to_string(list) + "u"});
            if (!shade) return shade.error();
            shade_[list] = std::move(*shade);
        }
        auto edge = ctx.shading_pipeline("cps_edge.shade.comp", shade_bindings, sizeof(CpsPush));
        if (!edge) return edge.error();
        edge_ = std::move(*edge);
        if (skip_ && host_background_) {
            auto bg = ctx.shading_pipeline("cps_shade.shade.comp", shade_bindings, sizeof(CpsPush),
                                           {"FOVEA_CPS_BACKGROUND"});
            if (!bg) return bg.error();
            background_ = std::move(*bg);
        }

        VkDevice d = ctx.device.device();
        classify_set_ = classify_.allocate_set();
        DescriptorWriter(d, classify_set_)
            .storage_buffer(0, lists_)
            .storage_buffer(1, args_)
            .storage_buffer(2, edges_)
            .storage_image(3, ctx.rate_tiles.view)
            .storage_buffer(4, luminance_)
            .storage_buffer(5, state_)
            .storage_buffer(6, no_detail_)
            .storage_image(7, rate_.view())
            .commit();
        auto shade_sets = [&](ComputePipeline& p) {
            std::vector<VkDescriptorSet> sets;
            for (const Image& color : colors_) {
                sets.push_back(p.allocate_set());
                DescriptorWriter(d, sets.back())
                    .storage_buffer(0, lists_)
                    .storage_buffer(1, args_)
                    .storage_buffer(2, edges_)
                    .storage_image(3, color.view())
                    .storage_buffer(4, luminance_)
                    .commit();
            }
            return sets;
        };
        for (uint32_t list = 0; list < 3; ++list) shade_sets_[list] = shade_sets(shade_[list]);
        edge_sets_ = shade_sets(edge_);
        if (background_.get()) background_sets_ = shade_sets(background_);
        extent_ = ctx.extent;
        return {};
    }

    void record(const MethodFrame& f) override {
        CpsArgs init{};
        for (auto& c : init.cmd) {
            c[1] = 1;
            c[2] = 1;
        }
        vkCmdUpdateBuffer(f.cmd, args_.get(), 0, sizeof(init), &init);
        compute_barrier(f.cmd);
        // Last frame's shading and tile state are valid only for the directly following frame.
        const bool history =
            has_history_ && f.frame_index == last_frame_ + 1 && !f.inputs.camera_cut;
        CpsPush push = push_;
        push.tiles_x = tiles_x_;
        push.tiles_y = tiles_y_;
        push.capacity = capacity_;
        push.edge_capacity = edge_capacity_;
        push.frame = static_cast<uint32_t>(f.frame_index);
        push.flags = (skip_ ? kSkip : 0u) | (history ? kHistory : 0u) |
                     (history && f.inputs.camera_pos == last_camera_ ? kCameraStill : 0u) |
                     (background_.get() ? kHostBackground : 0u) | (reuse_ ? kReuse : 0u);
        const uint32_t phase = static_cast<uint32_t>(f.frame_index % phases_);
        classify_.bind(f.cmd, f.frame_set, classify_set_, &push, sizeof(push));
        vkCmdDispatch(f.cmd, div_up(capacity_, 64), 1, 1);  // one thread per tile
        indirect_barrier(f.cmd);
        for (uint32_t list = 0; list < 3; ++list) {
            push.list = list;
            shade_[list].bind(f.cmd, f.frame_set, shade_sets_[list][phase], &push, sizeof(push));
            vkCmdDispatchIndirect(f.cmd, args_.get(), list * 16);
        }
        if (background_.get()) {
            for (uint32_t list = kBackgroundList; list < kBackgroundList + 3; ++list) {
                push.list = list;
                background_.bind(f.cmd, f.frame_set, background_sets_[phase], &push, sizeof(push));
                vkCmdDispatchIndirect(f.cmd, args_.get(), list * 16);
            }
        }
        indirect_barrier(f.cmd);
        push.list = kEdgeList;
        edge_.bind(f.cmd, f.frame_set, edge_sets_[phase], &push, sizeof(push));
        vkCmdDispatchIndirect(f.cmd, args_.get(), kEdgeList * 16);
        compute_barrier(f.cmd);
        VkImageCopy region{};
        region.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.dstSubresource = region.srcSubresource;
        region.extent = {extent_.width, extent_.height, 1};
        vkCmdCopyImage(f.cmd, colors_[phase].get(), VK_IMAGE_LAYOUT_GENERAL, f.color.image,
                       VK_IMAGE_LAYOUT_GENERAL, 1, &region);
        vkCmdCopyImage(f.cmd, rate_.get(), VK_IMAGE_LAYOUT_GENERAL, f.rate.image,
                       VK_IMAGE_LAYOUT_GENERAL, 1, &region);
        has_history_ = true;
        last_frame_ = f.frame_index;
        last_camera_ = f.inputs.camera_pos;
    }

private:
    uint32_t tiles_x_ = 0, tiles_y_ = 0, capacity_ = 0, edge_capacity_ = 0;
    VkExtent2D extent_{};
    bool skip_ = true, reuse_ = true, host_background_ = false;
    CpsPush push_{};
    bool has_history_ = false;
    uint64_t last_frame_ = 0;
    std::array<float, 3> last_camera_{};
    Buffer lists_, args_, edges_, state_, no_detail_, luminance_;
    uint32_t phases_ = 1;
    std::vector<Image> colors_;  // persistent shading per jitter phase: reused tiles keep theirs
    Image rate_;                 // persistent S_t
    ComputePipeline classify_, edge_, background_;
    std::array<ComputePipeline, 3> shade_;  // per host-function list (rate class)
    VkDescriptorSet classify_set_ = VK_NULL_HANDLE;
    std::array<std::vector<VkDescriptorSet>, 3> shade_sets_;    // per list, per phase
    std::vector<VkDescriptorSet> edge_sets_, background_sets_;  // per phase
};

}  // namespace

std::unique_ptr<Method> make_cps_method() { return std::make_unique<CpsMethod>(); }

}  // namespace fovea::vk
