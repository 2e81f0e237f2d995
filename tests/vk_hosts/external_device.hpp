// A host's own Vulkan instance and device, made the way an application makes them (not through
// the module), for tests of Device::wrap(). With FOVEA_VK_VALIDATION the host enables
// VK_LAYER_KHRONOS_validation itself and counts its errors, as a host app debugging its own
// instance would; the module's work on the wrapped device is then checked too. Not movable;
// `ok()` false without a Vulkan driver or, with validation asked for, without the layer.
#pragma once

#include <atomic>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "../support/vk_test_device.hpp"
#include "fovea/vk/device.hpp"

namespace fovea::vk::test {

class HostVulkan {
public:
    // api_version: VkApplicationInfo::apiVersion; features: what the host enables.
    HostVulkan(uint32_t api_version, const VkPhysicalDeviceFeatures& features)
        : api_version_(api_version), features_(features) {
        VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
        app.pApplicationName = "fovea host test";
        app.apiVersion = api_version;
        VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
        ici.pApplicationInfo = &app;
        const char* layer = "VK_LAYER_KHRONOS_validation";
        const char* debug_utils = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
        VkDebugUtilsMessengerCreateInfoEXT messenger{
            VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
        messenger.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                    VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
        messenger.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                                VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                                VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
        messenger.pfnUserCallback = &HostVulkan::on_message;
        messenger.pUserData = this;
        if (kValidation) {
            ici.enabledLayerCount = 1;
            ici.ppEnabledLayerNames = &layer;
            ici.enabledExtensionCount = 1;
            ici.ppEnabledExtensionNames = &debug_utils;
            ici.pNext = &messenger;  // also covers vkCreateInstance / vkDestroyInstance
        }
        const VkResult created = vkCreateInstance(&ici, nullptr, &instance_);
        if (created == VK_ERROR_LAYER_NOT_PRESENT || created == VK_ERROR_EXTENSION_NOT_PRESENT) {
            missing_ = std::string(layer) + " requested (FOVEA_VK_VALIDATION) but not installed";
            return;
        }
        if (created != VK_SUCCESS) return;
        if (kValidation) {
            auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
            if (!create || create(instance_, &messenger, nullptr, &messenger_) != VK_SUCCESS) {
                missing_ = "vkCreateDebugUtilsMessengerEXT failed";
                return;
            }
        }
        uint32_t n = 0;
        vkEnumeratePhysicalDevices(instance_, &n, nullptr);
        std::vector<VkPhysicalDevice> devs(n);
        vkEnumeratePhysicalDevices(instance_, &n, devs.data());
        for (VkPhysicalDevice d : devs) {  // lavapipe when present, as the module's tests use
            VkPhysicalDeviceProperties p;
            vkGetPhysicalDeviceProperties(d, &p);
            if (!physical_ || p.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU) physical_ = d;
        }
        if (!physical_) return;
        uint32_t qn = 0;
        vkGetPhysicalDeviceQueueFamilyProperties(physical_, &qn, nullptr);
        std::vector<VkQueueFamilyProperties> q(qn);
        vkGetPhysicalDeviceQueueFamilyProperties(physical_, &qn, q.data());
        for (uint32_t i = 0; i < qn; ++i)
            if ((q[i].queueFlags & (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT)) ==
                (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT)) {
                family_ = i;
                break;
            }
        const float prio = 1.f;
        VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
        qci.queueFamilyIndex = family_;
        qci.queueCount = 1;
        qci.pQueuePriorities = &prio;
        VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
        dci.queueCreateInfoCount = 1;
        dci.pQueueCreateInfos = &qci;
        dci.pEnabledFeatures = &features_;
        if (vkCreateDevice(physical_, &dci, nullptr, &device_) != VK_SUCCESS) return;
        vkGetDeviceQueue(device_, family_, 0, &queue_);
    }
    HostVulkan(const HostVulkan&) = delete;
    HostVulkan& operator=(const HostVulkan&) = delete;
    ~HostVulkan() {
        if (device_) vkDestroyDevice(device_, nullptr);
        if (messenger_) {
            auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
            if (destroy) destroy(instance_, messenger_, nullptr);
        }
        if (instance_) vkDestroyInstance(instance_, nullptr);
    }

    bool ok() const { return queue_ != VK_NULL_HANDLE; }
    // Why validation, asked for by the build, could not be had ("" when it could, or was not
    // asked).
    const std::string& validation_missing() const { return missing_; }
    // Validation messages of severity error since the instance was made (0 without validation).
    uint64_t validation_errors() const { return errors_.load(); }
    ExternalDevice external() const {
        ExternalDevice e;
        e.instance = instance_;
        e.physical = physical_;
        e.device = device_;
        e.queue = queue_;
        e.queue_family = family_;
        e.api_version = api_version_;
        e.enabled_features = features_;
        return e;
    }
    VkDevice device() const { return device_; }
    VkPhysicalDevice physical() const { return physical_; }

    // What requirements() asks for, as a host would copy it into VkDeviceCreateInfo.
    static VkPhysicalDeviceFeatures required_features() { return Device::requirements().features; }

private:
    static VkBool32 VKAPI_PTR on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                         VkDebugUtilsMessageTypeFlagsEXT,
                                         const VkDebugUtilsMessengerCallbackDataEXT* data,
                                         void* self) {
        if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT)
            ++static_cast<HostVulkan*>(self)->errors_;
        std::fprintf(stderr, "[host vk] %s\n", data && data->pMessage ? data->pMessage : "");
        return VK_FALSE;
    }

    uint32_t api_version_;
    VkPhysicalDeviceFeatures features_;
    VkInstance instance_ = VK_NULL_HANDLE;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    uint32_t family_ = 0;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
    std::string missing_;
    std::atomic<uint64_t> errors_{0};
};

}  // namespace fovea::vk::test

// In a test body: fails when the build asked for validation and the host could not have it,
// skips without a Vulkan device.
#define FOVEA_ASSERT_HOST_VULKAN(host)                                                         \
    do {                                                                                       \
        if (!(host).validation_missing().empty()) GTEST_FAIL() << (host).validation_missing(); \
        if (!(host).ok()) GTEST_SKIP() << "no Vulkan device";                                  \
        if (!::fovea::vk::test::kValidation)                                                   \
            std::fprintf(stderr, "%s\n", ::fovea::vk::test::kValidationOff);                   \
    } while (0)

// At the end of a test: the host's validation layer saw no error; with validation off, a loud skip.
#define FOVEA_EXPECT_NO_HOST_VALIDATION_ERRORS(host)                                            \
    do {                                                                                        \
        if (!::fovea::vk::test::kValidation) GTEST_SKIP() << ::fovea::vk::test::kValidationOff; \
        EXPECT_EQ((host).validation_errors(), 0u) << "Vulkan validation errors";                \
    } while (0)
