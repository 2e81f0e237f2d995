// Paths 3 and 4 (IntegrationPath::kRateImage, kPostOnly): the host rendered the frame itself, so
// there is nothing to shade; this writes S_t from the acuity model and counts the host's samples
// (shaders/host_rate.comp). Not in the registry: the Foveator makes it for those paths.
#include "../method.hpp"

namespace fovea::vk {
namespace {

class HostRenderedMethod final : public Method {
public:
    explicit HostRenderedMethod(bool count_rate) : count_rate_(count_rate ? 1 : 0) {}

    Result<void> init(const ModuleContext& ctx) override {
        pipeline_ = ctx.builtin_pipeline("host_rate.comp", {}, sizeof(count_rate_), true);
        return {};
    }

    bool uses_full_gbuffer() const override { return false; }

    void record(const MethodFrame& f) override {
        pipeline_.bind(f.cmd, f.frame_set, VK_NULL_HANDLE, &count_rate_, sizeof(count_rate_));
        vkCmdDispatch(f.cmd, div_up(f.rate.extent.width, 8), div_up(f.rate.extent.height, 8), 1);
    }

private:
    int32_t count_rate_;
    ComputePipeline pipeline_;
};

}  // namespace

std::unique_ptr<Method> make_host_rendered_method(bool rate_image) {
    return std::make_unique<HostRenderedMethod>(rate_image);
}

}  // namespace fovea::vk
