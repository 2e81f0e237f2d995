// The one list of post passes (run after shading, in FoveatorConfig::post_chain order): add one
// line per pass; each factory is defined in its own sdk/src/vk/post/<name>*.cpp.
#include "post_pass.hpp"

// The block-scope factory declarations are intended.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wvexing-parse"
#endif

namespace fovea::vk {

std::span<const PostPassEntry> post_pass_registry() {
    static const PostPassEntry kPasses[] = {
        {"copy",
         [] {
             std::unique_ptr<PostPass> make_copy_pass();
             return make_copy_pass();
         }},
        {"taa",
         [] {
             std::unique_ptr<PostPass> make_taa_pass();
             return make_taa_pass();
         }},
        {"contrast",
         [] {
             std::unique_ptr<PostPass> make_contrast_pass();
             return make_contrast_pass();
         }},
        {"noise",
         [] {
             std::unique_ptr<PostPass> make_noise_pass();
             return make_noise_pass();
         }},
    };
    return kPasses;
}

}  // namespace fovea::vk
