// Method "adaptive": Stengel et al. 2016 adaptive image-space sampling. Per frame: exposure
// update (Eq. 10) -> sampling probability (Eqs. 1–12) per 2x2 block into a half-resolution map
// -> 3x3 max there (the 5x5 dilation) -> a fixed-pattern threshold appending samples to a
// compacted list -> indirect dispatch shading only those samples -> pull-push fill (Gortler
// 1996). Every pass is straight-line code: llvmpipe pays for both sides of a branch.
// Options (FoveatorConfig::options): adaptive.omega0 (1.1715), adaptive.slope (-2.45),
// adaptive.omega_p (0.02), adaptive.gamma (20), adaptive.t_dark (0.15), adaptive.t_bright (0.9),
// adaptive.rate (0.05), adaptive.exposure_target (0.5), adaptive.depth_step (0.05),
// adaptive.normal_step (0.25), adaptive.albedo_step (0.25), adaptive.light ("0.3,0.8,0.5,1"),
// adaptive.seed (1), adaptive.brightness (1: Eqs. 9–11 on; 0: S = 1), adaptive.features (1: F_O,
// F_H, F_S on; 0: acuity and eye motion only).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <sstream>

#include "../method.hpp"
#include "adaptive_model.hpp"

namespace fovea::vk {
namespace {

struct AdaptivePush {  // shaders/adaptive_common.glsl
    float gaze[2];
    float gaze_ahead[2];
    float eye_motion_px[2];
    float dt;
    float omega0;
    float slope;
    float omega_p;
    float ecc_norm_deg;
    float gamma;
    float t_dark;
    float t_bright;
    float adapt_rate;
    float auto_exposure;
    float gain_depth;
    float gain_normal;
    float gain_albedo;
    int32_t has_history;
    uint32_t seed;
    int32_t level;
    float features;
    float pad;
    float light[4];
};
static_assert(sizeof(AdaptivePush) == 112, "push layout");
static_assert(offsetof(AdaptivePush, light) == 96, "std430: vec4 aligned to 16");

// Pyramid depth: at most 7 pull steps (1/128 resolution) suffice because the ω_p floor (0.02)
// puts ~5 samples in every 16x16 block; the pipelines' descriptor pools hold 8 sets.
constexpr uint32_t kMaxLevels = 8;
constexpr uint32_t kLuminanceLevel = 3;  // Stengel: brightness from a low-resolution frame
// A gaze step faster than this is a saccade: the eye lands and fixates, so the gaze segment and
// eye motion restart there instead of smearing the fovea along the jump (Eq. 5's top speed).
constexpr double kSaccadeDegPerS = 118.0;

class AdaptiveMethod final : public Method {
public:
    Result<void> init(const ModuleContext& ctx) override {
        extent_ = ctx.extent;
        display_ = ctx.config.display;
        p_.omega0 = float(ctx.option_number("adaptive.omega0", 1.1715));
        p_.slope = float(ctx.option_number("adaptive.slope", -2.45));
        p_.omega_p = float(ctx.option_number("adaptive.omega_p", 0.02));
        p_.gamma = float(ctx.option_number("adaptive.gamma", 20.0));
        p_.t_dark = float(ctx.option_number("adaptive.t_dark", 0.15));
        p_.t_bright = float(ctx.option_number("adaptive.t_bright", 0.9));
        p_.adapt_rate = float(ctx.option_number("adaptive.rate", 0.05));
        p_.auto_exposure = float(ctx.option_number("adaptive.exposure_target", 0.5));
        const double depth_step = ctx.option_number("adaptive.depth_step", 0.05);
        const double normal_step = ctx.option_number("adaptive.normal_step", 0.25);
        const double albedo_step = ctx.option_number("adaptive.albedo_step", 0.25);
        if (!(p_.omega_p > 0.0f && p_.omega_p <= 1.0f))
            return make_error("adaptive.omega_p must be in (0, 1]");
        if (!(p_.t_dark > 0.0f) || !(p_.t_bright < 1.0f) || !(depth_step > 0.0) ||
            !(normal_step > 0.0) || !(albedo_step > 0.0))
            return make_error("adaptive: thresholds must be positive and t_bright < 1");
        p_.gain_depth = float(1.0 / depth_step);
        p_.gain_normal = float(1.0 / normal_step);
        p_.gain_albedo = float(1.0 / albedo_step);
        p_.ecc_norm_deg = 0.5f * display_.fov_v_deg;
        p_.seed = uint32_t(ctx.option_number("adaptive.seed", 1.0));
        brightness_ = ctx.option_number("adaptive.brightness", 1.0) != 0.0;
        p_.features = ctx.option_number("adaptive.features", 1.0) != 0.0 ? 1.0f : 0.0f;
        auto light = parse_light(ctx.option("adaptive.light", "0.3,0.8,0.5,1"));
        if (!light) return light.error();
        std::memcpy(p_.light, light->data(), sizeof(p_.light));

        const VkDevice dev = ctx.device.device();
        const VkExtent2D half{std::max(1u, div_up(extent_.width, 2)),
                              std::max(1u, div_up(extent_.height, 2))};
        half_p_ = Image(ctx.device, half, VK_FORMAT_R32_SFLOAT, VK_IMAGE_USAGE_STORAGE_BIT);
        half_dilated_ = Image(ctx.device, half, VK_FORMAT_R32_SFLOAT, VK_IMAGE_USAGE_STORAGE_BIT);
        // A full mip chain is shorter than kMaxLevels on tiny frames.
        levels_ =
            std::min(kMaxLevels,
                     uint32_t(std::floor(std::log2(std::max(extent_.width, extent_.height)))) + 1);
        pyramid_ = Image(ctx.device, extent_, kColorFormat,
                         VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, levels_);
        list_ = Buffer(ctx.device, 16 + 4ull * extent_.width * extent_.height,
                       VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                           VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                       false);
        exposure_ = Buffer(ctx.device, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true);
        const float initial[4] = {1.0f, 0.0f, 0.0f, 0.0f};
        std::memcpy(exposure_.data(), initial, sizeof(initial));

        using B = Binding;
        const B img{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};
        const B buf{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};
        const B exposure_b[] = {img, buf};
        const B prob_b[] = {img, buf, img};
        const B select_b[] = {img, buf};
        const B args_b[] = {buf};
        const B shade_b[] = {buf, img};
        const B two_img[] = {img, img};
        constexpr uint32_t kPush = sizeof(AdaptivePush);
        exposure_pass_ = ctx.builtin_pipeline("adaptive_exposure.comp", exposure_b, kPush, true);
        prob_pass_ = ctx.builtin_pipeline("adaptive_probability.comp", prob_b, kPush, true);
        select_pass_ = ctx.builtin_pipeline("adaptive_select.comp", select_b, kPush, true);
        args_pass_ = ctx.builtin_pipeline("adaptive_args.comp", args_b, 0, true);
        pull_pass_ = ctx.builtin_pipeline("adaptive_pull.comp", two_img, kPush, true);
        const uint32_t not_final[] = {0u};
        const uint32_t final_level[] = {1u};
        push_pass_ = ctx.builtin_pipeline("adaptive_push.comp", two_img, kPush, true, not_final);
        push_final_ = ctx.builtin_pipeline("adaptive_push.comp", two_img, kPush, true, final_level);
        dilate_pass_ = ctx.builtin_pipeline("adaptive_dilate.comp", two_img, 0, false);
        auto shade = ctx.shading_pipeline("adaptive_shade.shade.comp", shade_b, 0);
        if (!shade) return shade.error();
        shade_pass_ = std::move(*shade);

        const VkImageView low = pyramid_.mip_view(std::min(kLuminanceLevel, levels_ - 1));
        exposure_set_ = exposure_pass_.allocate_set();
        DescriptorWriter(dev, exposure_set_)
            .storage_image(0, low)
            .storage_buffer(1, exposure_)
            .commit();
        prob_set_ = prob_pass_.allocate_set();
        DescriptorWriter(dev, prob_set_)
            .storage_image(0, low)
            .storage_buffer(1, exposure_)
            .storage_image(2, half_p_.view())
            .commit();
        dilate_set_ = dilate_pass_.allocate_set();
        DescriptorWriter(dev, dilate_set_)
            .storage_image(0, half_p_.view())
            .storage_image(1, half_dilated_.view())
            .commit();
        select_set_ = select_pass_.allocate_set();
        DescriptorWriter(dev, select_set_)
            .storage_image(0, half_dilated_.view())
            .storage_buffer(1, list_)
            .commit();
        args_set_ = args_pass_.allocate_set();
        DescriptorWriter(dev, args_set_).storage_buffer(0, list_).commit();
        shade_set_ = shade_pass_.allocate_set();
        DescriptorWriter(dev, shade_set_)
            .storage_buffer(0, list_)
            .storage_image(1, pyramid_.mip_view(0))
            .commit();
        for (uint32_t l = 0; l + 1 < levels_; ++l) {
            pull_sets_[l] = pull_pass_.allocate_set();
            DescriptorWriter(dev, pull_sets_[l])
                .storage_image(0, pyramid_.mip_view(l))
                .storage_image(1, pyramid_.mip_view(l + 1))
                .commit();
            push_sets_[l] = (l == 0 ? push_final_ : push_pass_).allocate_set();
            DescriptorWriter(dev, push_sets_[l])
                .storage_image(0, pyramid_.mip_view(l + 1))
                .storage_image(1, pyramid_.mip_view(l))
                .commit();
        }
        return {};
    }

    void record(const MethodFrame& f) override {
        AdaptivePush push = p_;
        const double t = f.inputs.time_s;
        const bool history = has_frame_ && !f.inputs.camera_cut && t > last_time_;
        const double dt = history ? t - last_time_ : 1.0 / 60.0;
        const methods::Vec2f64 g{f.gaze.x_px, f.gaze.y_px};
        methods::Vec2f64 prev = history ? last_gaze_ : g;
        const methods::ScreenFov fov{int(extent_.width), int(extent_.height), display_.fov_h_deg,
                                     display_.fov_v_deg};
        if (methods::eccentricity_deg(g, prev, fov) / dt > kSaccadeDegPerS) prev = g;
        push.gaze[0] = float(g.x);
        push.gaze[1] = float(g.y);
        push.gaze_ahead[0] = float(2.0 * g.x - prev.x);  // §4.1.2: the expected motion ahead
        push.gaze_ahead[1] = float(2.0 * g.y - prev.y);
        push.eye_motion_px[0] = float(g.x - prev.x);
        push.eye_motion_px[1] = float(g.y - prev.y);
        push.dt = float(dt);
        push.has_history = (history && brightness_) ? 1 : 0;
        has_frame_ = true;
        last_time_ = t;
        last_gaze_ = g;

        VkCommandBuffer cmd = f.cmd;
        vkCmdFillBuffer(cmd, list_.get(), 0, 16, 0);
        const VkClearColorValue zero{};
        const VkImageSubresourceRange level0{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        vkCmdClearColorImage(cmd, pyramid_.get(), VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &level0);
        compute_barrier(cmd);

        exposure_pass_.bind(cmd, f.frame_set, exposure_set_, &push, sizeof(push));
        vkCmdDispatch(cmd, 1, 1, 1);
        compute_barrier(cmd);
        const VkExtent2D half = half_p_.extent();
        prob_pass_.bind(cmd, f.frame_set, prob_set_, &push, sizeof(push));
        vkCmdDispatch(cmd, div_up(half.width, 8), div_up(half.height, 8), 1);
        compute_barrier(cmd);
        dilate_pass_.bind(cmd, VK_NULL_HANDLE, dilate_set_);
        vkCmdDispatch(cmd, div_up(half.width, 8), div_up(half.height, 8), 1);
        compute_barrier(cmd);
        select_pass_.bind(cmd, f.frame_set, select_set_, &push, sizeof(push));
        vkCmdDispatch(cmd, div_up(extent_.width, 8), div_up(extent_.height, 8), 1);
        compute_barrier(cmd);
        args_pass_.bind(cmd, f.frame_set, args_set_);
        vkCmdDispatch(cmd, 1, 1, 1);
        indirect_barrier(cmd);
        shade_pass_.bind(cmd, f.frame_set, shade_set_);
        vkCmdDispatchIndirect(cmd, list_.get(), 0);
        compute_barrier(cmd);

        for (uint32_t l = 0; l + 1 < levels_; ++l) {
            push.level = int32_t(l + 1);
            const VkExtent2D e = level_extent(l + 1);
            pull_pass_.bind(cmd, f.frame_set, pull_sets_[l], &push, sizeof(push));
            vkCmdDispatch(cmd, div_up(e.width, 8), div_up(e.height, 8), 1);
            compute_barrier(cmd);
        }
        for (uint32_t l = levels_ - 1; l-- > 0;) {
            push.level = int32_t(l);
            const VkExtent2D e = level_extent(l);
            (l == 0 ? push_final_ : push_pass_)
                .bind(cmd, f.frame_set, push_sets_[l], &push, sizeof(push));
            vkCmdDispatch(cmd, div_up(e.width, 8), div_up(e.height, 8), 1);
            if (l > 0) compute_barrier(cmd);
        }
    }

private:
    static Result<std::array<float, 4>> parse_light(const std::string& text) {
        std::array<float, 4> v{};
        std::stringstream in(text);
        std::string item;
        int n = 0;
        while (std::getline(in, item, ',') && n < 4) {
            char* end = nullptr;
            v[std::size_t(n++)] = std::strtof(item.c_str(), &end);
            if (end == item.c_str()) return make_error("adaptive.light: not a number: " + item);
        }
        const float len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (n != 4 || !(len > 0.0f))
            return make_error("adaptive.light wants 'x,y,z,intensity' with a non-zero direction");
        for (int i = 0; i < 3; ++i) v[std::size_t(i)] /= len;
        return v;
    }

    VkExtent2D level_extent(uint32_t l) const {
        return {std::max(1u, extent_.width >> l), std::max(1u, extent_.height >> l)};
    }

    VkExtent2D extent_{};
    EyeDisplay display_;
    AdaptivePush p_{};
    bool brightness_ = true;
    bool has_frame_ = false;
    double last_time_ = 0.0;
    methods::Vec2f64 last_gaze_;
    Image half_p_;
    Image half_dilated_;
    Image pyramid_;
    Buffer list_;
    Buffer exposure_;
    ComputePipeline exposure_pass_, prob_pass_, select_pass_, args_pass_, shade_pass_;
    ComputePipeline pull_pass_, push_pass_, push_final_, dilate_pass_;
    VkDescriptorSet exposure_set_ = VK_NULL_HANDLE, prob_set_ = VK_NULL_HANDLE;
    VkDescriptorSet select_set_ = VK_NULL_HANDLE, args_set_ = VK_NULL_HANDLE;
    VkDescriptorSet shade_set_ = VK_NULL_HANDLE, dilate_set_ = VK_NULL_HANDLE;
    uint32_t levels_ = kMaxLevels;
    std::array<VkDescriptorSet, kMaxLevels> pull_sets_{};
    std::array<VkDescriptorSet, kMaxLevels> push_sets_{};
};

}  // namespace

std::unique_ptr<Method> make_adaptive_method() { return std::make_unique<AdaptiveMethod>(); }

}  // namespace fovea::vk
