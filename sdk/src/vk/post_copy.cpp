// Post pass "copy": the smallest post pass (copies colour). A template for TAA/enhancement and a
// check that the chain's ping-pong plumbing works.
#include <map>

#include "post_pass.hpp"

namespace fovea::vk {
namespace {

class CopyPass final : public PostPass {
public:
    Result<void> init(const ModuleContext& ctx) override {
        const Binding img{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};
        const Binding bindings[] = {img, img};
        pipeline_ = ctx.builtin_pipeline("post_copy.comp", bindings, 0, false);
        device_ = ctx.device.device();
        return {};
    }

    void record(const PostFrame& f) override {
        // Two sets: the chain alternates between (A -> B) and (B -> A).
        const auto key = std::make_pair(f.color_in.view, f.color_out.view);
        auto it = sets_.find(key);
        if (it == sets_.end()) {
            VkDescriptorSet set = pipeline_.allocate_set();
            DescriptorWriter(device_, set)
                .storage_image(0, f.color_in.view)
                .storage_image(1, f.color_out.view)
                .commit();
            it = sets_.emplace(key, set).first;
        }
        pipeline_.bind(f.cmd, VK_NULL_HANDLE, it->second);
        vkCmdDispatch(f.cmd, div_up(f.color_in.extent.width, 8),
                      div_up(f.color_in.extent.height, 8), 1);
    }

private:
    ComputePipeline pipeline_;
    VkDevice device_ = VK_NULL_HANDLE;
    std::map<std::pair<VkImageView, VkImageView>, VkDescriptorSet> sets_;
};

}  // namespace

std::unique_ptr<PostPass> make_copy_pass() { return std::make_unique<CopyPass>(); }

}  // namespace fovea::vk
