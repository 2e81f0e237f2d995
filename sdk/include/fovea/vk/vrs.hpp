// The hardware path: the same rate model written into a VK_KHR_fragment_shading_rate attachment
// (R8_UINT, one texel per texel_width x texel_height pixels, value (log2 w << 2) | log2 h).
// Offered when the device supports attachment shading rates; elsewhere (lavapipe) supported()
// says why not, and the image can still be generated (for tests) as a plain storage image.
// Threads: create and record on the render thread.
#pragma once

#include <memory>

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

    // Records the compute pass that fills the image for this gaze. Leaves it in GENERAL layout
    // (transition to FRAGMENT_SHADING_RATE_ATTACHMENT_OPTIMAL_KHR before use as an attachment).
    void record(VkCommandBuffer cmd, const AcuityParams& acuity, const ResolvedGaze& gaze);
    const ImageRef& image() const;
    uint32_t texel_width() const;
    uint32_t texel_height() const;

private:
    struct Impl;
    explicit VrsAttachment(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace fovea::vk
