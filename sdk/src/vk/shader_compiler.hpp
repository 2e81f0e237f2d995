// Run-time GLSL -> SPIR-V through the glslang library, for shaders that call the host's shading
// function. #include "x" resolves to the embedded shaders/x, except "fovea_host.glsl", which is
// the host's source. Thread-safe (glslang process init is once; each compile is independent).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "fovea/result.hpp"

namespace fovea::vk {

// Compiles embedded compute shader `shader_name` (e.g. "cps_shade.shade.comp") with the host's
// shading GLSL. `defines` are "NAME" or "NAME=VALUE" preprocessor definitions.
Result<std::vector<uint32_t>> compile_with_host(std::string_view shader_name,
                                                std::string_view host_glsl,
                                                const std::vector<std::string>& defines = {});

// Compiles arbitrary compute GLSL (includes resolve to embedded shaders).
Result<std::vector<uint32_t>> compile_glsl(std::string_view source, std::string_view debug_name,
                                           std::string_view host_glsl = {},
                                           const std::vector<std::string>& defines = {});

}  // namespace fovea::vk
