// What a method or post pass gets from the Foveator at init time: the device, the configuration,
// the frame set layout (set 0, shaders/fovea_frame.glsl), the images it reads and writes, and
// pipeline factories. Called on the thread that creates the Foveator / switches methods.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "fovea/result.hpp"
#include "fovea/vk/foveator.hpp"
#include "gpu.hpp"

namespace fovea::vk {

struct ModuleContext {
    const Device& device;
    const FoveatorConfig& config;
    VkExtent2D extent;
    VkDescriptorSetLayout frame_set_layout;  // set 0 of every pipeline that wants it
    const GBufferRefs& gbuffer;
    const ImageRef& rate_tiles;  // R8_UINT per-tile rate (cps writes it)
    // The host's descriptor set of the frame being recorded (FrameInputs::host_set), bound as
    // set 2 of every shading pipeline when config.host_set_layout is set.
    const VkDescriptorSet* host_set = nullptr;

    // A pipeline from a *.shade.comp compiled at run time with the host's shading function.
    // Set 0 is the frame set, set 1 the pipeline's own `bindings`.
    Result<ComputePipeline> shading_pipeline(std::string_view shader_name,
                                             std::span<const Binding> bindings, uint32_t push_bytes,
                                             const std::vector<std::string>& defines = {},
                                             std::span<const uint32_t> spec = {}) const;
    // A pipeline from build-time SPIR-V (shaders/<name>, not *.shade.comp). with_frame_set:
    // set 0 = frame set and own bindings in set 1; otherwise own bindings in set 0.
    ComputePipeline builtin_pipeline(std::string_view shader_name,
                                     std::span<const Binding> bindings, uint32_t push_bytes,
                                     bool with_frame_set,
                                     std::span<const uint32_t> spec = {}) const;

    // FoveatorConfig::options lookup: "key=value"; `fallback` when absent.
    std::string option(std::string_view key, std::string_view fallback) const;
    double option_number(std::string_view key, double fallback) const;
};

}  // namespace fovea::vk
