// A host's own Vulkan instance and device, made the way an application makes them (not through
// the module), for tests of Device::wrap(). Move-only RAII; `ok()` false without a Vulkan driver.
#pragma once

#include <cstring>
#include <vector>

#include <vulkan/vulkan.h>

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
        if (vkCreateInstance(&ici, nullptr, &instance_) != VK_SUCCESS) return;
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
        if (instance_) vkDestroyInstance(instance_, nullptr);
    }

    bool ok() const { return queue_ != VK_NULL_HANDLE; }
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
    uint32_t api_version_;
    VkPhysicalDeviceFeatures features_;
    VkInstance instance_ = VK_NULL_HANDLE;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    uint32_t family_ = 0;
};

}  // namespace fovea::vk::test
