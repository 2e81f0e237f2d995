#include "fovea/vk/device.hpp"

#include <atomic>
#include <cassert>
#include <cstdio>
#include <cstring>
#include <mutex>

#include "fovea/vk/check.hpp"
#include "gpu.hpp"

namespace fovea::vk {
namespace {

// Where the validation layer's callback reports (address stable for the messenger's lifetime).
struct DebugSink {
    std::atomic<uint64_t> errors{0};
    LogFn log;
};

void VKAPI_CALL destroy_messenger(VkInstance instance, VkDebugUtilsMessengerEXT messenger,
                                  const VkAllocationCallbacks* allocator) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy) destroy(instance, messenger, allocator);
}
using UniqueMessenger = Unique<VkDebugUtilsMessengerEXT, destroy_messenger, VkInstance>;

}  // namespace

struct Device::Impl {
    // Owned objects in creation order, so they are destroyed in reverse: the command pool and
    // fence, the device, the messenger (which reports the device's leaks), the instance. A wrapped
    // host device owns only the pool and the fence.
    DebugSink sink;
    UniqueInstance owned_instance;
    UniqueMessenger messenger;
    UniqueDevice owned_device;
    UniqueCommandPool pool;
    UniqueFence fence;
    VkCommandBuffer cmd = VK_NULL_HANDLE;  // submit_and_wait's, freed with pool
    VkInstance instance = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    uint32_t family = 0;
    VkPhysicalDeviceProperties props{};
    VkPhysicalDeviceMemoryProperties mem{};
    VrsSupport vrs;
    DensityMapSupport fdm;
    LogFn log;
    mutable std::mutex submit_mutex;  // the command buffer and fence of submit_and_wait
    QueueLock queue_lock;

    // Scope of one use of the queue under the host's lock.
    struct QueueGuard {
        const QueueLock& l;
        explicit QueueGuard(const QueueLock& lock) : l(lock) {
            if (l.lock) l.lock();
        }
        ~QueueGuard() {
            if (l.unlock) l.unlock();
        }
        QueueGuard(const QueueGuard&) = delete;
        QueueGuard& operator=(const QueueGuard&) = delete;
    };

    ~Impl() {
        if (!device) return;
        if (owned_device) {
            vkDeviceWaitIdle(device);
        } else {  // the host's device: wait for our queue only, under its lock
            QueueGuard guard(queue_lock);
            vkQueueWaitIdle(queue);
        }
    }

    void finish_setup() {
        vkGetPhysicalDeviceProperties(physical, &props);
        vkGetPhysicalDeviceMemoryProperties(physical, &mem);
        VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        pci.queueFamilyIndex = family;
        pool = create_handle<UniqueCommandPool>(device, vkCreateCommandPool, pci);
        VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        fence = create_handle<UniqueFence>(device, vkCreateFence, fci);
        VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        ai.commandPool = pool.get();
        ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        ai.commandBufferCount = 1;
        VK_CHECK(vkAllocateCommandBuffers(device, &ai, &cmd));
    }

    bool has_extension(const char* name) const {
        uint32_t n = 0;
        vkEnumerateDeviceExtensionProperties(physical, nullptr, &n, nullptr);
        std::vector<VkExtensionProperties> exts(n);
        vkEnumerateDeviceExtensionProperties(physical, nullptr, &n, exts.data());
        for (const auto& e : exts)
            if (std::strcmp(e.extensionName, name) == 0) return true;
        return false;
    }

    // Fills an extension's properties and features structs (sType set by the caller).
    template <class Properties, class Features>
    void query_extension(Properties& properties, Features& features) const {
        VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
        p2.pNext = &properties;
        vkGetPhysicalDeviceProperties2(physical, &p2);
        VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
        f2.pNext = &features;
        vkGetPhysicalDeviceFeatures2(physical, &f2);
    }

    void query_fdm(bool enabled_on_device) {
        if (!has_extension(VK_EXT_FRAGMENT_DENSITY_MAP_EXTENSION_NAME)) {
            fdm.reason = std::string("device '") + props.deviceName + "' lacks " +
                         VK_EXT_FRAGMENT_DENSITY_MAP_EXTENSION_NAME;
            return;
        }
        VkPhysicalDeviceFragmentDensityMapPropertiesEXT fp{
            VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FRAGMENT_DENSITY_MAP_PROPERTIES_EXT};
        VkPhysicalDeviceFragmentDensityMapFeaturesEXT ff{
            VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FRAGMENT_DENSITY_MAP_FEATURES_EXT};
        query_extension(fp, ff);
        if (!ff.fragmentDensityMap) {
            fdm.reason = "fragmentDensityMap feature missing";
            return;
        }
        fdm.min_texel = fp.minFragmentDensityTexelSize.width;
        fdm.max_texel = fp.maxFragmentDensityTexelSize.width;
        if (!enabled_on_device) {
            fdm.reason = "VK_EXT_fragment_density_map not enabled on the device";
            return;
        }
        fdm.supported = true;
    }

    void query_vrs(bool enabled_on_device) {
        if (!has_extension(VK_KHR_FRAGMENT_SHADING_RATE_EXTENSION_NAME)) {
            vrs.reason = std::string("device '") + props.deviceName + "' lacks " +
                         VK_KHR_FRAGMENT_SHADING_RATE_EXTENSION_NAME;
            return;
        }
        VkPhysicalDeviceFragmentShadingRatePropertiesKHR fsr{
            VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FRAGMENT_SHADING_RATE_PROPERTIES_KHR};
        VkPhysicalDeviceFragmentShadingRateFeaturesKHR ff{
            VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FRAGMENT_SHADING_RATE_FEATURES_KHR};
        query_extension(fsr, ff);
        if (!ff.attachmentFragmentShadingRate) {
            vrs.reason = "attachmentFragmentShadingRate feature missing";
            return;
        }
        vrs.texel_width = fsr.maxFragmentShadingRateAttachmentTexelSize.width;
        vrs.texel_height = fsr.maxFragmentShadingRateAttachmentTexelSize.height;
        if (!enabled_on_device) {
            vrs.reason = "VK_KHR_fragment_shading_rate not enabled on the device";
            return;
        }
        vrs.supported = true;
    }
};

namespace {

VKAPI_ATTR VkBool32 VKAPI_CALL debug_callback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                              VkDebugUtilsMessageTypeFlagsEXT,
                                              const VkDebugUtilsMessengerCallbackDataEXT* data,
                                              void* user) {
    auto* impl = static_cast<DebugSink*>(user);
    if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
        impl->errors.fetch_add(1);
        if (impl->log) impl->log(LogLevel::kError, std::string("validation: ") + data->pMessage);
    } else if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
        if (impl->log) impl->log(LogLevel::kWarning, std::string("validation: ") + data->pMessage);
    }
    return VK_FALSE;
}

std::string version_string(uint32_t v) {
    return std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v));
}

// The features requirements() may ask for, by name for the error message.
struct NamedFeature {
    const char* name;
    VkBool32 VkPhysicalDeviceFeatures::*member;
};
constexpr NamedFeature kCheckedFeatures[] = {
    {"shaderStorageImageExtendedFormats",
     &VkPhysicalDeviceFeatures::shaderStorageImageExtendedFormats},
};

// Every unmet requirement of `ext`, one per line; empty when the device qualifies.
std::string unmet_requirements(const ExternalDevice& ext) {
    const DeviceRequirements req = Device::requirements();
    std::string missing;
    const auto add = [&](const std::string& what) { missing += "\n  - " + what; };
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(ext.physical, &props);
    if (ext.api_version < req.api_version)
        add("ExternalDevice::api_version is " + version_string(ext.api_version) + ", need " +
            version_string(req.api_version) + " (VkApplicationInfo::apiVersion of the instance)");
    if (props.apiVersion < req.api_version)
        add(std::string("device '") + props.deviceName + "' supports Vulkan " +
            version_string(props.apiVersion) + ", need " + version_string(req.api_version));
    uint32_t qn = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(ext.physical, &qn, nullptr);
    std::vector<VkQueueFamilyProperties> families(qn);
    vkGetPhysicalDeviceQueueFamilyProperties(ext.physical, &qn, families.data());
    if (ext.queue_family >= qn)
        add("queue_family " + std::to_string(ext.queue_family) + " does not exist (" +
            std::to_string(qn) + " families)");
    else if ((families[ext.queue_family].queueFlags & req.queue_flags) != req.queue_flags)
        add("queue family " + std::to_string(ext.queue_family) + " has no compute capability");
    for (const NamedFeature& f : kCheckedFeatures)
        if (req.features.*f.member && !(ext.enabled_features.*f.member))
            add(std::string("feature ") + f.name +
                " not enabled (ExternalDevice::enabled_features)");
    for (const DeviceRequirements::Format& f : req.formats) {
        VkFormatProperties fp;
        vkGetPhysicalDeviceFormatProperties(ext.physical, f.format, &fp);
        const VkFormatFeatureFlags lacking = f.features & ~fp.optimalTilingFeatures;
        if (lacking == 0) continue;
        char what[96];
        std::snprintf(what, sizeof(what), "format %d lacks optimal-tiling features 0x%x",
                      static_cast<int>(f.format), static_cast<unsigned>(lacking));
        add(what);
    }
    if (props.limits.maxComputeWorkGroupInvocations < req.min_compute_workgroup_invocations)
        add("maxComputeWorkGroupInvocations " +
            std::to_string(props.limits.maxComputeWorkGroupInvocations) + " < " +
            std::to_string(req.min_compute_workgroup_invocations));
    return missing;
}

bool has_layer(const char* name) {
    uint32_t n = 0;
    vkEnumerateInstanceLayerProperties(&n, nullptr);
    std::vector<VkLayerProperties> layers(n);
    vkEnumerateInstanceLayerProperties(&n, layers.data());
    for (const auto& l : layers)
        if (std::strcmp(l.layerName, name) == 0) return true;
    return false;
}

}  // namespace

Device::Device(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Device::Device(Device&&) noexcept = default;
Device& Device::operator=(Device&&) noexcept = default;
Device::~Device() = default;

Result<Device> Device::create_headless(const DeviceOptions& options) {
    try {
        auto impl = std::make_unique<Impl>();
        impl->log = options.log;
        impl->sink.log = options.log;
        VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
        app.pApplicationName = "fovea";
        app.apiVersion = VK_API_VERSION_1_2;
        std::vector<const char*> layers, exts;
        // Asked-for validation that silently is not there would make "zero validation errors" pass.
        const bool validation = options.validation;
        if (validation && !has_layer("VK_LAYER_KHRONOS_validation"))
            return make_error(
                "validation requested but VK_LAYER_KHRONOS_validation is not installed "
                "(Debian: vulkan-validationlayers)",
                static_cast<int>(VK_ERROR_LAYER_NOT_PRESENT));
        if (validation) {
            layers.push_back("VK_LAYER_KHRONOS_validation");
            exts.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
        }
        VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
        ici.pApplicationInfo = &app;
        ici.enabledLayerCount = static_cast<uint32_t>(layers.size());
        ici.ppEnabledLayerNames = layers.data();
        ici.enabledExtensionCount = static_cast<uint32_t>(exts.size());
        ici.ppEnabledExtensionNames = exts.data();
        VkInstance instance = VK_NULL_HANDLE;
        VkResult r = vkCreateInstance(&ici, nullptr, &instance);
        if (r != VK_SUCCESS)
            return make_error(std::string("no Vulkan instance: ") + result_name(r));
        impl->owned_instance = UniqueInstance(instance);
        impl->instance = instance;
        if (validation) {
            VkDebugUtilsMessengerCreateInfoEXT mci{
                VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
            mci.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT |
                                  VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT;
            mci.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                              VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
            mci.pfnUserCallback = debug_callback;
            mci.pUserData = &impl->sink;
            auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(impl->instance, "vkCreateDebugUtilsMessengerEXT"));
            if (!create)
                return make_error(
                    "validation requested but vkCreateDebugUtilsMessengerEXT is missing",
                    static_cast<int>(VK_ERROR_EXTENSION_NOT_PRESENT));
            VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
            VK_CHECK(create(impl->instance, &mci, nullptr, &messenger));
            impl->messenger = UniqueMessenger(impl->instance, messenger);
        }
        uint32_t n = 0;
        vkEnumeratePhysicalDevices(impl->instance, &n, nullptr);
        std::vector<VkPhysicalDevice> devs(n);
        vkEnumeratePhysicalDevices(impl->instance, &n, devs.data());
        int best = -1, best_score = -1;
        uint32_t best_family = 0;
        for (uint32_t i = 0; i < n; ++i) {
            VkPhysicalDeviceProperties p;
            vkGetPhysicalDeviceProperties(devs[i], &p);
            if (p.apiVersion < VK_API_VERSION_1_1) continue;
            uint32_t qn = 0;
            vkGetPhysicalDeviceQueueFamilyProperties(devs[i], &qn, nullptr);
            std::vector<VkQueueFamilyProperties> q(qn);
            vkGetPhysicalDeviceQueueFamilyProperties(devs[i], &qn, q.data());
            int fam = -1;
            for (uint32_t k = 0; k < qn; ++k)
                if (q[k].queueFlags & VK_QUEUE_COMPUTE_BIT) {
                    fam = static_cast<int>(k);
                    break;
                }
            if (fam < 0) continue;
            const bool cpu = p.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
            int score = cpu == options.prefer_software ? 2 : 1;
            if (score > best_score) {
                best = static_cast<int>(i);
                best_score = score;
                best_family = static_cast<uint32_t>(fam);
            }
        }
        if (best < 0) return make_error("no Vulkan 1.1 device with a compute queue");
        impl->physical = devs[best];
        impl->family = best_family;
        const float prio = 1.0f;
        VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
        qci.queueFamilyIndex = best_family;
        qci.queueCount = 1;
        qci.pQueuePriorities = &prio;
        VkPhysicalDeviceFeatures supported{};
        vkGetPhysicalDeviceFeatures(impl->physical, &supported);
        VkPhysicalDeviceFeatures features{};
        features.shaderStorageImageWriteWithoutFormat =
            supported.shaderStorageImageWriteWithoutFormat;
        features.shaderStorageImageExtendedFormats = supported.shaderStorageImageExtendedFormats;
        VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
        dci.queueCreateInfoCount = 1;
        dci.pQueueCreateInfos = &qci;
        dci.pEnabledFeatures = &features;
        VkDevice device = VK_NULL_HANDLE;
        r = vkCreateDevice(impl->physical, &dci, nullptr, &device);
        if (r != VK_SUCCESS) return make_error(std::string("vkCreateDevice: ") + result_name(r));
        impl->owned_device = UniqueDevice(device);
        impl->device = device;
        vkGetDeviceQueue(impl->device, best_family, 0, &impl->queue);
        ExternalDevice self{impl->instance, impl->physical, impl->device, impl->queue,
                            best_family,    app.apiVersion, features};
        if (const std::string missing = unmet_requirements(self); !missing.empty())
            return make_error("the Vulkan device does not meet Device::requirements():" + missing);
        impl->finish_setup();
        // A headless compute device has no rasterizer use for VRS; report what the GPU offers.
        impl->query_vrs(false);
        impl->query_fdm(false);
        return Device(std::move(impl));
    } catch (const VkError& e) { return make_error(e.what(), static_cast<int>(e.result())); }
}

DeviceRequirements Device::requirements() {
    DeviceRequirements r;
    r.features.shaderStorageImageExtendedFormats = VK_TRUE;
    constexpr VkFormatFeatureFlags kStorage = VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT;
    constexpr VkFormatFeatureFlags kSampled =
        VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT | VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT;
    r.formats = {
        {VK_FORMAT_R16G16B16A16_SFLOAT, kStorage | kSampled},
        {VK_FORMAT_R32G32B32A32_SFLOAT, kStorage},
        {VK_FORMAT_R8G8B8A8_UNORM, kStorage},
        {VK_FORMAT_R32_SFLOAT, kStorage},
        {VK_FORMAT_R16_SFLOAT, kStorage},
        {VK_FORMAT_R16G16_SFLOAT, kStorage},
        {VK_FORMAT_R8_UINT, kStorage},
    };
    return r;
}

Result<Device> Device::wrap(const ExternalDevice& ext, LogFn log) {
    if (!ext.instance || !ext.physical || !ext.device || !ext.queue)
        return make_error("ExternalDevice: instance, physical, device and queue are required");
    if (const std::string missing = unmet_requirements(ext); !missing.empty())
        return make_error(
            "Device::wrap: the host's device does not meet "
            "Device::requirements():" +
            missing);
    try {
        auto impl = std::make_unique<Impl>();
        impl->log = std::move(log);
        impl->instance = ext.instance;
        impl->physical = ext.physical;
        impl->device = ext.device;
        impl->queue = ext.queue;
        impl->family = ext.queue_family;
        impl->queue_lock = ext.queue_lock;
        impl->finish_setup();
        impl->query_vrs(ext.fragment_shading_rate_enabled);
        impl->query_fdm(ext.fragment_density_map_enabled);
        return Device(std::move(impl));
    } catch (const VkError& e) { return make_error(e.what(), static_cast<int>(e.result())); }
}

VkInstance Device::instance() const { return impl_->instance; }
VkPhysicalDevice Device::physical() const { return impl_->physical; }
VkDevice Device::device() const { return impl_->device; }
VkQueue Device::queue() const { return impl_->queue; }
uint32_t Device::queue_family() const { return impl_->family; }
const VkPhysicalDeviceProperties& Device::properties() const { return impl_->props; }
std::string Device::name() const { return impl_->props.deviceName; }
bool Device::is_software() const { return impl_->props.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU; }
VrsSupport Device::vrs_support() const { return impl_->vrs; }
DensityMapSupport Device::density_map_support() const { return impl_->fdm; }
uint64_t Device::validation_errors() const { return impl_->sink.errors.load(); }
bool Device::validation_enabled() const { return static_cast<bool>(impl_->messenger); }
const LogFn& Device::log() const { return impl_->log; }
void Device::log(LogLevel level, const std::string& message) const {
    if (impl_->log) impl_->log(level, message);
}

uint32_t Device::memory_type(uint32_t type_bits, VkMemoryPropertyFlags required) const {
    for (uint32_t i = 0; i < impl_->mem.memoryTypeCount; ++i)
        if ((type_bits & (1u << i)) &&
            (impl_->mem.memoryTypes[i].propertyFlags & required) == required)
            return i;
    assert(!"no memory type with the required properties");
    return 0;
}

void Device::wait_idle() const {
    Impl::QueueGuard guard(impl_->queue_lock);
    VK_CHECK(vkQueueWaitIdle(impl_->queue));
}

void Device::submit_and_wait(const std::function<void(VkCommandBuffer)>& record) const {
    std::lock_guard<std::mutex> lock(impl_->submit_mutex);
    const VkCommandBuffer cmd = impl_->cmd;
    const VkFence fence = impl_->fence.get();
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK_CHECK(vkBeginCommandBuffer(cmd, &bi));  // resets it (the pool allows reset)
    try {
        record(cmd);
        VK_CHECK(vkEndCommandBuffer(cmd));
        VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        si.commandBufferCount = 1;
        si.pCommandBuffers = &cmd;
        VK_CHECK(vkResetFences(impl_->device, 1, &fence));
        Impl::QueueGuard guard(impl_->queue_lock);  // only around the submission
        VK_CHECK(vkQueueSubmit(impl_->queue, 1, &si, fence));
    } catch (...) {
        vkResetCommandBuffer(cmd, 0);  // half-recorded or never submitted: back to initial
        throw;
    }
    VK_CHECK(vkWaitForFences(impl_->device, 1, &fence, VK_TRUE, UINT64_MAX));
}

uint32_t format_bytes(VkFormat f) {
    switch (f) {
        case VK_FORMAT_R8_UINT:
        case VK_FORMAT_R8_UNORM: return 1;
        case VK_FORMAT_R16_SFLOAT:
        case VK_FORMAT_R8G8_UNORM: return 2;
        case VK_FORMAT_R8G8B8A8_UNORM:
        case VK_FORMAT_R8G8B8A8_SRGB:
        case VK_FORMAT_R32_SFLOAT:
        case VK_FORMAT_R32_UINT:
        case VK_FORMAT_R16G16_SFLOAT: return 4;
        case VK_FORMAT_R16G16B16A16_SFLOAT:
        case VK_FORMAT_R32G32_SFLOAT: return 8;
        case VK_FORMAT_R32G32B32A32_SFLOAT:
        case VK_FORMAT_R32G32B32A32_UINT: return 16;
        default: assert(!"format_bytes: unexpected format"); return 0;
    }
}

std::vector<uint8_t> Device::read_image(const ImageRef& image) const {
    const VkDeviceSize bytes = static_cast<VkDeviceSize>(image.extent.width) * image.extent.height *
                               format_bytes(image.format);
    const Buffer staging(*this, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, /*host_visible=*/true);
    submit_and_wait([&](VkCommandBuffer cmd) {
        VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        mb.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
        mb.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                             VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &mb, 0, nullptr, 0, nullptr);
        VkBufferImageCopy region{};
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.imageExtent = {image.extent.width, image.extent.height, 1};
        vkCmdCopyImageToBuffer(cmd, image.image, VK_IMAGE_LAYOUT_GENERAL, staging.get(), 1,
                               &region);
        VkMemoryBarrier hb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        hb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        hb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1,
                             &hb, 0, nullptr, 0, nullptr);
    });
    std::vector<uint8_t> out(bytes);
    std::memcpy(out.data(), staging.data(), bytes);
    return out;
}

}  // namespace fovea::vk
