// The viewer's host code for one Fovea integration path: the Foveator configuration it needs
// (display, the viewer's shading and scene set on the deferred path) and, per frame, everything
// the host renders for it: the G-buffer and views (deferred), each eccentricity layer views()
// asks for with the forward shaders (forward layers), the full frame (post only). `fovea bench
// --scene` drives the same code. One thread.
#pragma once

#include <memory>
#include <string>

#include "fovea/vk/foveator.hpp"
#include "gltf_viewer/host_device.hpp"
#include "gltf_viewer/model.hpp"
#include "gltf_viewer/renderer.hpp"
#include "gltf_viewer/scene_file.hpp"

namespace gltfv {

class FrameHost {
public:
    // Loads every model of `scene` (each file once) and uploads it. Throws std::runtime_error on
    // Vulkan failure; load errors come back in `error` with a null result.
    static std::unique_ptr<FrameHost> create(HostDevice& device, const SceneFile& scene,
                                             std::vector<std::string>& warnings,
                                             std::string& error);

    // Display, extent, path; shading GLSL and host set on the deferred path.
    fovea::vk::FoveatorConfig config(fovea::vk::IntegrationPath path, VkExtent2D extent) const;
    // Camera position, pixel angle, time and host set (the scene set) of the frame at t_s.
    fovea::vk::FrameInputs inputs(double t_s, VkExtent2D extent) const;
    // Records the host's rendering of frame `index` (time t_s) for `f`'s path: call views()
    // first (it does), then renders into what the Foveator hands out. After this, record().
    void record(VkCommandBuffer cmd, fovea::vk::Foveator& f, uint64_t index,
                const fovea::vk::FrameInputs& in, double t_s, double frame_dt_s);

    const SceneFile& scene() const { return scene_; }
    Renderer& renderer() { return *renderer_; }
    HostDevice& device() { return device_; }

private:
    FrameHost(HostDevice& device, const SceneFile& scene) : device_(device), scene_(scene) {}
    HostDevice& device_;
    SceneFile scene_;
    std::vector<std::unique_ptr<Model>> models_;
    std::unique_ptr<Renderer> renderer_;
};

fovea::vk::EyeDisplay display_of(const SceneFile& scene, VkExtent2D extent);

}  // namespace gltfv
