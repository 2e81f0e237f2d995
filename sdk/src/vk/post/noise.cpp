// Post pass "noise": Tariq 2022's Gabor-noise enhancement (after TAA) as four compute stages:
// display luminance + Gaussian pyramid G0..G3 (enhance_luma, enhance_reduce), the level-3 Sobel
// and min/max field (enhance_noise_gradient), per-impulse Gabor parameters on a fixed
// constant-seed grid (enhance_noise_impulses), and the per-pixel sparse convolution added to
// every channel after gamma (enhance_noise_apply). CPU reference: gabor_noise() in
// enhance_model.cpp. Options: noise.impulses (12..64 per kernel, 16), noise.blur_rate
// (arcmin/deg for s_k, s_f from Tariq Table 2, 0.34), noise.sk, noise.sf (override the table),
// noise.list_entries (memory for the synthesis's strip lists, in uint32 entries; 2^20).
// Needs an extent of at least 8×8 (the level-3 pyramid). Called on the host's render thread.
// The synthesis runs at full resolution because the band needs it: F_L is at least the blur's
// cutoff 3/(2πσ), and σ ≤ 1.12 px (S_t ≤ 1) puts that at ≥ 0.43 cycles/px, while F_H/ppd ≥ 0.54
// (Thibos's 20.5 cpd at 30°, ≤ 38 ppd on the desktop and HMD displays) clamps F_H to the pixel
// Nyquist 0.5. Every impulse lies in [0.43, 0.5] cycles/px, above a half-resolution grid's 0.25.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <tuple>

#include "post/enhance_model.hpp"
#include "post_pass.hpp"

namespace fovea::vk {
namespace {

// Level 3 is where Tariq reads orientation and the min/max headroom; the Laplacian levels an
// S_t <= 1 blur selects (l_p < 1.6) are covered by G0..G3 as well.
constexpr uint32_t kPyramidLevels = 4;
// enhance_noise_apply.comp: 8x4-pixel strips per 16x16 tile, and the most strip-list entries
// (uint32) one chunk of its dispatch may use by default (noise.list_entries): 4 MB.
constexpr uint32_t kStrips = 8;
constexpr double kListBudget = 1u << 20;

// Mirrors shaders/enhance_noise_push.glsl.
struct NoisePush {
    float display_size_px[2];
    float display_half_tan[2];
    float gaze_px[2];
    float ppd;
    float s_k;
    float s_f;
    float attenuation_p;
    float radius;
    float bandwidth;
    float norm;
    int32_t per_cell;
    int32_t cells_x;
    int32_t cells_y;
    uint32_t seed;
    int32_t group_offset_x;
    int32_t group_offset_y;
    int32_t chunk_groups_x;
};

// Pixels per degree at the display centre, as EyeDisplay::pixels_per_degree() computes it
// (fovea_pixel_size_deg at the centre); 0 when the frame carries no display.
float centre_pixels_per_degree(const FrameUniforms& u) {
    if (!(u.display_half_tan[0] > 0.0f && u.display_half_tan[1] > 0.0f)) return 0.0f;
    const float sx = u.display_size_px[0] * 0.5f / u.display_half_tan[0];
    const float sy = u.display_size_px[1] * 0.5f / u.display_half_tan[1];
    return 1.0f / (std::max(1.0f / sx, 1.0f / sy) * 57.29577951308232f);
}

class NoisePass final : public PostPass {
public:
    Result<void> init(const ModuleContext& ctx) override {
        device_ = ctx.device.device();
        const VkExtent2D e = ctx.extent;
        if (e.width < 8 || e.height < 8) return make_error("noise pass needs at least 8x8 pixels");
        const int impulses = int(ctx.option_number("noise.impulses", 16));
        if (impulses < 12 || impulses > 64)
            return make_error("noise.impulses must be in [12, 64] (Tariq 2022 §6.3)");
        const post::EnhanceCalibration cal =
            post::calibration_for_blur_rate(float(ctx.option_number("noise.blur_rate", 0.34)));
        params_.impulses_per_kernel = impulses;
        params_.s_k = float(ctx.option_number("noise.sk", cal.s_k));
        params_.s_f = float(ctx.option_number("noise.sf", cal.s_f));
        if (!(params_.s_k >= 0.0f && params_.s_k < 1e3f))
            return make_error("noise.sk out of range");
        if (!(params_.s_f > 0.0f && params_.s_f < 1e3f)) return make_error("noise.sf out of range");

        const float r = post::gabor_radius(params_.kernel_bandwidth);
        const int per_cell = post::impulses_per_cell(impulses);
        const float a = params_.kernel_bandwidth;
        // enhance_noise_apply.comp lists a 4x4 block of cells (≤ 20 impulses each) per 16x16
        // tile, which holds only while a tile spans at most 2x2 home cells.
        if (!(r >= 15.0f) || per_cell > 20)
            return make_error("noise kernel radius must be >= 15 px with <= 20 impulses per cell");
        // Cells cover every pixel's 3×3 neighbourhood: indices −1 .. floor((w − ½)/r) + 1.
        push_.cells_x = int32_t(std::floor((float(e.width) - 0.5f) / r)) + 3;
        push_.cells_y = int32_t(std::floor((float(e.height) - 0.5f) / r)) + 3;
        push_.radius = r;
        push_.bandwidth = a;
        push_.norm = 1.0f / std::sqrt(float(per_cell) / (r * r) / 3.0f / (4.0f * a * a));
        push_.per_cell = per_cell;
        push_.s_k = params_.s_k;
        push_.s_f = params_.s_f;
        push_.attenuation_p = params_.attenuation_p;
        push_.seed = params_.seed;

        const VkImageUsageFlags usage = VK_IMAGE_USAGE_STORAGE_BIT;
        pyramid_ = Image(ctx.device, e, VK_FORMAT_R32_SFLOAT, usage, kPyramidLevels);
        field_ = Image(ctx.device, {std::max(1u, e.width >> 3), std::max(1u, e.height >> 3)},
                       VK_FORMAT_R32G32B32A32_SFLOAT, usage);
        const VkDeviceSize cells = VkDeviceSize(push_.cells_x) * VkDeviceSize(push_.cells_y);
        const uint64_t texel_limit = ctx.device.properties().limits.maxTexelBufferElements;
        // The strip lists hold a slot in 28 bits (enhance_noise_apply.comp).
        if (uint64_t(cells) * uint64_t(per_cell) > std::min<uint64_t>(texel_limit, 1u << 28))
            return make_error("noise: " + std::to_string(cells * per_cell) +
                              " impulses exceed this device's maxTexelBufferElements (" +
                              std::to_string(texel_limit) +
                              "); use fewer noise.impulses or a smaller image");
        // Written as SSBOs by the impulse stage, read as texel buffers by the synthesis.
        const VkBufferUsageFlags both =
            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT;
        impulses_ = Buffer(ctx.device, cells * per_cell * 16, both, false);
        amplitudes_ = Buffer(ctx.device, cells * per_cell * 4, both, false);
        cell_peaks_ = Buffer(ctx.device, cells * 4, both, false);
        impulse_texels_ = texel_view(ctx.device, impulses_, VK_FORMAT_R32G32B32A32_SFLOAT, 16);
        amplitude_texels_ = texel_view(ctx.device, amplitudes_, VK_FORMAT_R32_SFLOAT, 4);
        peak_texels_ = texel_view(ctx.device, cell_peaks_, VK_FORMAT_R32_SFLOAT, 4);
        // The apply stage's strip lists: one per 8x4 strip of a 16x16 tile, room for every
        // impulse of its 4x4 block of cells. The tiles are dispatched in chunks so the lists
        // stay within a few MB and within the device's texel-buffer limit.
        const uint32_t per_group = kStrips * 16 * uint32_t(per_cell);
        const double entries = ctx.option_number("noise.list_entries", kListBudget);
        if (!(entries >= 1.0 && entries < 4294967296.0))
            return make_error("noise.list_entries must be in [1, 2^32)");
        const uint64_t budget = std::min<uint64_t>(uint64_t(entries), texel_limit);
        groups_ = {div_up(e.width, 16), div_up(e.height, 16)};
        chunk_.width = uint32_t(std::clamp<uint64_t>(budget / per_group, 1, groups_.width));
        chunk_.height = uint32_t(
            std::clamp<uint64_t>(budget / (uint64_t(per_group) * chunk_.width), 1, groups_.height));
        strip_lists_ =
            Buffer(ctx.device, VkDeviceSize(chunk_.width) * chunk_.height * per_group * 4,
                   VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT, false);
        strip_list_texels_ = texel_view(ctx.device, strip_lists_, VK_FORMAT_R32_UINT, 4);

        const Binding img{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};
        const Binding buf{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};
        const Binding texels{VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER};
        const Binding luma_b[] = {img, img};
        const Binding red_b[] = {img, img};
        const Binding grad_b[] = {img, img, img};
        const Binding imp_b[] = {img, img, img, img, img, img, buf, buf, buf};
        const Binding lists{VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER};
        const Binding app_b[] = {img, img, texels, texels, texels, lists};
        luma_ = ctx.builtin_pipeline("enhance_luma.comp", luma_b, 0, false);
        reduce_ = ctx.builtin_pipeline("enhance_reduce.comp", red_b, 0, false);
        gradient_ = ctx.builtin_pipeline("enhance_noise_gradient.comp", grad_b, 0, false);
        impulse_ =
            ctx.builtin_pipeline("enhance_noise_impulses.comp", imp_b, sizeof(NoisePush), false);
        apply_ = ctx.builtin_pipeline("enhance_noise_apply.comp", app_b, sizeof(NoisePush), false);
        for (uint32_t l = 0; l + 1 < kPyramidLevels; ++l) {
            VkDescriptorSet s = reduce_.allocate_set();
            DescriptorWriter(device_, s)
                .storage_image(0, pyramid_.mip_view(l))
                .storage_image(1, pyramid_.mip_view(l + 1))
                .commit();
            reduce_sets_.push_back(s);
        }
        gradient_set_ = gradient_.allocate_set();
        DescriptorWriter(device_, gradient_set_)
            .storage_image(0, pyramid_.mip_view(0))
            .storage_image(1, pyramid_.mip_view(3))
            .storage_image(2, field_.view())
            .commit();
        return {};
    }

    VkImageView display_luma_target() const override { return pyramid_.mip_view(0); }

    void record(const PostFrame& f) override {
        const VkExtent2D e = f.color_in.extent;
        NoisePush push = push_;
        std::copy_n(f.uniforms.display_size_px, 2, push.display_size_px);
        std::copy_n(f.uniforms.display_half_tan, 2, push.display_half_tan);
        std::copy_n(f.uniforms.gaze_px, 2, push.gaze_px);
        push.ppd = centre_pixels_per_degree(f.uniforms);

        if (!f.display_luma_ready) {
            luma_.bind(f.cmd, VK_NULL_HANDLE, luma_set(f.color_in.view));
            vkCmdDispatch(f.cmd, div_up(e.width, 8), div_up(e.height, 8), 1);
            compute_barrier(f.cmd);
        }
        for (uint32_t l = 0; l < reduce_sets_.size(); ++l) {
            reduce_.bind(f.cmd, VK_NULL_HANDLE, reduce_sets_[l]);
            vkCmdDispatch(f.cmd, div_up(std::max(1u, e.width >> (l + 1)), 8),
                          div_up(std::max(1u, e.height >> (l + 1)), 8), 1);
            compute_barrier(f.cmd);
        }
        gradient_.bind(f.cmd, VK_NULL_HANDLE, gradient_set_);
        vkCmdDispatch(f.cmd, div_up(std::max(1u, e.width >> 3), 8),
                      div_up(std::max(1u, e.height >> 3), 8), 1);
        compute_barrier(f.cmd);
        impulse_.bind(f.cmd, VK_NULL_HANDLE, impulse_set(f.rate.view), &push, sizeof(push));
        vkCmdDispatch(f.cmd, div_up(uint32_t(push.cells_x * push.cells_y), 64), 1, 1);
        compute_barrier(f.cmd);
        const VkDescriptorSet set = apply_set(f.color_in.view, f.color_out.view);
        for (uint32_t y = 0; y < groups_.height; y += chunk_.height) {
            for (uint32_t x = 0; x < groups_.width; x += chunk_.width) {
                if (x + y > 0) compute_barrier(f.cmd);  // the chunks share the strip lists
                push.group_offset_x = int32_t(x);
                push.group_offset_y = int32_t(y);
                push.chunk_groups_x = int32_t(std::min(chunk_.width, groups_.width - x));
                apply_.bind(f.cmd, VK_NULL_HANDLE, set, &push, sizeof(push));
                vkCmdDispatch(f.cmd, uint32_t(push.chunk_groups_x),
                              std::min(chunk_.height, groups_.height - y), 1);
            }
        }
    }

private:
    // Descriptor sets per bound view, made once: the Foveator alternates a few images.
    VkDescriptorSet luma_set(VkImageView colour) {
        auto it = luma_sets_.find(colour);
        if (it != luma_sets_.end()) return it->second;
        VkDescriptorSet s = luma_.allocate_set();
        DescriptorWriter(device_, s)
            .storage_image(0, colour)
            .storage_image(1, pyramid_.mip_view(0))
            .commit();
        return luma_sets_.emplace(colour, s).first->second;
    }

    VkDescriptorSet impulse_set(VkImageView rate) {
        auto it = impulse_sets_.find(rate);
        if (it != impulse_sets_.end()) return it->second;
        VkDescriptorSet s = impulse_.allocate_set();
        DescriptorWriter(device_, s)
            .storage_image(0, rate)
            .storage_image(1, pyramid_.mip_view(0))
            .storage_image(2, pyramid_.mip_view(1))
            .storage_image(3, pyramid_.mip_view(2))
            .storage_image(4, pyramid_.mip_view(3))
            .storage_image(5, field_.view())
            .storage_buffer(6, impulses_)
            .storage_buffer(7, amplitudes_)
            .storage_buffer(8, cell_peaks_)
            .commit();
        return impulse_sets_.emplace(rate, s).first->second;
    }

    VkDescriptorSet apply_set(VkImageView in, VkImageView out) {
        const auto key = std::make_pair(in, out);
        auto it = apply_sets_.find(key);
        if (it != apply_sets_.end()) return it->second;
        VkDescriptorSet s = apply_.allocate_set();
        DescriptorWriter(device_, s)
            .storage_image(0, in)
            .storage_image(1, out)
            .uniform_texel_buffer(2, impulse_texels_.get())
            .uniform_texel_buffer(3, amplitude_texels_.get())
            .uniform_texel_buffer(4, peak_texels_.get())
            .storage_texel_buffer(5, strip_list_texels_.get())
            .commit();
        return apply_sets_.emplace(key, s).first->second;
    }

    VkDevice device_ = VK_NULL_HANDLE;
    post::NoiseParams params_;
    NoisePush push_{};
    Image pyramid_, field_;
    Buffer impulses_, amplitudes_, cell_peaks_;
    UniqueBufferView impulse_texels_, amplitude_texels_, peak_texels_;
    Buffer strip_lists_;
    VkExtent2D groups_{};  // the apply stage's 16x16 tiles
    VkExtent2D chunk_{};   // tiles per dispatch of the apply stage
    UniqueBufferView strip_list_texels_;
    ComputePipeline luma_, reduce_, gradient_, impulse_, apply_;
    std::vector<VkDescriptorSet> reduce_sets_;
    VkDescriptorSet gradient_set_ = VK_NULL_HANDLE;
    std::map<VkImageView, VkDescriptorSet> luma_sets_;
    std::map<VkImageView, VkDescriptorSet> impulse_sets_;
    std::map<std::pair<VkImageView, VkImageView>, VkDescriptorSet> apply_sets_;
};

}  // namespace

std::unique_ptr<PostPass> make_noise_pass() { return std::make_unique<NoisePass>(); }

}  // namespace fovea::vk
