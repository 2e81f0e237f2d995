// Shaders embedded at build time by cmake/FoveaShaders.cmake: every shaders/*.comp and *.glsl
// as source text, and SPIR-V for compute shaders that do not call the host shading function.
// Files named *.shade.comp include "fovea_host.glsl" and are compiled at run time
// (ShaderCompiler) with the host's function; at build time they are only validated.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

namespace fovea::vk {

struct EmbeddedShader {
    const char* name;       // file name, e.g. "cps_classify.comp"
    const uint32_t* spirv;  // nullptr for .glsl includes and *.shade.comp
    size_t spirv_words;
    const char* source;
};

// nullptr when no such file was embedded.
const EmbeddedShader* find_shader(std::string_view name);
std::span<const uint32_t> shader_spirv(std::string_view name);  // asserts it exists

}  // namespace fovea::vk
