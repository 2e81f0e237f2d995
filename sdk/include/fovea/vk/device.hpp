// fovea::vk::Device: the Vulkan instance/physical device/device/queue the foveation module runs
// on. Either the host's own objects (wrap(): nothing is destroyed, the host keeps ownership) or a
// headless device the module creates (create_headless(): lavapipe or any compute-capable GPU,
// optionally with validation layers). Move-only; destroying it destroys what it owns.
//
// Threads: create/wrap/destroy on any one thread. submit_and_wait(), read_image(), wait_idle()
// may be called from any thread; they serialize among themselves and take the queue lock
// (ExternalDevice::queue_lock) around every use of the queue, so a host that submits to the same
// queue from other threads shares its lock with the module instead of stopping them.
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
    // VK_LAYER_KHRONOS_validation + a debug messenger counting errors; create_headless() fails
    // (code VK_ERROR_LAYER_NOT_PRESENT) when the layer is not installed.
    bool validation = false;
    bool prefer_software = false;  // pick a CPU device (lavapipe) even when a GPU exists
    LogFn log;
};

// What the module needs of a device (Device::requirements()); Device::wrap() checks a host's
// device against it and names what is missing. The headless device meets it by construction.
struct DeviceRequirements {
    // Instance and device API version: the shaders are SPIR-V 1.3 (Vulkan 1.1).
    uint32_t api_version = VK_API_VERSION_1_1;
    // The queue the host submits record() on, and the module's own submissions.
    VkQueueFlags queue_flags = VK_QUEUE_COMPUTE_BIT;
    // Device features the host must enable (VkDeviceCreateInfo::pEnabledFeatures or
    // VkPhysicalDeviceFeatures2::features): shaderStorageImageExtendedFormats (the R16F, RG16F
    // and R8_UINT storage images). Every other member is false.
    VkPhysicalDeviceFeatures features{};
    // Optimal-tiling format features the module's images need (storage, and linear filtering of
    // the sampled RGBA16F ones).
    struct Format {
        VkFormat format;
        VkFormatFeatureFlags features;
    };
    std::vector<Format> formats;
    uint32_t min_compute_workgroup_invocations = 256;  // 16x16 workgroups (spec minimum: 128)
    // Not required, used when present: timestampComputeAndGraphics (FrameStats GPU times),
    // VK_KHR_fragment_shading_rate (VrsAttachment).
};

// The host's queue lock: the module calls lock() before and unlock() after each of its own
// vkQueueSubmit / vkQueueWaitIdle on the wrapped queue (Vulkan requires external
// synchronisation of a VkQueue). Both empty: the host promises not to use the queue concurrently
// with the module's blocking calls.
struct QueueLock {
    std::function<void()> lock;
    std::function<void()> unlock;
};

// The host's objects, when the host already has a device.
struct ExternalDevice {
    VkInstance instance = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    uint32_t queue_family = 0;  // of `queue`: must have DeviceRequirements::queue_flags
    // VkApplicationInfo::apiVersion the host created `instance` with (the effective version is
    // the lower of it and the device's).
    uint32_t api_version = VK_API_VERSION_1_0;
    // The features the host enabled on `device`: wrap() checks DeviceRequirements::features.
    VkPhysicalDeviceFeatures enabled_features{};
    // Set when the host enabled VK_KHR_fragment_shading_rate with attachment rates on `device`.
    bool fragment_shading_rate_enabled = false;
    // Set when the host enabled VK_EXT_fragment_density_map (feature fragmentDensityMap).
    bool fragment_density_map_enabled = false;
    QueueLock queue_lock;
};

// VK_KHR_fragment_shading_rate attachment support as the device reports it.
struct VrsSupport {
    bool supported = false;     // extension present and attachmentFragmentShadingRate
    uint32_t texel_width = 16;  // maxFragmentShadingRateAttachmentTexelSize (or default)
    uint32_t texel_height = 16;
    std::string reason;  // why not, when unsupported
};

// VK_EXT_fragment_density_map support as the device reports it.
struct DensityMapSupport {
    bool supported = false;   // extension present, feature fragmentDensityMap, enabled
    uint32_t min_texel = 16;  // minFragmentDensityTexelSize (width; square texels used)
    uint32_t max_texel = 16;  // maxFragmentDensityTexelSize
    std::string reason;       // why not, when unsupported
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
    // Fails, naming each unmet requirement, when the host's device, queue or enabled features
    // fall short of requirements().
    static Result<Device> wrap(const ExternalDevice& external, LogFn log = {});
    static DeviceRequirements requirements();

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
    DensityMapSupport density_map_support() const;

    // Memory type index with all `required` flags among `type_bits`; asserts one exists.
    uint32_t memory_type(uint32_t type_bits, VkMemoryPropertyFlags required) const;

    // Records with `record` into a one-time command buffer, submits it and waits. Blocking; the
    // queue lock is held only around the submission, not while waiting.
    void submit_and_wait(const std::function<void(VkCommandBuffer)>& record) const;
    // vkQueueWaitIdle under the queue lock. Blocking.
    void wait_idle() const;

    // Copies an image (GENERAL layout, 2D, one mip) to host memory, tightly packed. Blocking.
    std::vector<uint8_t> read_image(const ImageRef& image) const;

    // Validation messages of severity error seen so far (own instance with validation only).
    uint64_t validation_errors() const;
    // True when validation_errors() counts: a headless device created with validation.
    bool validation_enabled() const;
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
