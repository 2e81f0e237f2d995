// The viewer's own Vulkan instance and device, made as any engine makes them and handed to the
// SDK through fovea::vk::Device::wrap(): a graphics + compute queue and the features
// Device::requirements() names. (No VRS or density map: path 3 needs hardware this example is
// not tested on; the SDK's Foveator says what is missing.)
#pragma once

#include <memory>
#include <string>

#include "fovea/vk/device.hpp"
#include "gltf_viewer/vk_util.hpp"

namespace gltfv {

class HostDevice {
public:
    // prefer_software: a CPU device (lavapipe) even where a GPU exists. validation: the Khronos
    // layer, its errors counted (an error when the layer is not installed).
    static std::unique_ptr<HostDevice> create(bool prefer_software, bool validation,
                                              std::string& error);
    HostDevice(const HostDevice&) = delete;
    HostDevice& operator=(const HostDevice&) = delete;
    ~HostDevice();

    const Gpu& gpu() const { return gpu_; }
    fovea::vk::Device& sdk() { return *sdk_; }
    std::string name() const;
    uint64_t validation_errors() const { return validation_errors_; }

private:
    HostDevice() = default;
    VkInstance instance_ = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
    Gpu gpu_;
    std::unique_ptr<fovea::vk::Device> sdk_;
    uint64_t validation_errors_ = 0;
    friend VKAPI_ATTR VkBool32 VKAPI_CALL
    host_debug_callback(VkDebugUtilsMessageSeverityFlagBitsEXT, VkDebugUtilsMessageTypeFlagsEXT,
                        const VkDebugUtilsMessengerCallbackDataEXT*, void*);
};

}  // namespace gltfv
