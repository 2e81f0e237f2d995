#include "fovea/vk/vrs.hpp"

#include <cmath>

#include "gpu.hpp"
#include "shaders.hpp"

namespace fovea::vk {
namespace {

// Matches RatePush in shaders/vrs_rate.comp and shaders/density_map.comp.
struct RatePush {
    float display[4];  // size_px, half_tan
    float acuity[8];
    float gaze_px[2];
    float texel[2];
};
static_assert(sizeof(RatePush) == 64);

}  // namespace

// A texel image of the acuity model's tile rates (both rate-image kinds): image, compute pass.
struct RateImagePass {
    EyeDisplay display;
    Image image;
    ComputePipeline pipeline;
    VkDescriptorSet set = VK_NULL_HANDLE;
    uint32_t tw = 16, th = 16;

    void build(const Device& device, const EyeDisplay& d, VkFormat format, VkImageUsageFlags usage,
               const char* shader, uint32_t texel_w, uint32_t texel_h) {
        display = d;
        tw = texel_w;
        th = texel_h;
        image = Image(device, {div_up(d.width_px, tw), div_up(d.height_px, th)}, format, usage);
        const Binding b[] = {{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}};
        pipeline =
            ComputePipeline(device, shader_spirv(shader), VK_NULL_HANDLE, b, sizeof(RatePush));
        set = pipeline.allocate_set();
        DescriptorWriter(device.device(), set).storage_image(0, image.view()).commit();
    }

    void record(VkCommandBuffer cmd, const AcuityParams& a, const ResolvedGaze& g) const {
        constexpr double kDegToRad = 0.017453292519943295;
        RatePush p{};
        p.display[0] = static_cast<float>(display.width_px);
        p.display[1] = static_cast<float>(display.height_px);
        p.display[2] = static_cast<float>(std::tan(display.fov_h_deg * 0.5 * kDegToRad));
        p.display[3] = static_cast<float>(std::tan(display.fov_v_deg * 0.5 * kDegToRad));
        const float acuity[8] = {
            a.mar_slope,  a.mar_omega0, a.foveal_radius_deg,    a.transition_deg,
            g.margin_deg, a.max_rate,   static_cast<float>(tw), 0.f};
        for (int i = 0; i < 8; ++i) p.acuity[i] = acuity[i];
        p.gaze_px[0] = g.x_px;
        p.gaze_px[1] = g.y_px;
        p.texel[0] = static_cast<float>(tw);
        p.texel[1] = static_cast<float>(th);
        pipeline.bind(cmd, VK_NULL_HANDLE, set, &p, sizeof(p));
        vkCmdDispatch(cmd, div_up(image.extent().width, 8), div_up(image.extent().height, 8), 1);
        compute_barrier(cmd);
    }
};

struct VrsAttachment::Impl : RateImagePass {};
struct DensityMap::Impl : RateImagePass {};

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
        VkImageUsageFlags usage = VK_IMAGE_USAGE_STORAGE_BIT;
        if (s.supported) usage |= VK_IMAGE_USAGE_FRAGMENT_SHADING_RATE_ATTACHMENT_BIT_KHR;
        impl->build(device, display, VK_FORMAT_R8_UINT, usage, "vrs_rate.comp",
                    texel_w ? texel_w : s.texel_width, texel_h ? texel_h : s.texel_height);
        return VrsAttachment(std::move(impl));
    } catch (const VkError& e) { return make_error(std::string("VrsAttachment: ") + e.what()); }
}

void VrsAttachment::record(VkCommandBuffer cmd, const AcuityParams& a, const ResolvedGaze& g) {
    impl_->record(cmd, a, g);
}
const ImageRef& VrsAttachment::image() const { return impl_->image.ref(); }
uint32_t VrsAttachment::texel_width() const { return impl_->tw; }
uint32_t VrsAttachment::texel_height() const { return impl_->th; }

DensityMap::DensityMap(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
DensityMap::DensityMap(DensityMap&&) noexcept = default;
DensityMap& DensityMap::operator=(DensityMap&&) noexcept = default;
DensityMap::~DensityMap() = default;

DensityMapSupport DensityMap::supported(const Device& device) {
    return device.density_map_support();
}

Result<DensityMap> DensityMap::create(const Device& device, const EyeDisplay& display,
                                      uint32_t texel, bool allow_unsupported) {
    const DensityMapSupport s = device.density_map_support();
    if (!s.supported && !allow_unsupported)
        return make_error("fragment density maps unsupported: " + s.reason);
    if (display.width_px == 0 || display.height_px == 0)
        return make_error("DensityMap: display size must be at least 1x1");
    if (texel == 0) texel = s.min_texel;
    if (texel == 0 || (texel & (texel - 1)) != 0)
        return make_error("DensityMap: the texel size must be a power of two");
    if (s.supported && (texel < s.min_texel || texel > s.max_texel))
        return make_error("DensityMap: texel " + std::to_string(texel) + " outside the device's " +
                          std::to_string(s.min_texel) + ".." + std::to_string(s.max_texel));
    try {
        auto impl = std::make_unique<Impl>();
        VkImageUsageFlags usage = VK_IMAGE_USAGE_STORAGE_BIT;
        if (s.supported) usage |= VK_IMAGE_USAGE_FRAGMENT_DENSITY_MAP_BIT_EXT;
        impl->build(device, display, VK_FORMAT_R8G8_UNORM, usage, "density_map.comp", texel, texel);
        return DensityMap(std::move(impl));
    } catch (const VkError& e) { return make_error(std::string("DensityMap: ") + e.what()); }
}

void DensityMap::record(VkCommandBuffer cmd, const AcuityParams& a, const ResolvedGaze& g) {
    impl_->record(cmd, a, g);
}
const ImageRef& DensityMap::image() const { return impl_->image.ref(); }
uint32_t DensityMap::texel_size() const { return impl_->tw; }

std::vector<uint8_t> cpu_density_texels(const EyeDisplay& d, const AcuityParams& a,
                                        const ResolvedGaze& g, uint32_t texel) {
    const std::vector<uint8_t> rates = cpu_rate_tiles(d, a, g, texel, texel);
    std::vector<uint8_t> out(rates.size() * 2);
    for (size_t i = 0; i < rates.size(); ++i)
        out[i * 2] = out[i * 2 + 1] = static_cast<uint8_t>(255 / rates[i]);
    return out;
}

}  // namespace fovea::vk
