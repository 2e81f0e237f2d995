#include "gltf_viewer/frame_host.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace gltfv {

fovea::vk::EyeDisplay display_of(const SceneFile& scene, VkExtent2D extent) {
    return fovea::vk::EyeDisplay::from_fov(extent.width, extent.height, scene.fov_h_deg,
                                           scene.fov_v_deg);
}

std::unique_ptr<FrameHost> FrameHost::create(HostDevice& device, const SceneFile& scene,
                                             std::vector<std::string>& warnings,
                                             std::string& error) {
    std::unique_ptr<FrameHost> h(new FrameHost(device, scene));
    CpuScene content;
    std::map<std::string, Model*> by_file;
    for (const ModelDesc& d : scene.models) {
        Model*& m = by_file[d.file];
        if (!m) {
            auto loaded = std::make_unique<Model>();
            if (std::string e = load_gltf(d.file, *loaded, warnings); !e.empty()) {
                error = e;
                return nullptr;
            }
            m = loaded.get();
            h->models_.push_back(std::move(loaded));
        }
        content.add_instance(*m, d.placement(), d.fit);
    }
    h->renderer_ = std::make_unique<Renderer>(device.gpu(), scene, content);
    return h;
}

fovea::vk::FoveatorConfig FrameHost::config(fovea::vk::IntegrationPath path,
                                            VkExtent2D extent) const {
    fovea::vk::FoveatorConfig c;
    c.path = path;
    c.extent = extent;
    c.display = display_of(scene_, extent);
    if (path == fovea::vk::IntegrationPath::kDeferred) {
        c.shading_glsl = Renderer::shading_glsl();
        c.host_set_layout = renderer_->scene_set_layout();
    }
    return c;
}

fovea::vk::FrameInputs FrameHost::inputs(double t_s, VkExtent2D extent) const {
    const Camera cam = camera_for(scene_, t_s);
    fovea::vk::FrameInputs in;
    in.camera_pos = cam.eye;
    constexpr float kRad = 0.017453292519943295f;
    in.radians_per_pixel =
        2.f * std::tan(scene_.fov_v_deg * 0.5f * kRad) / static_cast<float>(extent.height);
    in.time_s = t_s;
    in.host_set = renderer_->scene_set();  // read on the deferred path only
    return in;
}

namespace {

ViewSpec view_spec(const fovea::vk::ViewRequest& v, const fovea::vk::Foveator& f) {
    const float s = (v.crop[2] - v.crop[0]) * float(f.config().extent.width) /
                    float(std::max(v.extent.width, 1u));
    return {v.crop, v.jitter_px, v.extent, s};
}

}  // namespace

void FrameHost::record(VkCommandBuffer cmd, fovea::vk::Foveator& f, uint64_t index,
                       const fovea::vk::FrameInputs& in, double t_s, double frame_dt_s) {
    using fovea::vk::IntegrationPath;
    const Camera cam = camera_for(scene_, t_s), prev = camera_for(scene_, t_s - frame_dt_s);
    renderer_->begin_frame();
    const IntegrationPath path = f.config().path;
    const std::vector<fovea::vk::ViewRequest> views = f.views(index, in);
    if (path == IntegrationPath::kForwardLayers) {
        for (const auto& v : views)
            renderer_->record_forward(cmd, v.targets, cam, prev, view_spec(v, f));
    } else if (path == IntegrationPath::kPostOnly || path == IntegrationPath::kRateImage) {
        const fovea::vk::HostTargets& t = f.host_targets();
        renderer_->record_forward(cmd, t, cam, prev,
                                  {{0.f, 0.f, 1.f, 1.f}, f.jitter(index), t.extent, 1.f});
    } else {  // deferred: the full-resolution G-buffer where the method reads it, and views
        const fovea::vk::GBufferRefs& g = f.gbuffer();
        if (f.needs_full_gbuffer())
            renderer_->record_gbuffer(cmd, g, cam, prev,
                                      {{0.f, 0.f, 1.f, 1.f}, f.jitter(index), g.extent, 1.f});
        for (const auto& v : views)
            renderer_->record_gbuffer(cmd, v.gbuffer, cam, prev, view_spec(v, f));
    }
}

}  // namespace gltfv
