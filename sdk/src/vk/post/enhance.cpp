// Post pass "contrast": Patney 2016's contrast enhancement (after TAA), strength f_e from Tariq
// 2022 Table 2 for the configured blur rate. Shaders: shaders/enhance_*.comp; CPU reference:
// contrast_enhance() in enhance_model.cpp. Options: contrast.blur_rate (arcmin/deg, 0.34),
// contrast.fe (overrides the table). Called on the host's render thread (PostPass contract).
#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "post/enhance_model.hpp"
#include "post_pass.hpp"

namespace fovea::vk {
namespace {

constexpr uint32_t kMaxPyramidLevels = 8;

struct ContrastPush {
    float f_e;
    int32_t levels;
};

class ContrastPass final : public PostPass {
public:
    Result<void> init(const ModuleContext& ctx) override {
        device_ = ctx.device.device();
        const double rate = ctx.option_number("contrast.blur_rate", 0.34);
        push_.f_e = float(
            ctx.option_number("contrast.fe", post::calibration_for_blur_rate(float(rate)).f_e));
        if (!(push_.f_e >= 0.0f && push_.f_e < 10.0f))
            return make_error("contrast.fe must be in [0, 10)");
        // Only the levels I_avg can read: S_t <= 1 bounds σ and so LOD = log2(1 + √2σ) (< 1.4).
        const float max_lod = post::blur_lod(post::blur_sigma_for_rate(1.0f));
        const uint32_t needed = std::min(kMaxPyramidLevels, uint32_t(std::ceil(max_lod)) + 1);
        uint32_t levels = 1;
        for (uint32_t w = ctx.extent.width, h = ctx.extent.height;
             levels < needed && (w > 1 || h > 1); ++levels) {
            w = std::max(1u, w / 2);
            h = std::max(1u, h / 2);
        }
        push_.levels = int32_t(levels);
        pyramid_ = Image(ctx.device, ctx.extent, VK_FORMAT_R32_SFLOAT,
                         VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT, levels);
        sampler_ = LinearClampSampler(ctx.device, levels);  // I_avg: trilinear
        const Binding img{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};
        const Binding tex{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER};
        const Binding luma_b[] = {img, img};
        const Binding red_b[] = {img, img};
        const Binding con_b[] = {img, img, tex, img};
        luma_ = ctx.builtin_pipeline("enhance_luma.comp", luma_b, 0, false);
        reduce_ = ctx.builtin_pipeline("enhance_reduce.comp", red_b, 0, false);
        contrast_ =
            ctx.builtin_pipeline("enhance_contrast.comp", con_b, sizeof(ContrastPush), false);
        // One reduce set per level; the pipeline's pool holds 8 sets.
        for (uint32_t l = 0; l + 1 < levels; ++l) {
            VkDescriptorSet s = reduce_.allocate_set();
            DescriptorWriter(device_, s)
                .storage_image(0, pyramid_.mip_view(l))
                .storage_image(1, pyramid_.mip_view(l + 1))
                .commit();
            reduce_sets_.push_back(s);
        }
        return {};
    }

    VkImageView display_luma_target() const override { return pyramid_.mip_view(0); }

    void record(const PostFrame& f) override {
        const VkExtent2D e = f.color_in.extent;
        if (!f.display_luma_ready) {
            auto lit = luma_sets_.find(f.color_in.view);
            if (lit == luma_sets_.end()) {
                VkDescriptorSet s = luma_.allocate_set();
                DescriptorWriter(device_, s)
                    .storage_image(0, f.color_in.view)
                    .storage_image(1, pyramid_.mip_view(0))
                    .commit();
                lit = luma_sets_.emplace(f.color_in.view, s).first;
            }
            luma_.bind(f.cmd, VK_NULL_HANDLE, lit->second);
            vkCmdDispatch(f.cmd, div_up(e.width, 8), div_up(e.height, 8), 1);
            compute_barrier(f.cmd);
        }
        for (uint32_t l = 0; l < reduce_sets_.size(); ++l) {
            reduce_.bind(f.cmd, VK_NULL_HANDLE, reduce_sets_[l]);
            vkCmdDispatch(f.cmd, div_up(std::max(1u, e.width >> (l + 1)), 8),
                          div_up(std::max(1u, e.height >> (l + 1)), 8), 1);
            compute_barrier(f.cmd);
        }
        const auto key = std::make_tuple(f.color_in.view, f.rate.view, f.color_out.view);
        auto cit = contrast_sets_.find(key);
        if (cit == contrast_sets_.end()) {
            VkDescriptorSet s = contrast_.allocate_set();
            DescriptorWriter(device_, s)
                .storage_image(0, f.color_in.view)
                .storage_image(1, f.rate.view)
                .sampled_image(2, pyramid_.view(), sampler_.get())
                .storage_image(3, f.color_out.view)
                .commit();
            cit = contrast_sets_.emplace(key, s).first;
        }
        contrast_.bind(f.cmd, VK_NULL_HANDLE, cit->second, &push_, sizeof(push_));
        vkCmdDispatch(f.cmd, div_up(e.width, 8), div_up(e.height, 8), 1);
    }

private:
    VkDevice device_ = VK_NULL_HANDLE;
    LinearClampSampler sampler_;
    ContrastPush push_{};
    Image pyramid_;
    ComputePipeline luma_, reduce_, contrast_;
    std::vector<VkDescriptorSet> reduce_sets_;
    std::map<VkImageView, VkDescriptorSet> luma_sets_;
    std::map<std::tuple<VkImageView, VkImageView, VkImageView>, VkDescriptorSet> contrast_sets_;
};

}  // namespace

std::unique_ptr<PostPass> make_contrast_pass() { return std::make_unique<ContrastPass>(); }

}  // namespace fovea::vk
