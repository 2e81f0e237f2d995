// The post-process seam: passes that run after the method's shading, in FoveatorConfig::post_chain
// order (TAA, then enhancement). One class per pass in sdk/src/vk/<name>*.cpp, registered with one
// line in sdk/src/vk/post_registry.cpp. See sdk/src/vk/README.md.
#pragma once

#include <memory>
#include <span>

#include "fovea/result.hpp"
#include "fovea/vk/foveator.hpp"
#include "frame_uniforms.hpp"
#include "module_context.hpp"

namespace fovea::vk {

// Called on the host's render thread. All images in GENERAL layout; the previous pass's writes
// are visible (the Foveator puts a barrier between passes).
struct PostFrame {
    VkCommandBuffer cmd;
    VkDescriptorSet frame_set;  // set 0 of pipelines made with_frame_set (uniforms, G-buffer)
    uint64_t frame_index;
    const FrameUniforms& uniforms;  // jitter_px, gaze, acuity, ...
    const FrameInputs& inputs;      // camera_cut resets history
    const ResolvedGaze& gaze;
    const ImageRef& color_in;   // RGBA16F linear HDR (method output or previous pass)
    const ImageRef& color_out;  // RGBA16F: write every pixel
    const ImageRef& depth;      // G-buffer depth (R32F, 1 = far)
    const ImageRef& motion;     // G-buffer motion (RG16F pixels, current - previous)
    const ImageRef& rate;       // S_t of this frame (R16F; 0 fovea .. 1 coarsest)
    std::array<float, 2> jitter_px;
    // Where this pass also writes the display luminance of color_out (enhance_luma.comp's R32F,
    // from the RGBA16F values stored), when the next pass asked for it and this pass
    // writes_display_luma(); else null.
    VkImageView display_luma_out = VK_NULL_HANDLE;
    // The previous pass wrote this pass's display_luma_target() from color_in.
    bool display_luma_ready = false;
};

class PostPass {
public:
    virtual ~PostPass() = default;
    virtual Result<void> init(const ModuleContext& ctx) = 0;
    virtual void record(const PostFrame& frame) = 0;
    // A pass that starts by computing the display luminance of color_in returns the R32F image
    // (extent of the frame) it keeps it in; the previous pass fills it when it can, saving a
    // full-screen pass. Stable after init().
    virtual VkImageView display_luma_target() const { return VK_NULL_HANDLE; }
    // This pass honours PostFrame::display_luma_out.
    virtual bool writes_display_luma() const { return false; }
};

using PostPassFactory = std::unique_ptr<PostPass> (*)();
struct PostPassEntry {
    const char* name;
    PostPassFactory make;
};
std::span<const PostPassEntry> post_pass_registry();

}  // namespace fovea::vk
