// Method "full": every pixel shaded once (the full-rate reference the others are measured against).
#include "../method.hpp"

namespace fovea::vk {
namespace {

class FullMethod final : public Method {
public:
    Result<void> init(const ModuleContext& ctx) override {
        auto p = ctx.shading_pipeline("full.shade.comp", {}, 0);
        if (!p) return p.error();
        pipeline_ = std::move(*p);
        return {};
    }

    void record(const MethodFrame& f) override {
        pipeline_.bind(f.cmd, f.frame_set, VK_NULL_HANDLE);
        vkCmdDispatch(f.cmd, div_up(f.color.extent.width, 8), div_up(f.color.extent.height, 8), 1);
    }

private:
    ComputePipeline pipeline_;
};

}  // namespace

std::unique_ptr<Method> make_full_method() { return std::make_unique<FullMethod>(); }

}  // namespace fovea::vk
