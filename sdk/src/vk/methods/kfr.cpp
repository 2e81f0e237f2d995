// Method "kfr": Meng et al. 2018 kernel foveated rendering. Pass I shades a reduced log-polar
// buffer (σ² fewer texels) from the full-resolution G-buffer — only the texels that land on
// the screen, through a compacted list and an indirect dispatch — a 3x3 Gaussian smooths its
// peripheral columns, pass II maps it back to the screen with anti-aliasing.
// Options: kfr.sigma (1.8), kfr.alpha (4), kfr.literal (0: the study's kernel direction, see
// kfr_model.hpp), kfr.betas ("b1,b2,..": polynomial kernel, overrides alpha).
#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

#include "../method.hpp"
#include "kfr_model.hpp"

namespace fovea::vk {
namespace {

struct KfrPush {  // shaders/kfr_map.glsl
    float gaze[2];
    float lp_size[2];
    float screen[2];
    float log_max_r;
    float exponent;
    int32_t betas;
    float blur_u0;
    float aa_u1;
    float pad;
    float beta[8];
};
static_assert(sizeof(KfrPush) == 80, "push layout");

Result<methods::KfrKernel> kernel_from_options(const ModuleContext& ctx) {
    const std::string betas = ctx.option("kfr.betas", "");
    if (betas.empty()) {
        const double alpha = ctx.option_number("kfr.alpha", 4.0);
        if (!(alpha > 0.0) || alpha > 16.0) return make_error("kfr.alpha must be in (0, 16]");
        return methods::kfr_study_kernel(alpha, ctx.option_number("kfr.literal", 0.0) != 0.0);
    }
    std::vector<double> b{0.0};
    std::stringstream in(betas);
    std::string item;
    while (std::getline(in, item, ',')) {
        char* end = nullptr;
        const double v = std::strtod(item.c_str(), &end);
        if (end == item.c_str()) return make_error("kfr.betas: not a number: '" + item + "'");
        b.push_back(v);
    }
    if (b.size() > 9) return make_error("kfr.betas: at most 8 coefficients (β1..β8)");
    return methods::KfrKernel::polynomial(std::move(b));
}

class KfrMethod final : public Method {
public:
    Result<void> init(const ModuleContext& ctx) override {
        sigma_ = ctx.option_number("kfr.sigma", 1.8);
        if (!(sigma_ >= 1.0) || sigma_ > 8.0) return make_error("kfr.sigma must be in [1, 8]");
        auto kernel = kernel_from_options(ctx);
        if (!kernel) return kernel.error();
        kernel_ = std::move(*kernel);
        extent_ = ctx.extent;
        lp_extent_ = {uint32_t(methods::kfr_buffer_extent(int(extent_.width), sigma_)),
                      uint32_t(methods::kfr_buffer_extent(int(extent_.height), sigma_))};
        lp_ = Image(ctx.device, lp_extent_, kColorFormat,
                    VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT);
        lp_blur_ = Image(ctx.device, lp_extent_, kColorFormat, VK_IMAGE_USAGE_STORAGE_BIT);
        list_ = Buffer(ctx.device, 16 + 4ull * lp_extent_.width * lp_extent_.height,
                       VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                           VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                       false);

        const Binding one_image[] = {{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}};
        const Binding two_images[] = {{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
                                      {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}};
        // KFR_POLY as a specialization constant: the unused kernel is compiled out.
        const uint32_t spec[] = {kernel_.is_power() ? 0u : 1u};
        const Binding list_b[] = {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}};
        const Binding forward_b[] = {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                                     {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}};
        list_pass_ = ctx.builtin_pipeline("kfr_list.comp", list_b, sizeof(KfrPush), false, spec);
        args_pass_ = ctx.builtin_pipeline("kfr_args.comp", list_b, 0, true);
        auto forward =
            ctx.shading_pipeline("kfr_forward.shade.comp", forward_b, sizeof(KfrPush), {}, spec);
        if (!forward) return forward.error();
        forward_ = std::move(*forward);
        blur_ = ctx.builtin_pipeline("kfr_blur.comp", two_images, sizeof(KfrPush), false, spec);
        inverse_ = ctx.builtin_pipeline("kfr_inverse.comp", one_image, sizeof(KfrPush), true, spec);

        const VkDevice dev = ctx.device.device();
        list_set_ = list_pass_.allocate_set();
        DescriptorWriter(dev, list_set_).storage_buffer(0, list_).commit();
        args_set_ = args_pass_.allocate_set();
        DescriptorWriter(dev, args_set_).storage_buffer(0, list_).commit();
        forward_set_ = forward_.allocate_set();
        DescriptorWriter(dev, forward_set_)
            .storage_buffer(0, list_)
            .storage_image(1, lp_.view())
            .commit();
        blur_set_ = blur_.allocate_set();
        DescriptorWriter(dev, blur_set_)
            .storage_image(0, lp_.view())
            .storage_image(1, lp_blur_.view())
            .commit();
        inverse_set_ = inverse_.allocate_set();
        DescriptorWriter(dev, inverse_set_).storage_image(0, lp_blur_.view()).commit();
        return {};
    }

    void record(const MethodFrame& f) override {
        const methods::Vec2d gaze{f.gaze.x_px, f.gaze.y_px};
        const methods::KfrMap map(int(extent_.width), int(extent_.height), int(lp_extent_.width),
                                  int(lp_extent_.height), gaze, kernel_);
        KfrPush push{};
        push.gaze[0] = float(map.gaze().x);
        push.gaze[1] = float(map.gaze().y);
        push.lp_size[0] = float(lp_extent_.width);
        push.lp_size[1] = float(lp_extent_.height);
        push.screen[0] = float(extent_.width);
        push.screen[1] = float(extent_.height);
        push.log_max_r = float(map.log_max_radius());
        push.exponent = float(kernel_.alpha());
        const auto& b = kernel_.betas();
        push.betas = b.empty() ? 0 : int32_t(b.size() - 1);
        for (std::size_t i = 1; i < b.size(); ++i) push.beta[i - 1] = float(b[i]);
        push.blur_u0 = float(blur_start(map));
        // Around the gaze, LP rows are closer than a pixel along the circle for r < h / 2π.
        const methods::Vec2d g = map.gaze();
        push.aa_u1 =
            float(map.forward({g.x + lp_extent_.height / (2.0 * 3.14159265358979), g.y}).x);

        const uint32_t gx = div_up(lp_extent_.width, 8);
        const uint32_t gy = div_up(lp_extent_.height, 8);
        vkCmdFillBuffer(f.cmd, list_.get(), 0, 16, 0);
        const VkClearColorValue zero{};
        const VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        vkCmdClearColorImage(f.cmd, lp_.get(), VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &range);
        compute_barrier(f.cmd);
        list_pass_.bind(f.cmd, VK_NULL_HANDLE, list_set_, &push, sizeof(push));
        vkCmdDispatch(f.cmd, gx, gy, 1);
        compute_barrier(f.cmd);
        args_pass_.bind(f.cmd, f.frame_set, args_set_);
        vkCmdDispatch(f.cmd, 1, 1, 1);
        indirect_barrier(f.cmd);
        forward_.bind(f.cmd, f.frame_set, forward_set_, &push, sizeof(push));
        vkCmdDispatchIndirect(f.cmd, list_.get(), 0);
        compute_barrier(f.cmd);
        blur_.bind(f.cmd, VK_NULL_HANDLE, blur_set_, &push, sizeof(push));
        vkCmdDispatch(f.cmd, gx, gy, 1);
        compute_barrier(f.cmd);
        inverse_.bind(f.cmd, f.frame_set, inverse_set_, &push, sizeof(push));
        vkCmdDispatch(f.cmd, div_up(extent_.width, 8), div_up(extent_.height, 8), 1);
    }

private:
    // The Gaussian smooths only the right part of the buffer (§3.1), where every LP texel spans
    // more than a screen pixel radially; the fovea keeps its detail. (With the study kernel the
    // first few columns, r < 2 px, are coarse too: they are not "the periphery".)
    static double blur_start(const methods::KfrMap& map) {
        int u = map.buffer_width();
        while (u > 0 && map.radial_scale(u - 0.5) > 1.0) --u;
        return u;
    }

    double sigma_ = 1.8;
    methods::KfrKernel kernel_ = methods::kfr_study_kernel(4.0);
    VkExtent2D extent_{};
    VkExtent2D lp_extent_{};
    Image lp_;
    Image lp_blur_;
    Buffer list_;
    ComputePipeline list_pass_;
    ComputePipeline args_pass_;
    ComputePipeline forward_;
    ComputePipeline blur_;
    ComputePipeline inverse_;
    VkDescriptorSet list_set_ = VK_NULL_HANDLE;
    VkDescriptorSet args_set_ = VK_NULL_HANDLE;
    VkDescriptorSet forward_set_ = VK_NULL_HANDLE;
    VkDescriptorSet blur_set_ = VK_NULL_HANDLE;
    VkDescriptorSet inverse_set_ = VK_NULL_HANDLE;
};

}  // namespace

std::unique_ptr<Method> make_kfr_method() { return std::make_unique<KfrMethod>(); }

}  // namespace fovea::vk
