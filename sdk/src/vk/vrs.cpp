#include "fovea/vk/vrs.hpp"

#include <cmath>

#include "gpu.hpp"
#include "shaders.hpp"

namespace fovea::vk {
namespace {

// Matches VrsPush in shaders/vrs_rate.comp (push-constant std430-like offsets).
struct VrsPush {
    float display[4];  // size_px, half_tan
    float acuity[8];
    float gaze_px[2];
    float texel[2];
};
static_assert(sizeof(VrsPush) == 64);

}  // namespace

struct VrsAttachment::Impl {
    const Device* device = nullptr;
    EyeDisplay display;
    Image image;
    ComputePipeline pipeline;
    VkDescriptorSet set = VK_NULL_HANDLE;
    uint32_t tw = 16, th = 16;
};

VrsAttachment::VrsAttachment(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
VrsAttachment::VrsAttachment(VrsAttachment&&) noexcept = default;
VrsAttachment& VrsAttachment::operator=(VrsAttachment&&) noexcept = default;
VrsAttachment::~VrsAttachment() = default;

VrsSupport VrsAttachment::supported(const Device& device) { return device.vrs_support(); }

Result<VrsAttachment> VrsAttachment::create(const Device& device, const EyeDisplay& display,
                                            uint32_t texel_w, uint32_t texel_h,
                                            bool allow_unsupported) {
    const VrsSupport s = device.vrs_support();
    if (!s.supported && !allow_unsupported)
        return make_error("fragment shading rate attachments unsupported: " + s.reason);
    if (display.width_px == 0 || display.height_px == 0)
        return make_error("VrsAttachment: display size must be at least 1x1");
    try {
        auto impl = std::make_unique<Impl>();
        impl->device = &device;
        impl->display = display;
        impl->tw = texel_w ? texel_w : s.texel_width;
        impl->th = texel_h ? texel_h : s.texel_height;
        VkImageUsageFlags usage = VK_IMAGE_USAGE_STORAGE_BIT;
        if (s.supported) usage |= VK_IMAGE_USAGE_FRAGMENT_SHADING_RATE_ATTACHMENT_BIT_KHR;
        impl->image = Image(device, {div_up(display.width_px, impl->tw),
                                     div_up(display.height_px, impl->th)},
                            VK_FORMAT_R8_UINT, usage);
        const Binding b[] = {{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}};
        impl->pipeline = ComputePipeline(device, shader_spirv("vrs_rate.comp"), VK_NULL_HANDLE, b,
                                         sizeof(VrsPush));
        impl->set = impl->pipeline.allocate_set();
        DescriptorWriter(device.device(), impl->set).storage_image(0, impl->image.view()).commit();
        return VrsAttachment(std::move(impl));
    } catch (const VkError& e) {
        return make_error(std::string("VrsAttachment: ") + e.what());
    }
}

void VrsAttachment::record(VkCommandBuffer cmd, const AcuityParams& a, const ResolvedGaze& g) {
    Impl& m = *impl_;
    constexpr double kDegToRad = 0.017453292519943295;
    VrsPush p{};
    p.display[0] = static_cast<float>(m.display.width_px);
    p.display[1] = static_cast<float>(m.display.height_px);
    p.display[2] = static_cast<float>(std::tan(m.display.fov_h_deg * 0.5 * kDegToRad));
    p.display[3] = static_cast<float>(std::tan(m.display.fov_v_deg * 0.5 * kDegToRad));
    const float acuity[8] = {a.mar_slope,   a.mar_omega0, a.foveal_radius_deg,
                             a.transition_deg, g.margin_deg, a.max_rate,
                             static_cast<float>(m.tw), 0.f};
    for (int i = 0; i < 8; ++i) p.acuity[i] = acuity[i];
    p.gaze_px[0] = g.x_px;
    p.gaze_px[1] = g.y_px;
    p.texel[0] = static_cast<float>(m.tw);
    p.texel[1] = static_cast<float>(m.th);
    m.pipeline.bind(cmd, VK_NULL_HANDLE, m.set, &p, sizeof(p));
    vkCmdDispatch(cmd, div_up(m.image.extent().width, 8), div_up(m.image.extent().height, 8), 1);
    compute_barrier(cmd);
}

const ImageRef& VrsAttachment::image() const { return impl_->image.ref(); }
uint32_t VrsAttachment::texel_width() const { return impl_->tw; }
uint32_t VrsAttachment::texel_height() const { return impl_->th; }

}  // namespace fovea::vk
