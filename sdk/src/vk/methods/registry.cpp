// The one list of foveation methods: add one line per method. Each factory is defined in its own
// sdk/src/vk/methods/<name>.cpp (the block-scope declaration keeps the entry to a single line).
#include "../method.hpp"

// The block-scope factory declarations are intended.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wvexing-parse"
#endif

namespace fovea::vk {

std::span<const MethodEntry> method_registry() {
    static const MethodEntry kMethods[] = {
        {"full",
         [] {
             std::unique_ptr<Method> make_full_method();
             return make_full_method();
         }},
        {"cps",
         [] {
             std::unique_ptr<Method> make_cps_method();
             return make_cps_method();
         }},
        {"layers",
         [] {
             std::unique_ptr<Method> make_layers_method();
             return make_layers_method();
         }},
        {"adaptive",
         [] {
             std::unique_ptr<Method> make_adaptive_method();
             return make_adaptive_method();
         }},
        {"kfr",
         [] {
             std::unique_ptr<Method> make_kfr_method();
             return make_kfr_method();
         }},
    };
    return kMethods;
}

}  // namespace fovea::vk
