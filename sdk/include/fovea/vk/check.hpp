// VK_CHECK: every Vulkan call's result is checked; a failure throws fovea::vk::VkError naming the
// call, the VkResult and the place. Vulkan failures inside the module are contract violations or
// device loss, not expected outcomes: expected failures (no device, unsupported feature, bad
// shading GLSL) are reported as fovea::Result errors by the public entry points instead.
#pragma once

#include <stdexcept>
#include <string>

#include <vulkan/vulkan.h>

namespace fovea::vk {

const char* result_name(VkResult r);

class VkError : public std::runtime_error {
public:
    VkError(VkResult result, const std::string& what) : std::runtime_error(what), result_(result) {}
    VkResult result() const { return result_; }

private:
    VkResult result_;
};

[[noreturn]] void throw_vk_error(VkResult r, const char* call, const char* file, int line);

}  // namespace fovea::vk

#define VK_CHECK(call)                                                                 \
    do {                                                                               \
        const VkResult fovea_vk_check_r_ = (call);                                     \
        if (fovea_vk_check_r_ != VK_SUCCESS)                                           \
            ::fovea::vk::throw_vk_error(fovea_vk_check_r_, #call, __FILE__, __LINE__); \
    } while (0)
