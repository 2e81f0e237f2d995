// Path 3's hardware rate images (IntegrationPath::kRateImage), both from the acuity model the
// module's own methods use:
// - VrsAttachment: a VK_KHR_fragment_shading_rate attachment (R8_UINT, one texel per
//   texel_width x texel_height pixels, value (log2 w << 2) | log2 h).
// - DensityMap: a VK_EXT_fragment_density_map (R8G8_UNORM, one texel per texel x texel pixels,
//   density 1 / rate per axis, stored as floor(255 / rate) / 255 so the area it implies is never
//   below the rate).
// Offered where the device supports them; elsewhere (lavapipe) supported() says why not, and the
// image can still be generated as a plain storage image (allow_unsupported: tests read it back).
//
// Render-pass set-up the host needs (record() leaves the image in VK_IMAGE_LAYOUT_GENERAL):
// - VrsAttachment: enable VK_KHR_fragment_shading_rate (attachmentFragmentShadingRate) and set
//   ExternalDevice::fragment_shading_rate_enabled; transition image() to
//   FRAGMENT_SHADING_RATE_ATTACHMENT_OPTIMAL_KHR (src COMPUTE_SHADER / SHADER_WRITE, dst
//   FRAGMENT_SHADING_RATE_ATTACHMENT_BIT_KHR / FRAGMENT_SHADING_RATE_ATTACHMENT_READ_BIT_KHR);
//   chain VkFragmentShadingRateAttachmentInfoKHR{attachment, shadingRateAttachmentTexelSize =
//   {texel_width(), texel_height()}} into the subpass (vkCreateRenderPass2) and set the
//   combiner ops to KEEP, REPLACE (vkCmdSetFragmentShadingRateKHR or the pipeline state), so the
//   attachment's rate applies.
// - DensityMap: enable VK_EXT_fragment_density_map and set fragment_density_map_enabled;
//   transition image() to FRAGMENT_DENSITY_MAP_OPTIMAL_EXT (dst FRAGMENT_DENSITY_PROCESS_BIT_EXT
//   / FRAGMENT_DENSITY_MAP_READ_BIT_EXT) before the render pass begins (the map is read when it
//   begins); chain VkRenderPassFragmentDensityMapCreateInfoEXT into the render pass. Colour,
//   depth and motion attachments created without VK_IMAGE_CREATE_SUBSAMPLED_BIT_EXT come out at
//   full size, as the post chain reads them.
// Threads: create and record on the render thread.
#pragma once

#include <memory>
#include <vector>

#include "fovea/result.hpp"
#include "fovea/vk/acuity.hpp"
#include "fovea/vk/device.hpp"

namespace fovea::vk {

class VrsAttachment {
public:
    // Usable as a fragment shading rate attachment on this device?
    static VrsSupport supported(const Device& device);

    // texel size 0 = the device's maximum attachment texel size (16x16 when unsupported).
    // allow_unsupported: build the image as a storage image even where VRS is missing.
    static Result<VrsAttachment> create(const Device& device, const EyeDisplay& display,
                                        uint32_t texel_w = 0, uint32_t texel_h = 0,
                                        bool allow_unsupported = false);

    VrsAttachment(VrsAttachment&&) noexcept;
    VrsAttachment& operator=(VrsAttachment&&) noexcept;
    VrsAttachment(const VrsAttachment&) = delete;
    VrsAttachment& operator=(const VrsAttachment&) = delete;
    ~VrsAttachment();

    // Records the compute pass that fills the image for this gaze. Leaves it in GENERAL layout.
    void record(VkCommandBuffer cmd, const AcuityParams& acuity, const ResolvedGaze& gaze);
    const ImageRef& image() const;
    uint32_t texel_width() const;
    uint32_t texel_height() const;

private:
    struct Impl;
    explicit VrsAttachment(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

class DensityMap {
public:
    static DensityMapSupport supported(const Device& device);

    // texel 0 = the device's smallest density texel (16 when unsupported); a power of two.
    static Result<DensityMap> create(const Device& device, const EyeDisplay& display,
                                     uint32_t texel = 0, bool allow_unsupported = false);

    DensityMap(DensityMap&&) noexcept;
    DensityMap& operator=(DensityMap&&) noexcept;
    DensityMap(const DensityMap&) = delete;
    DensityMap& operator=(const DensityMap&) = delete;
    ~DensityMap();

    void record(VkCommandBuffer cmd, const AcuityParams& acuity, const ResolvedGaze& gaze);
    const ImageRef& image() const;
    uint32_t texel_size() const;

private:
    struct Impl;
    explicit DensityMap(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

// The density map texels (R8G8, two bytes per texel): floor(255 / rate) per axis.
std::vector<uint8_t> cpu_density_texels(const EyeDisplay& display, const AcuityParams& acuity,
                                        const ResolvedGaze& gaze, uint32_t texel);

}  // namespace fovea::vk
