// The images a host renders itself on the host-shaded paths (IntegrationPath::kForwardLayers,
// kRateImage, kPostOnly; foveator.hpp): colour, depth and motion, either into the module's own
// images (HostTargets) or into the host's, which the module then reads in their place
// (HostFrameImages). Plain data; see the conventions in fovea/vk/projection.hpp.
#pragma once

#include <array>

#include <vulkan/vulkan.h>

#include "fovea/vk/device.hpp"

namespace fovea::vk {

// The module's images for one view. Formats: colour kHostColorFormat (linear HDR, a ignored),
// depth kHostDepthFormat (0..1, 1 = far/background), motion kHostMotionFormat (pixels of this
// view, current - previous; projection.hpp). VK_IMAGE_LAYOUT_GENERAL throughout; usage colour
// attachment, storage, sampled, transfer src/dst, so the host renders all three as colour
// attachments of its own render pass (depth written as a colour output beside the depth
// attachment its depth test uses), or fills them by compute or copies.
struct HostTargets {
    VkExtent2D extent{0, 0};
    ImageRef color, depth, motion;
};

inline constexpr VkFormat kHostColorFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
inline constexpr VkFormat kHostDepthFormat = VK_FORMAT_R32_SFLOAT;
inline constexpr VkFormat kHostMotionFormat = VK_FORMAT_R16G16_SFLOAT;
inline constexpr VkImageUsageFlags kHostTargetUsage =
    VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
    VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;

// One of the host's own images, read (texelFetch through a sampler) in place of a target.
struct HostImage {
    VkImageView view = VK_NULL_HANDLE;  // 2D, 1 mip level, 1 layer; image has SAMPLED usage
    // The layout the image is in when the recorded frame runs; the module leaves it there.
    VkImageLayout layout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
};

enum class DepthMapping {
    kForward,   // 0 at the near plane .. 1 at the far plane (the module's own convention)
    kReversed,  // reverse-Z: 1 near .. 0 far; the module reads 1 - d
};

// A view's colour, depth and motion in the host's own images, e.g. an engine's HDR target and
// its depth buffer. The module copies them into its targets in one compute pass at the start of
// record() (sampled reads: any sampleable format, including a depth aspect view of D32_SFLOAT
// or D24_UNORM_S8_UINT); extent must equal the targets'. Set per frame in FrameInputs.
struct HostFrameImages {
    VkExtent2D extent{0, 0};
    HostImage color;   // rgb linear (an sRGB format decodes on read)
    HostImage depth;   // see depth_mapping
    HostImage motion;  // rg; view VK_NULL_HANDLE: no motion (a still camera and scene)
    DepthMapping depth_mapping = DepthMapping::kForward;
    // Multiplies the host's motion into pixels, current - previous: {1, 1} when it is already,
    // {width, height} for UV units, negated for previous - current.
    std::array<float, 2> motion_scale{1.f, 1.f};
};

}  // namespace fovea::vk
