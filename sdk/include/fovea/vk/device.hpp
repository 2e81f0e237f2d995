// fovea::vk::Device: the Vulkan instance/physical device/device/queue the foveation module runs
// on. Either the host's own objects (wrap(): nothing is destroyed, the host keeps ownership) or a
// headless device the module creates (create_headless(): lavapipe or any compute-capable GPU,
// optionally with validation layers). Move-only; destroying it destroys what it owns.
//
// Threads: create/wrap/destroy on any one thread. submit_and_wait() and read_image() lock the
// queue internally; a wrapped host queue must not be used by the host concurrently with them.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "fovea/result.hpp"

namespace fovea::vk {

enum class LogLevel { kDebug, kInfo, kWarning, kError };
// The SDK never installs a global logger; hosts pass a callback (may be called from any thread
// that calls into the module, and from the validation layer's callback).
using LogFn = std::function<void(LogLevel, const std::string&)>;

struct DeviceOptions {
    bool validation = false;       // VK_LAYER_KHRONOS_validation + debug messenger counting errors
    bool prefer_software = false;  // pick a CPU device (lavapipe) even when a GPU exists
    LogFn log;
};

// The host's objects, when the host already has a device. The queue must support compute.
struct ExternalDevice {
    VkInstance instance = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    uint32_t queue_family = 0;
    // Set when the host enabled VK_KHR_fragment_shading_rate with attachment rates on `device`.
    bool fragment_shading_rate_enabled = false;
};

// VK_KHR_fragment_shading_rate attachment support as the device reports it.
struct VrsSupport {
    bool supported = false;          // extension present and attachmentFragmentShadingRate
    uint32_t texel_width = 16;       // maxFragmentShadingRateAttachmentTexelSize (or default)
    uint32_t texel_height = 16;
    std::string reason;              // why not, when unsupported
};

// An image in VK_IMAGE_LAYOUT_GENERAL as the module hands it out.
struct ImageRef {
    VkImage image = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
    VkExtent2D extent{0, 0};
};

class Device {
public:
    static Result<Device> create_headless(const DeviceOptions& options = {});
    static Result<Device> wrap(const ExternalDevice& external, LogFn log = {});

    Device(Device&&) noexcept;
    Device& operator=(Device&&) noexcept;
    Device(const Device&) = delete;
    Device& operator=(const Device&) = delete;
    ~Device();

    VkInstance instance() const;
    VkPhysicalDevice physical() const;
    VkDevice device() const;
    VkQueue queue() const;
    uint32_t queue_family() const;
    const VkPhysicalDeviceProperties& properties() const;
    std::string name() const;  // e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
    bool is_software() const;  // VK_PHYSICAL_DEVICE_TYPE_CPU
    VrsSupport vrs_support() const;

    // Memory type index with all `required` flags among `type_bits`; asserts one exists.
    uint32_t memory_type(uint32_t type_bits, VkMemoryPropertyFlags required) const;

    // Records with `record` into a one-time command buffer, submits it and waits. Blocking.
    void submit_and_wait(const std::function<void(VkCommandBuffer)>& record) const;

    // Copies an image (GENERAL layout, 2D, one mip) to host memory, tightly packed. Blocking.
    std::vector<uint8_t> read_image(const ImageRef& image) const;

    // Validation messages of severity error seen so far (own instance with validation only).
    uint64_t validation_errors() const;
    const LogFn& log() const;
    void log(LogLevel level, const std::string& message) const;

private:
    struct Impl;
    explicit Device(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

// Bytes per texel of the formats the module uses (asserts on others).
uint32_t format_bytes(VkFormat format);

}  // namespace fovea::vk
