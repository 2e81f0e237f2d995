// The method interface: one class per foveation method in sdk/src/vk/methods/<name>.cpp,
// registered with one line in sdk/src/vk/methods/registry.cpp. See sdk/src/vk/README.md.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "fovea/result.hpp"
#include "fovea/vk/foveator.hpp"
#include "frame_uniforms.hpp"
#include "module_context.hpp"

namespace fovea::vk {

// Everything a method's record() sees. Called on the host's render thread.
struct MethodFrame {
    VkCommandBuffer cmd;
    VkDescriptorSet frame_set;  // bind as set 0
    uint64_t frame_index;
    const FrameUniforms& uniforms;  // CPU copy of the frame's uniform block
    const FrameInputs& inputs;
    const ResolvedGaze& gaze;
    const ImageRef& color;  // write every pixel (RGBA16F linear)
    const ImageRef& rate;   // write S_t for every pixel (R16F)
    // Forward layers (IntegrationPath::kForwardLayers): write every pixel of depth and motion
    // for the post chain; null on the other paths.
    const HostTargets* depth_out = nullptr;
};

class Method {
public:
    virtual ~Method() = default;
    // Builds pipelines and resources (compile the host GLSL via ctx.shading_pipeline). The
    // context outlives the method.
    virtual Result<void> init(const ModuleContext& ctx) = 0;
    // Extra G-buffers the host renders this frame (default: none).
    virtual std::vector<ViewRequest> views(uint64_t /*frame_index*/, const ResolvedGaze&) {
        return {};
    }
    // True when views() asks the host for images every frame (record() warns when the host did
    // not call views() for the frame).
    virtual bool has_views() const { return false; }
    // Samples the host rendered itself this frame (forward layers), added to shaded_samples.
    virtual uint64_t host_rendered_samples() const { return 0; }
    // False when the method needs only its views(), not the full-resolution G-buffer.
    virtual bool uses_full_gbuffer() const { return true; }
    // Records the shading. The frame stats buffer was zeroed and the G-buffer made visible; add
    // every host-function invocation to fovea_stats.shaded_samples (atomicAdd) and write colour
    // and S_t for every pixel.
    virtual void record(const MethodFrame& frame) = 0;
};

using MethodFactory = std::unique_ptr<Method> (*)();
struct MethodEntry {
    const char* name;
    MethodFactory make;
};
std::span<const MethodEntry> method_registry();

}  // namespace fovea::vk
