#include "gltf_viewer/host_device.hpp"

#include <cstdio>
#include <cstring>
#include <vector>

namespace gltfv {

VKAPI_ATTR VkBool32 VKAPI_CALL host_debug_callback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                   VkDebugUtilsMessageTypeFlagsEXT,
                                                   const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                   void* user) {
    if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
        ++static_cast<HostDevice*>(user)->validation_errors_;
        std::fprintf(stderr, "gltf_viewer: validation: %s\n", data->pMessage);
    }
    return VK_FALSE;
}

std::unique_ptr<HostDevice> HostDevice::create(bool prefer_software, bool validation,
                                               std::string& error) {
    std::unique_ptr<HostDevice> h(new HostDevice);
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "fovea gltf_viewer";
    app.apiVersion = VK_API_VERSION_1_2;
    std::vector<const char*> layers, exts;
    if (validation) {
        uint32_t n = 0;
        vkEnumerateInstanceLayerProperties(&n, nullptr);
        std::vector<VkLayerProperties> l(n);
        vkEnumerateInstanceLayerProperties(&n, l.data());
        for (const auto& x : l)
            if (std::strcmp(x.layerName, "VK_LAYER_KHRONOS_validation") == 0) {
                layers.push_back("VK_LAYER_KHRONOS_validation");
                exts.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
            }
        if (layers.empty()) {  // asked for: never run unchecked in silence
            error =
                "validation asked for but VK_LAYER_KHRONOS_validation is not installed "
                "(Debian: vulkan-validationlayers)";
            return nullptr;
        }
    }
    VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ici.pApplicationInfo = &app;
    ici.enabledLayerCount = uint32_t(layers.size());
    ici.ppEnabledLayerNames = layers.data();
    ici.enabledExtensionCount = uint32_t(exts.size());
    ici.ppEnabledExtensionNames = exts.data();
    if (vkCreateInstance(&ici, nullptr, &h->instance_) != VK_SUCCESS) {
        error = "no Vulkan instance (install mesa-vulkan-drivers)";
        return nullptr;
    }
    if (!layers.empty()) {
        VkDebugUtilsMessengerCreateInfoEXT mci{
            VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
        mci.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
        mci.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
        mci.pfnUserCallback = host_debug_callback;
        mci.pUserData = h.get();
        auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(h->instance_, "vkCreateDebugUtilsMessengerEXT"));
        if (create) create(h->instance_, &mci, nullptr, &h->messenger_);
    }
    uint32_t n = 0;
    vkEnumeratePhysicalDevices(h->instance_, &n, nullptr);
    std::vector<VkPhysicalDevice> devs(n);
    vkEnumeratePhysicalDevices(h->instance_, &n, devs.data());
    int best_score = -1;
    for (VkPhysicalDevice d : devs) {
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(d, &p);
        if (p.apiVersion < VK_API_VERSION_1_2) continue;
        uint32_t qn = 0;
        vkGetPhysicalDeviceQueueFamilyProperties(d, &qn, nullptr);
        std::vector<VkQueueFamilyProperties> q(qn);
        vkGetPhysicalDeviceQueueFamilyProperties(d, &qn, q.data());
        for (uint32_t i = 0; i < qn; ++i) {
            const VkQueueFlags want = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
            if ((q[i].queueFlags & want) != want) continue;
            const bool cpu = p.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
            const int score = cpu == prefer_software ? 2 : 1;
            if (score > best_score) {
                best_score = score;
                h->gpu_.physical = d;
                h->gpu_.queue_family = i;
            }
            break;
        }
    }
    if (!h->gpu_.physical) {
        error = "no Vulkan 1.2 device with a graphics + compute queue";
        return nullptr;
    }
    // What the SDK needs, checked again by Device::wrap().
    VkPhysicalDeviceFeatures supported{};
    vkGetPhysicalDeviceFeatures(h->gpu_.physical, &supported);
    VkPhysicalDeviceFeatures features = fovea::vk::Device::requirements().features;
    features.shaderStorageImageWriteWithoutFormat = supported.shaderStorageImageWriteWithoutFormat;
    const float prio = 1.f;
    VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qci.queueFamilyIndex = h->gpu_.queue_family;
    qci.queueCount = 1;
    qci.pQueuePriorities = &prio;
    VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    dci.queueCreateInfoCount = 1;
    dci.pQueueCreateInfos = &qci;
    dci.pEnabledFeatures = &features;
    if (vkCreateDevice(h->gpu_.physical, &dci, nullptr, &h->gpu_.device) != VK_SUCCESS) {
        error = "vkCreateDevice failed";
        return nullptr;
    }
    vkGetDeviceQueue(h->gpu_.device, h->gpu_.queue_family, 0, &h->gpu_.queue);
    fovea::vk::ExternalDevice ext;
    ext.instance = h->instance_;
    ext.physical = h->gpu_.physical;
    ext.device = h->gpu_.device;
    ext.queue = h->gpu_.queue;
    ext.queue_family = h->gpu_.queue_family;
    ext.api_version = app.apiVersion;
    ext.enabled_features = features;
    auto d = fovea::vk::Device::wrap(ext, [](fovea::vk::LogLevel l, const std::string& m) {
        if (l >= fovea::vk::LogLevel::kWarning) std::fprintf(stderr, "fovea: %s\n", m.c_str());
    });
    if (!d) {
        error = d.error().message;
        return nullptr;
    }
    h->sdk_ = std::make_unique<fovea::vk::Device>(std::move(*d));
    return h;
}

HostDevice::~HostDevice() {
    sdk_.reset();  // waits for the queue, frees its command pool
    if (gpu_.device) vkDestroyDevice(gpu_.device, nullptr);
    if (messenger_) {
        auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
        if (destroy) destroy(instance_, messenger_, nullptr);
    }
    if (instance_) vkDestroyInstance(instance_, nullptr);
}

std::string HostDevice::name() const {
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(gpu_.physical, &p);
    return p.deviceName;
}

}  // namespace gltfv
