#include "module_context.hpp"

#include <cstdlib>

#include "shader_compiler.hpp"
#include "shaders.hpp"

namespace fovea::vk {

Result<ComputePipeline> ModuleContext::shading_pipeline(std::string_view shader_name,
                                                        std::span<const Binding> bindings,
                                                        uint32_t push_bytes,
                                                        const std::vector<std::string>& defines,
                                                        std::span<const uint32_t> spec) const {
    auto spirv = compile_with_host(shader_name, config.shading_glsl, defines);
    if (!spirv) return spirv.error();
    try {
        return ComputePipeline(device, *spirv, frame_set_layout, bindings, push_bytes, spec, 8,
                               config.host_set_layout, host_set);
    } catch (const VkError& e) {
        return make_error(std::string(shader_name) + ": " + e.what(), static_cast<int>(e.result()));
    }
}

ComputePipeline ModuleContext::builtin_pipeline(std::string_view shader_name,
                                                std::span<const Binding> bindings,
                                                uint32_t push_bytes, bool with_frame_set,
                                                std::span<const uint32_t> spec) const {
    return ComputePipeline(device, shader_spirv(shader_name),
                           with_frame_set ? frame_set_layout : VK_NULL_HANDLE, bindings, push_bytes,
                           spec);
}

std::string ModuleContext::option(std::string_view key, std::string_view fallback) const {
    for (const std::string& o : config.options) {
        const auto eq = o.find('=');
        if (eq != std::string::npos && std::string_view(o).substr(0, eq) == key)
            return o.substr(eq + 1);
    }
    return std::string(fallback);
}

double ModuleContext::option_number(std::string_view key, double fallback) const {
    const std::string v = option(key, "");
    if (v.empty()) return fallback;
    char* end = nullptr;
    const double d = std::strtod(v.c_str(), &end);
    return end && *end == '\0' ? d : fallback;
}

}  // namespace fovea::vk
