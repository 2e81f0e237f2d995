#include "shader_compiler.hpp"

#include <cstring>
#include <mutex>
#include <string>

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>

#include "shaders.hpp"

namespace fovea::vk {
namespace {

void init_glslang() {
    static std::once_flag once;
    std::call_once(once, [] { glslang::InitializeProcess(); });
}

// Resolves #include "x" to embedded shaders/x, and "fovea_host.glsl" to the host's source.
class Includer : public glslang::TShader::Includer {
public:
    explicit Includer(std::string_view host) : host_(host) {}
    IncludeResult* includeLocal(const char* name, const char*, size_t) override {
        return resolve(name);
    }
    IncludeResult* includeSystem(const char* name, const char*, size_t) override {
        return resolve(name);
    }
    void releaseInclude(IncludeResult* r) override { delete r; }

private:
    IncludeResult* resolve(const char* name) {
        if (std::strcmp(name, "fovea_host.glsl") == 0 && !host_.empty())
            return new IncludeResult(name, host_.data(), host_.size(), nullptr);
        const EmbeddedShader* s = find_shader(name);
        if (!s) return nullptr;
        return new IncludeResult(name, s->source, std::strlen(s->source), nullptr);
    }
    std::string_view host_;
};

}  // namespace

Result<std::vector<uint32_t>> compile_glsl(std::string_view source, std::string_view debug_name,
                                           std::string_view host_glsl,
                                           const std::vector<std::string>& defines) {
    init_glslang();
    std::string preamble;
    for (const std::string& d : defines) {
        const auto eq = d.find('=');
        preamble += "#define " +
                    (eq == std::string::npos ? d : d.substr(0, eq) + " " + d.substr(eq + 1)) + "\n";
    }
    glslang::TShader shader(EShLangCompute);
    const char* src = source.data();
    const int len = static_cast<int>(source.size());
    const std::string name(debug_name);
    const char* names[] = {name.c_str()};
    shader.setStringsWithLengthsAndNames(&src, &len, names, 1);
    shader.setPreamble(preamble.c_str());
    shader.setEnvInput(glslang::EShSourceGlsl, EShLangCompute, glslang::EShClientVulkan, 100);
    shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_1);
    shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_3);
    Includer includer(host_glsl);
    const auto messages = static_cast<EShMessages>(EShMsgSpvRules | EShMsgVulkanRules);
    if (!shader.parse(GetDefaultResources(), 450, false, messages, includer))
        return make_error("GLSL compile of " + name + " failed:\n" + shader.getInfoLog() +
                          shader.getInfoDebugLog());
    glslang::TProgram program;
    program.addShader(&shader);
    if (!program.link(messages))
        return make_error("GLSL link of " + name + " failed:\n" + program.getInfoLog());
    std::vector<uint32_t> spirv;
    glslang::SpvOptions options;
    options.disableOptimizer = false;
    options.optimizeSize = false;
    glslang::GlslangToSpv(*program.getIntermediate(EShLangCompute), spirv, &options);
    if (spirv.empty()) return make_error("GLSL to SPIR-V of " + name + " produced nothing");
    return spirv;
}

Result<std::vector<uint32_t>> compile_with_host(std::string_view shader_name,
                                                std::string_view host_glsl,
                                                const std::vector<std::string>& defines) {
    const EmbeddedShader* s = find_shader(shader_name);
    if (!s) return make_error("no embedded shader named " + std::string(shader_name));
    return compile_glsl(s->source, shader_name, host_glsl, defines);
}

}  // namespace fovea::vk
