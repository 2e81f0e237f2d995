// The G-buffer contract between the host and the foveation module. The module owns the images
// (Foveator::gbuffer()); the host writes all of them every frame at full resolution (visibility
// stays at full rate, Patney 2016 §4) before recording Foveator::record(), with storage-image
// writes from compute or as colour attachments (the demo rasterizes its scene). They stay in
// VK_IMAGE_LAYOUT_GENERAL. Four images, 40 bytes per pixel:
//
//  image     format               contents
//  position  R32G32B32A32_SFLOAT  xyz world position, w view distance (0 = background/sky)
//  surface   R32G32B32A32_UINT    x unit normal, octahedral (packSnorm2x16); for background
//                                   pixels the view direction (the environment lookup)
//                                 y albedo rgb linear + a host-defined (packUnorm4x8)
//                                 z bits 0-15 material id (an integer: coarse pixels never blend
//                                   ids), bits 16-31 material.y (half, host-defined)
//                                 w material.z, material.w (packHalf2x16, host-defined; the demo:
//                                   roughness, metalness, pattern)
//  depth     R32_SFLOAT           0..1, 1 = far/background (TAA disocclusion)
//  motion    R16G16_SFLOAT        screen motion in pixels, current - previous position
//
// GLSL writers and readers use shaders/fovea_gbuffer.glsl (fovea_pack_surface(), no bindings, for
// a host's G-buffer pass); shading functions get the decoded FoveaGSample (fovea_frame.glsl).
// CPU writers (uploads, tests) use pack_surface() below, which packs bit for bit as the GLSL does.
#pragma once

#include <array>
#include <cstdint>

#include <vulkan/vulkan.h>

#include "fovea/vk/device.hpp"

namespace fovea::vk {

enum class GBufferImage { kPosition, kSurface, kDepth, kMotion };
inline constexpr int kGBufferImageCount = 4;

inline constexpr std::array<VkFormat, kGBufferImageCount> kGBufferFormats = {
    VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R32G32B32A32_UINT, VK_FORMAT_R32_SFLOAT,
    VK_FORMAT_R16G16_SFLOAT};

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

// One surface texel before packing. Any thread; pure functions.
struct SurfaceSample {
    std::array<float, 3> normal{0.f, 0.f, 1.f};  // any non-zero length; zero/non-finite -> +z
    std::array<float, 3> albedo{0.f, 0.f, 0.f};  // linear, 0..1 (clamped)
    float albedo_a = 1.f;                        // host-defined, 0..1
    std::array<float, 4> material{0.f, 0.f, 0.f, 0.f};  // x id (rounded, 0..65535), yzw host
};
using SurfaceTexel = std::array<uint32_t, 4>;  // the R32G32B32A32_UINT texel

// Packs as fovea_pack_surface() in shaders/fovea_gbuffer.glsl does (same bits for the same input).
SurfaceTexel pack_surface(const SurfaceSample& s);
// Decodes as fovea_frame.glsl does: unit normal, albedo and halves exactly as the shader sees them.
SurfaceSample unpack_surface(const SurfaceTexel& t);

// Formats of the shading outputs.
inline constexpr VkFormat kColorFormat = VK_FORMAT_R16G16B16A16_SFLOAT;  // linear HDR
inline constexpr VkFormat kRateFormat = VK_FORMAT_R16_SFLOAT;            // S_t per pixel

}  // namespace fovea::vk
