// Post pass "taa": Patney 2016's variance-sampled, saccade-aware temporal anti-aliasing as four
// compute stages (moments straight at mip level 1, the rest of the moment mip chain, 8×8 tiles
// sorted by which moment levels they read, resolve: one indirect dispatch per tile list with a
// pipeline holding only those reads; where it reads level 0 it computes it itself). The CPU
// reference is taa_model.cpp; the shaders are shaders/taa_*.glsl. Options
// (FoveatorConfig::options): taa.alpha (0.1), taa.alpha_max (1/3), taa.beta (0.25), taa.gamma (1),
// taa.depth_tolerance (0.05), taa.saccade (1 = on), taa.precision (half | float: moment and
// history storage), taa.share_luma (1: when an enhancement pass follows, the resolve also writes
// its display luminance, PostPass::writes_display_luma; 0 for comparison).
// Called on the host's render thread (PostPass contract).
#include <algorithm>
#include <array>
#include <map>
#include <tuple>

#include "post_pass.hpp"

namespace fovea::vk {
namespace {

constexpr uint32_t kMomentLevels = 5;  // LOD = 4·S_t reads levels 0..4
constexpr uint32_t kTile = 8;          // resolve workgroup = tile of taa_tiles.comp
// taa_tiles.comp's lists, one resolve pipeline each (kTileClass): 0 some LOD < 1 (not all 0),
// 1 every LOD >= 1, 2 every LOD 0.
constexpr uint32_t kTileLists = 3;

struct ResolvePush {
    float jitter[2];  // first, as in the shader (std430 aligns a vec2 to 8 bytes)
    float alpha;
    float alpha_max;
    float beta;
    float gamma;
    float depth_tolerance;
    int32_t levels;
    uint32_t flags;
    uint32_t tiles_x;
    uint32_t list_base;
};

struct TilesPush {
    uint32_t tiles_x, tiles_y;
    int32_t levels;
};

// taa_tiles.comp's indirect arguments: VkDispatchIndirectCommand + pad per list.
struct TileArgs {
    uint32_t cmd[kTileLists][4];
};

class TaaPass final : public PostPass {
public:
    Result<void> init(const ModuleContext& ctx) override {
        device_ = ctx.device.device();
        push_.alpha = float(ctx.option_number("taa.alpha", 0.1));
        push_.alpha_max = float(ctx.option_number("taa.alpha_max", 1.0 / 3.0));
        push_.beta = float(ctx.option_number("taa.beta", 0.25));
        push_.gamma = float(ctx.option_number("taa.gamma", 1.0));
        push_.depth_tolerance = float(ctx.option_number("taa.depth_tolerance", 0.05));
        saccade_ = ctx.option_number("taa.saccade", 1.0) != 0.0;
        share_luma_ = ctx.option_number("taa.share_luma", 1.0) != 0.0;
        const std::string precision = ctx.option("taa.precision", "half");
        if (precision != "half" && precision != "float")
            return make_error("taa.precision must be half or float, not '" + precision + "'");
        const bool half = precision == "half";
        const VkFormat fmt = half ? VK_FORMAT_R16G16B16A16_SFLOAT : VK_FORMAT_R32G32B32A32_SFLOAT;
        const std::string suffix = half ? "_half.comp" : "_float.comp";
        if (!(push_.beta > 0.0f)) return make_error("taa.beta must be > 0");

        const VkExtent2D e = ctx.extent;
        uint32_t levels = 1;
        for (uint32_t w = e.width, h = e.height; levels < kMomentLevels && (w > 1 || h > 1);
             ++levels) {
            w = std::max(1u, w / 2);  // Vulkan mip sizes
            h = std::max(1u, h / 2);
        }
        push_.levels = int32_t(levels);
        const VkImageUsageFlags mom_usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
        // Chain levels 1..levels-1 (mip k = level k + 1; Vulkan mip sizes of the full extent).
        // A 1×1 frame has level 0 only: one unread texel keeps the descriptors valid.
        const VkExtent2D half_extent{std::max(1u, e.width / 2), std::max(1u, e.height / 2)};
        const uint32_t stored = std::max(1u, levels - 1);
        m1_ = Image(ctx.device, half_extent, fmt, mom_usage, stored);
        m2_ = Image(ctx.device, half_extent, fmt, mom_usage, stored);
        for (auto& h : hist_) h = Image(ctx.device, e, fmt, mom_usage);
        for (auto& d : hist_depth_)
            d = Image(ctx.device, e, VK_FORMAT_R32_SFLOAT, VK_IMAGE_USAGE_STORAGE_BIT);

        // Trilinear for the moment chain (LOD = 4·S_t, clamped to the chain like the model),
        // clamp to edge as the model's fetch().
        sampler_ = LinearClampSampler(ctx.device, stored);
        tiles_x_ = div_up(e.width, kTile);
        tiles_y_ = div_up(e.height, kTile);
        const uint64_t capacity = uint64_t{tiles_x_} * tiles_y_;
        tile_args_ =
            Buffer(ctx.device, sizeof(TileArgs),
                   VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT, false);
        tile_lists_ = Buffer(ctx.device, capacity * kTileLists * 4,
                             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false);

        const Binding img{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};
        const Binding tex{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER};
        const Binding mom_b[] = {img, img, img};
        const Binding red_b[] = {img, img, img, img};
        const Binding buf{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};
        const Binding tiles_b[] = {img, buf, buf};
        const Binding res_b[] = {img, img, img, img, tex, tex, img, img, img, img, buf, img};
        moments_ = ctx.builtin_pipeline("taa_moments" + suffix, mom_b, 0, false);
        reduce_ = ctx.builtin_pipeline("taa_reduce" + suffix, red_b, 0, false);
        tiles_ = ctx.builtin_pipeline("taa_tiles.comp", tiles_b, sizeof(TilesPush), false);
        for (uint32_t luma = 0; luma < 2; ++luma)
            for (uint32_t list = 0; list < kTileLists; ++list) {
                const uint32_t spec[] = {list, luma};  // kTileClass, kWriteLuma
                resolve_[luma][list] = ctx.builtin_pipeline("taa_resolve" + suffix, res_b,
                                                            sizeof(ResolvePush), false, spec);
            }
        // What binding 11 holds when no pass after this one takes the luminance.
        no_luma_ = Image(ctx.device, {1, 1}, VK_FORMAT_R32_SFLOAT, VK_IMAGE_USAGE_STORAGE_BIT);
        // Mip 0 (level 1) comes from the moments pass; the rest are 2×2 reductions.
        for (uint32_t l = 0; l + 1 < stored; ++l) {
            VkDescriptorSet s = reduce_.allocate_set();
            DescriptorWriter(device_, s)
                .storage_image(0, m1_.mip_view(l))
                .storage_image(1, m2_.mip_view(l))
                .storage_image(2, m1_.mip_view(l + 1))
                .storage_image(3, m2_.mip_view(l + 1))
                .commit();
            reduce_sets_.push_back(s);
        }
        return {};
    }

    void record(const PostFrame& f) override {
        const VkExtent2D e = f.color_in.extent;
        TileArgs args{};
        for (auto& c : args.cmd) {
            c[1] = 1;
            c[2] = 1;
        }
        // Last frame's resolve read these arguments (indirect stage) and the depth history
        // overwritten below before they are reset.
        VkMemoryBarrier war{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        vkCmdPipelineBarrier(
            f.cmd, VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
            VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &war, 0, nullptr, 0, nullptr);
        vkCmdUpdateBuffer(f.cmd, tile_args_.get(), 0, sizeof(args), &args);
        // Next frame's depth history is this frame's depth: a copy, not a store per pixel in
        // the resolve (a store costs lavapipe about as much as 4 loads); the resolve sanitizes
        // what it reads back.
        VkImageCopy depth_copy{};
        depth_copy.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        depth_copy.dstSubresource = depth_copy.srcSubresource;
        depth_copy.extent = {e.width, e.height, 1};
        vkCmdCopyImage(f.cmd, f.depth.image, VK_IMAGE_LAYOUT_GENERAL,
                       hist_depth_[1 - parity_].get(), VK_IMAGE_LAYOUT_GENERAL, 1, &depth_copy);

        auto mit = moment_sets_.find(f.color_in.view);
        if (mit == moment_sets_.end()) {
            VkDescriptorSet s = moments_.allocate_set();
            DescriptorWriter(device_, s)
                .storage_image(0, f.color_in.view)
                .storage_image(1, m1_.mip_view(0))
                .storage_image(2, m2_.mip_view(0))
                .commit();
            mit = moment_sets_.emplace(f.color_in.view, s).first;
        }
        moments_.bind(f.cmd, VK_NULL_HANDLE, mit->second);
        vkCmdDispatch(f.cmd, div_up(std::max(1u, e.width / 2), 8),
                      div_up(std::max(1u, e.height / 2), 8), 1);
        compute_barrier(f.cmd);
        for (uint32_t i = 0; i < reduce_sets_.size(); ++i) {
            const uint32_t dst = i + 2;  // chain level written
            reduce_.bind(f.cmd, VK_NULL_HANDLE, reduce_sets_[i]);
            vkCmdDispatch(f.cmd, div_up(std::max(1u, e.width >> dst), 8),
                          div_up(std::max(1u, e.height >> dst), 8), 1);
            compute_barrier(f.cmd);
        }
        auto tit = tile_sets_.find(f.rate.view);
        if (tit == tile_sets_.end()) {
            VkDescriptorSet s = tiles_.allocate_set();
            DescriptorWriter(device_, s)
                .storage_image(0, f.rate.view)
                .storage_buffer(1, tile_args_)
                .storage_buffer(2, tile_lists_)
                .commit();
            tit = tile_sets_.emplace(f.rate.view, s).first;
        }
        const TilesPush tiles_push{tiles_x_, tiles_y_, push_.levels};
        tiles_.bind(f.cmd, VK_NULL_HANDLE, tit->second, &tiles_push, sizeof(tiles_push));
        vkCmdDispatch(f.cmd, div_up(tiles_x_ * tiles_y_, 64), 1, 1);
        indirect_barrier(f.cmd);

        const int src = parity_;
        const int dst = 1 - parity_;
        const bool write_luma = f.display_luma_out != VK_NULL_HANDLE;
        const VkImageView luma = write_luma ? f.display_luma_out : no_luma_.view();
        auto& resolve = resolve_[write_luma ? 1 : 0];
        const auto key = std::make_tuple(f.color_in.view, f.color_out.view, f.depth.view,
                                         f.motion.view, f.rate.view, src, luma);
        auto rit = resolve_sets_.find(key);
        if (rit == resolve_sets_.end()) {
            std::array<VkDescriptorSet, kTileLists> sets{};
            for (uint32_t list = 0; list < kTileLists; ++list) {
                sets[list] = resolve[list].allocate_set();
                DescriptorWriter(device_, sets[list])
                    .storage_image(0, f.color_in.view)
                    .storage_image(1, f.depth.view)
                    .storage_image(2, f.motion.view)
                    .storage_image(3, f.rate.view)
                    .sampled_image(4, m1_.view(), sampler_.get())
                    .sampled_image(5, m2_.view(), sampler_.get())
                    .storage_image(6, hist_[src].view())
                    .storage_image(7, hist_depth_[src].view())
                    .storage_image(8, hist_[dst].view())
                    .storage_image(9, f.color_out.view)
                    .storage_buffer(10, tile_lists_)
                    .storage_image(11, luma)
                    .commit();
            }
            rit = resolve_sets_.emplace(key, sets).first;
        }
        ResolvePush push = push_;
        const bool have_history = valid_ && !f.inputs.camera_cut;
        push.flags = (have_history ? 1u : 0u) | (saccade_ ? 2u : 0u);
        push.jitter[0] = f.jitter_px[0];
        push.jitter[1] = f.jitter_px[1];
        push.tiles_x = tiles_x_;
        for (uint32_t list = 0; list < kTileLists; ++list) {
            push.list_base = list * tiles_x_ * tiles_y_;
            resolve[list].bind(f.cmd, VK_NULL_HANDLE, rit->second[list], &push, sizeof(push));
            vkCmdDispatchIndirect(f.cmd, tile_args_.get(), list * 16);
        }
        parity_ = dst;
        valid_ = true;
    }

    bool writes_display_luma() const override { return share_luma_; }

private:
    VkDevice device_ = VK_NULL_HANDLE;
    LinearClampSampler sampler_;
    ResolvePush push_{};
    bool saccade_ = true;
    bool share_luma_ = true;
    bool valid_ = false;
    int parity_ = 0;
    Image m1_, m2_;
    std::array<Image, 2> hist_, hist_depth_;
    Image no_luma_;
    uint32_t tiles_x_ = 0, tiles_y_ = 0;
    Buffer tile_args_, tile_lists_;  // taa_tiles.comp's indirect arguments and tile lists
    ComputePipeline moments_, reduce_, tiles_;
    // [writes display luminance][tile class]
    std::array<std::array<ComputePipeline, kTileLists>, 2> resolve_;
    std::vector<VkDescriptorSet> reduce_sets_;
    std::map<VkImageView, VkDescriptorSet> moment_sets_, tile_sets_;
    std::map<std::tuple<VkImageView, VkImageView, VkImageView, VkImageView, VkImageView, int,
                        VkImageView>,
             std::array<VkDescriptorSet, kTileLists>>
        resolve_sets_;
};

}  // namespace

std::unique_ptr<PostPass> make_taa_pass() { return std::make_unique<TaaPass>(); }

}  // namespace fovea::vk
