// LDR-FLIP on a Vulkan device (shaders/flip_prepare|horizontal|vertical.comp): the same metric
// as the CPU reference (flip.hpp), whose kernels and constants it uploads, for `fovea bench` to
// measure every frame where it was rendered. It keeps several references, each with its own ppd
// field: a reference is filtered once (record_reference) and any number of test images are
// compared with it (record_compare); a temporal FLIP takes as reference the previous frame
// back-projected along the motion (record_back_projected_reference).
//
// Threads: one thread records and reads; like the Foveator, one recorded use in flight. Inputs
// are sampled images in VK_IMAGE_LAYOUT_GENERAL, written before the recorded passes (a compute or
// transfer write; the passes put their own barrier first).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include <vulkan/vulkan.h>

#include "fovea/metrics/flip.hpp"
#include "fovea/result.hpp"
#include "fovea/vk/acuity.hpp"
#include "fovea/vk/device.hpp"

namespace fovea::metrics {

// What an input image holds (see shaders/flip_common.glsl).
enum class FlipInput : uint32_t {
    kSrgb = 0,         // sRGB-encoded values: an 8-bit UNORM image, or floats in 0..1
    kDemoDisplay = 1,  // linear HDR shown through the demo's display transform (demo::tonemap)
};

// The ppd a display's pixels are seen at, per axis, from the SDK's acuity model
// (vk::pixel_size_deg_axes), constant over aligned 16-pixel blocks (the GPU's granularity).
PpdField display_ppd_field(const vk::EyeDisplay& display, uint32_t width, uint32_t height);

// GPU milliseconds of one compare, per pass (all 0 without timestamps).
struct FlipPassTimes {
    double prepare_ms = 0, horizontal_ms = 0, vertical_ms = 0, total_ms = 0;
};

class GpuFlip {
public:
    // One reference slot per ppd field (`references[i]` is slot i's). Each field must be constant
    // within aligned 16-pixel blocks, and no kernel wider than 2 * kMaxRadius + 1 (ppd up to
    // ~470); errors otherwise. Builds pipelines; blocking.
    static constexpr int kMaxRadius = 64;
    static Result<GpuFlip> create(const vk::Device& device, uint32_t width, uint32_t height,
                                  const std::vector<PpdField>& references);
    GpuFlip(GpuFlip&&) noexcept;
    GpuFlip& operator=(GpuFlip&&) noexcept;
    GpuFlip(const GpuFlip&) = delete;
    GpuFlip& operator=(const GpuFlip&) = delete;
    ~GpuFlip();

    uint32_t width() const;
    uint32_t height() const;

    // Records filtering `image` into reference slot `slot`.
    void record_reference(VkCommandBuffer cmd, const vk::ImageRef& image, FlipInput kind,
                          int slot = 0);
    // Records slot `slot` as `previous` (kDemoDisplay) back-projected along the motion given to
    // set_motion(), bilinearly; pixels whose previous position leaves the frame take `current`
    // and are not pooled (NaN in the map).
    void record_back_projected_reference(VkCommandBuffer cmd, const vk::ImageRef& previous,
                                         const vk::ImageRef& current, int slot = 0);
    // Per pixel, current - previous position of its centre in pixels (2 floats per pixel, NaN
    // for none). Copied now; not while a recorded back-projection is in flight.
    void set_motion(std::span<const float> motion_px);
    // Records FLIP of `test` against slot `slot`, at its ppd, into map().
    void record_compare(VkCommandBuffer cmd, const vk::ImageRef& test, FlipInput kind,
                        int slot = 0);

    // Forgets the input images recorded so far (their descriptor sets). Call before their
    // views are destroyed, e.g. between a bench's configurations: at most 64 distinct (input,
    // fill) image pairs are kept, and recording a 65th fails. No recorded use may be in flight.
    void forget_inputs();
    // After the recorded compare completed: the map, row-major (NaN where not pooled), and the
    // GPU milliseconds of the compare's passes (0 where the device has no timestamps).
    std::span<const float> map() const;
    double compare_gpu_ms() const;
    FlipPassTimes compare_gpu_times() const;

private:
    struct Impl;
    explicit GpuFlip(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace fovea::metrics
