// `fovea bench --scene FILE`: the sweep's frames rendered through the glTF viewer's host code
// (sdk/examples/gltf_viewer: its own instance and device handed over by Device::wrap, its models,
// deferred and forward renderers, camera path) instead of the demo scene: the module's methods on
// the deferred path and the viewer's forward integration paths. run() keeps demo::run's
// contract, so bench_sweep measures both scenes with the same code. One thread.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "fovea/demo/demo.hpp"
#include "fovea/result.hpp"
#include "fovea/vk/acuity.hpp"
#include "fovea/vk/device.hpp"

namespace fovea::bench {

class SceneBench {
public:
    // Loads the TOML scene (data_dir non-empty: replaces the file's data_dir) and its models on
    // the viewer's own device (a CPU device, lavapipe, when prefer_software; the validation
    // layer when validation). Load warnings are kept in warnings().
    static Result<std::unique_ptr<SceneBench>> open(const std::string& scene_file,
                                                    const std::string& data_dir,
                                                    bool prefer_software, bool validation);
    SceneBench(const SceneBench&) = delete;
    SceneBench& operator=(const SceneBench&) = delete;
    ~SceneBench();

    const vk::Device& device() const;
    const std::vector<std::string>& warnings() const;
    uint64_t validation_errors() const;  // so far, with validation
    std::string description() const;     // "FILE: N models, T triangles"
    // The scene file's display, or one of width x height with its field of view.
    vk::EyeDisplay display(uint32_t width = 0, uint32_t height = 0) const;

    // The scene's full-rate forward frame, the reference of the forward paths.
    static constexpr const char* kForwardReference = "full-forward";
    // The variants run() knows, in sweep order: the module's methods on the deferred path
    // (path 1, the viewer's PBR as fovea_shade(), against "full"), then the forward paths
    // ("forward-layers", "post-only", "rate-image": paths 2, 4, 3; run() adds their reference).
    static std::vector<std::string> variants();

    // methods with kForwardReference inserted before the first forward path (run() wants it
    // there: results[k] must match {"full"} + methods, as demo::run's do).
    static std::vector<std::string> with_references(const std::vector<std::string>& methods);

    // demo::run on this scene: o.display (the scene's field of view), o.acuity, o.post_chain,
    // o.options, o.frames (+1 warm-up), o.frame_dt_s, o.gaze and o.on_frame as there;
    // o.methods names variants() (through with_references()); results[k] is {"full"} +
    // o.methods in order. "full" (path 1, every pixel shaded) is the deferred methods'
    // reference, kForwardReference (the same forward pass into the post-only path at rate 1
    // everywhere, S_t = 0, and the same post chain) the forward paths' after it. A variant whose
    // Foveator cannot be made (rate-image without VRS) gets its error and no figures. on_frame's
    // Foveator renders each variant (the deferred methods share one, switched by set_method() as
    // demo::run does).
    Result<std::vector<demo::MethodResult>> run(const demo::RunOptions& o);

private:
    struct Impl;
    explicit SceneBench(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace fovea::bench
