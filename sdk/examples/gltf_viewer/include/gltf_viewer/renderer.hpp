// The viewer's renderer: its glTF scene on the GPU and its own raster passes into the Fovea
// module's images. One class per integration path's needs:
// - forward (paths 2 and 4, and their full-rate reference): colour + depth + motion into a
//   fovea::vk::HostTargets (the full frame, or an eccentricity layer views() asks for);
// - G-buffer (path 1): the module's packed G-buffer, plus shading_glsl() (its PBR as
//   fovea_shade(), textures pre-filtered at the footprint's LOD) and the scene set the module
//   binds as the host set (FoveatorConfig::host_set_layout / FrameInputs::host_set).
// One thread; begin_frame() before a frame's passes, after the previous frame completed.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "fovea/vk/foveator.hpp"
#include "gltf_viewer/math.hpp"
#include "gltf_viewer/model.hpp"
#include "gltf_viewer/scene_file.hpp"
#include "gltf_viewer/vk_util.hpp"

namespace gltfv {

// A camera for one frame: view and unjittered projection (Vulkan clip space, perspective()).
struct Camera {
    Mat4 view = identity();
    Mat4 projection = identity();
    Vec3 eye{0.f, 0.f, 0.f};
};
// The scene's camera path at time t; the projection covers the scene's display field of view.
Camera camera_for(const SceneFile& scene, double t_s);

// What a pass draws: the full frame or a module view (crop of the frame, its own jitter).
struct ViewSpec {
    std::array<float, 4> crop{0.f, 0.f, 1.f, 1.f};
    std::array<float, 2> jitter_px{0.f, 0.f};
    VkExtent2D extent{0, 0};
    float output_px_per_view_px = 1.f;  // a layer's sampling factor s; 1 for the full frame
};

class Renderer {
public:
    Renderer(const Gpu& gpu, const SceneFile& scene, const CpuScene& content);
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;
    ~Renderer();

    void begin_frame();
    // Forward: colour, depth and motion of `view` into `targets` (GENERAL layout in and out).
    void record_forward(VkCommandBuffer cmd, const fovea::vk::HostTargets& targets,
                        const Camera& cam, const Camera& prev, const ViewSpec& view);
    // Deferred (path 1): the packed G-buffer of `view` into `g` (the module's full-resolution
    // gbuffer() or a view's), GENERAL layout in and out.
    void record_gbuffer(VkCommandBuffer cmd, const fovea::vk::GBufferRefs& g, const Camera& cam,
                        const Camera& prev, const ViewSpec& view);
    // The deferred path's fovea_shade() (FoveatorConfig::shading_glsl): shaders/viewer_shade.glsl
    // with the scene set as the module's host set.
    static const std::string& shading_glsl();
    // GPU milliseconds of the last completed frame's passes (timestamps; 0 where none).
    double gpu_ms() const;

    // The module's host set for fovea_shade (the scene set: lights, materials, textures).
    VkDescriptorSetLayout scene_set_layout() const { return scene_layout_.get(); }
    VkDescriptorSet scene_set() const { return scene_set_; }

    uint32_t triangles() const { return triangles_; }

private:
    void record_pass(VkCommandBuffer cmd, bool gbuffer, std::array<VkImageView, 4> colors,
                     VkExtent2D extent, const Camera& cam, const Camera& prev,
                     const ViewSpec& view);
    struct Impl;
    std::unique_ptr<Impl> impl_;
    SetLayout scene_layout_;
    VkDescriptorSet scene_set_ = VK_NULL_HANDLE;
    uint32_t triangles_ = 0;
};

}  // namespace gltfv
