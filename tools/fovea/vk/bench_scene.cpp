#include "bench_scene.hpp"

#include <algorithm>
#include <optional>
#include <stdexcept>

#include "fovea/vk/foveator.hpp"
#include "gltf_viewer/frame_host.hpp"

namespace fovea::bench {

struct SceneBench::Impl {
    std::string file;
    gltfv::SceneFile scene;
    std::unique_ptr<gltfv::HostDevice> device;
    std::unique_ptr<gltfv::FrameHost> host;
    std::vector<std::string> warnings;
};

SceneBench::SceneBench(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
SceneBench::~SceneBench() = default;

Result<std::unique_ptr<SceneBench>> SceneBench::open(const std::string& scene_file,
                                                     const std::string& data_dir,
                                                     bool prefer_software, bool validation) {
    auto impl = std::make_unique<Impl>();
    impl->file = scene_file;
    if (std::string e = gltfv::load_scene_file(scene_file, data_dir, impl->scene); !e.empty())
        return make_error(e);
    std::string error;
    impl->device = gltfv::HostDevice::create(prefer_software, validation, error);
    if (!impl->device) return make_error(error);
    try {
        impl->host = gltfv::FrameHost::create(*impl->device, impl->scene, impl->warnings, error);
    } catch (const std::exception& e) {
        return make_error(std::string("loading the scene on the device: ") + e.what());
    }
    if (!impl->host) return make_error(error);
    return std::unique_ptr<SceneBench>(new SceneBench(std::move(impl)));
}

const vk::Device& SceneBench::device() const { return impl_->device->sdk(); }
const std::vector<std::string>& SceneBench::warnings() const { return impl_->warnings; }
uint64_t SceneBench::validation_errors() const { return impl_->device->validation_errors(); }

std::string SceneBench::description() const {
    return impl_->file + ": " + std::to_string(impl_->scene.models.size()) + " models, " +
           std::to_string(impl_->host->renderer().triangles()) + " triangles";
}

vk::EyeDisplay SceneBench::display(uint32_t width, uint32_t height) const {
    const gltfv::SceneFile& s = impl_->scene;
    return gltfv::display_of(s, {width ? width : s.width, height ? height : s.height});
}

namespace {

// The forward variants' path; nullopt for a method of the deferred path.
std::optional<vk::IntegrationPath> forward_path(const std::string& name) {
    if (name == SceneBench::kForwardReference || name == "post-only")
        return vk::IntegrationPath::kPostOnly;
    if (name == "forward-layers") return vk::IntegrationPath::kForwardLayers;
    if (name == "rate-image") return vk::IntegrationPath::kRateImage;
    return std::nullopt;
}

}  // namespace

std::vector<std::string> SceneBench::with_references(const std::vector<std::string>& methods) {
    std::vector<std::string> out;
    for (const auto& m : methods) {
        if (m == kForwardReference) continue;
        if (forward_path(m) && std::find(out.begin(), out.end(), kForwardReference) == out.end())
            out.push_back(kForwardReference);
        out.push_back(m);
    }
    return out;
}

std::vector<std::string> SceneBench::variants() {
    std::vector<std::string> v = vk::Foveator::methods();  // "full" first: path 1's reference
    for (const char* p : {"forward-layers", "post-only", "rate-image"}) v.push_back(p);
    return v;
}

Result<std::vector<demo::MethodResult>> SceneBench::run(const demo::RunOptions& o) {
    gltfv::FrameHost& host = *impl_->host;
    const vk::Device& device = impl_->device->sdk();
    const VkExtent2D extent{o.display.width_px, o.display.height_px};
    const auto make_config = [&](vk::IntegrationPath path) {
        vk::FoveatorConfig c = host.config(path, extent);
        c.display = o.display;
        c.acuity = o.acuity;
        c.post_chain = o.post_chain;
        c.options = o.options;
        return c;
    };
    // demo::run's order: "full", then o.methods as given (results[k] <-> names[k]).
    std::vector<std::string> names{"full"};
    bool have_reference = false;
    for (const auto& m : o.methods) {
        if (m == "full") continue;
        if (m == kForwardReference) have_reference = true;
        if (forward_path(m) && m != kForwardReference && !have_reference)
            return make_error(std::string("scene: ") + kForwardReference + " must come before " +
                              m + " in the methods (SceneBench::with_references)");
        names.push_back(m);
    }
    const bool forward = have_reference;

    vk::FoveatorConfig dc = make_config(vk::IntegrationPath::kDeferred);
    dc.method = "full";
    auto deferred = vk::Foveator::create(device, dc);
    if (!deferred) return make_error("scene, deferred path: " + deferred.error().message);
    std::vector<demo::MethodResult> results(names.size());
    std::vector<std::unique_ptr<vk::Foveator>> own(names.size());  // forward paths' foveators
    std::vector<size_t> reference_of(names.size(), 0);
    size_t forward_reference = 0;
    for (size_t k = 0; k < names.size(); ++k) {
        demo::MethodResult& r = results[k];
        r.name = names[k];
        const auto path = forward_path(names[k]);
        if (!path) {
            if (auto s = deferred->set_method(names[k]); !s) r.error = s.error().message;
            continue;
        }
        vk::FoveatorConfig c = make_config(*path);
        if (names[k] == kForwardReference) {
            c.acuity.max_rate = 1.f;  // S_t = 0 everywhere: the forward frame at full rate
            forward_reference = k;
        }
        reference_of[k] = forward_reference;
        if (auto made = vk::Foveator::create(device, c); !made)
            r.error = made.error().message;
        else
            own[k] = std::make_unique<vk::Foveator>(std::move(*made));
    }
    if (!results[0].error.empty()) return make_error(results[0].error);
    if (forward && !own[forward_reference])
        return make_error("scene, forward reference: " + results[forward_reference].error);

    std::vector<std::vector<double>> gpu_ms(names.size());
    std::vector<demo::ErrorPool> errors(names.size());  // pooled over frames, as demo::run
    std::vector<int> compared(names.size(), 0);
    const uint32_t w = extent.width, h = extent.height;
    for (int i = -1; i < o.frames; ++i) {  // frame -1 warms every variant up, not measured
        const double t = std::max(i, 0) * o.frame_dt_s;
        const uint64_t index = static_cast<uint64_t>(i + 1);
        vk::FrameInputs in = host.inputs(t, extent);
        if (o.gaze) in.gaze = o.gaze(t);
        in.camera_cut = i <= 0;
        std::vector<demo::Rgb8> images(names.size());
        demo::BandLabels labels;
        for (size_t k = 0; k < names.size(); ++k) {
            demo::MethodResult& r = results[k];
            if (!r.error.empty()) continue;
            vk::Foveator* f = own[k] ? own[k].get() : &*deferred;
            if (!own[k]) {
                if (auto s = f->set_method(names[k]); !s) {
                    r.error = s.error().message;
                    continue;
                }
            }
            const double ms = f->render_blocking(index, in, [&](VkCommandBuffer cmd) {
                host.record(cmd, *f, index, in, t, o.frame_dt_s);
            });
            if (i < 0) continue;
            const vk::FrameStats st = f->stats();
            r.ms.push_back(ms);
            gpu_ms[k].push_back(st.method_gpu_ms);
            r.shaded_fraction += st.shaded_fraction / o.frames;
            r.skipped_tiles += static_cast<double>(st.skipped_tiles) / o.frames;
            r.reused_tiles += static_cast<double>(st.reused_tiles) / o.frames;
            images[k] = demo::tonemap(device.read_image(f->output()), w, h);
            if (k == 0)
                labels = demo::band_labels(w, h, o.display, st.gaze, o.acuity.foveal_radius_deg);
            errors[k].add(images[k], images[reference_of[k]], labels);
            ++compared[k];
            if (o.on_frame) o.on_frame(k, i, *f, images[k]);
        }
    }
    for (size_t k = 0; k < names.size(); ++k) {
        demo::MethodResult& r = results[k];
        if (!r.error.empty() || compared[k] == 0) continue;
        r.ms_median = demo::median(r.ms);
        r.method_gpu_ms = demo::median(gpu_ms[k]);
        r.error_figures = errors[k].figures();
    }
    return results;
}

}  // namespace fovea::bench
