// The G-buffer contract between the host and the foveation module. The module owns the images
// (Foveator::gbuffer()); the host writes all of them every frame at full resolution (visibility
// stays at full rate, Patney 2016 §4) before recording Foveator::record(), with storage-image
// writes from compute or as colour attachments (the demo rasterizes its scene). They stay in
// VK_IMAGE_LAYOUT_GENERAL.
//
//  image     format               contents
//  position  R32G32B32A32_SFLOAT  xyz world position, w view distance (0 = background/sky)
//  normal    R16G16B16A16_SFLOAT  xyz unit world normal, w host-defined
//  albedo    R8G8B8A8_UNORM       rgb linear albedo, a host-defined
//  material  R16G16B16A16_SFLOAT  x material id (an integer; coarse pixels never blend ids),
//                                 yzw host-defined (the demo: roughness, metalness, pattern)
//  depth     R32_SFLOAT           0..1, 1 = far/background (TAA disocclusion)
//  motion    R16G16_SFLOAT        screen motion in pixels, current - previous position
// Shaders read them through shaders/fovea_frame.glsl (fovea_load_gsample).
#pragma once

#include <array>

#include <vulkan/vulkan.h>

#include "fovea/vk/device.hpp"

namespace fovea::vk {

enum class GBufferImage { kPosition, kNormal, kAlbedo, kMaterial, kDepth, kMotion };
inline constexpr int kGBufferImageCount = 6;

inline constexpr std::array<VkFormat, kGBufferImageCount> kGBufferFormats = {
    VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_R8G8B8A8_UNORM,
    VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_R32_SFLOAT,          VK_FORMAT_R16G16_SFLOAT};

// Usage of every G-buffer image: storage, sampled, transfer src/dst, and colour attachment (a host
// may rasterize its G-buffer, as the demo does).
inline constexpr VkImageUsageFlags kGBufferUsage =
    VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
    VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;

struct GBufferRefs {
    VkExtent2D extent{0, 0};
    std::array<ImageRef, kGBufferImageCount> images{};
    const ImageRef& operator[](GBufferImage i) const { return images[static_cast<int>(i)]; }
};

// Formats of the shading outputs.
inline constexpr VkFormat kColorFormat = VK_FORMAT_R16G16B16A16_SFLOAT;  // linear HDR
inline constexpr VkFormat kRateFormat = VK_FORMAT_R16_SFLOAT;            // S_t per pixel

}  // namespace fovea::vk
