#include "fovea/vk/device.hpp"

#include <atomic>
#include <cassert>
#include <cstring>
#include <mutex>

#include "fovea/vk/check.hpp"

namespace fovea::vk {
namespace {

// Where the validation layer's callback reports (address stable for the messenger's lifetime).
struct DebugSink {
    std::atomic<uint64_t> errors{0};
    LogFn log;
};

}  // namespace

struct Device::Impl {
    bool owns = false;
    VkInstance instance = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    uint32_t family = 0;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    VkPhysicalDeviceProperties props{};
    VkPhysicalDeviceMemoryProperties mem{};
    VrsSupport vrs;
    LogFn log;
    DebugSink sink;
    VkCommandPool pool = VK_NULL_HANDLE;
    VkFence fence = VK_NULL_HANDLE;
    mutable std::mutex queue_mutex;

    ~Impl() {
        if (device) {
            vkDeviceWaitIdle(device);
            if (fence) vkDestroyFence(device, fence, nullptr);
            if (pool) vkDestroyCommandPool(device, pool, nullptr);
        }
        if (!owns) return;
        if (device) vkDestroyDevice(device, nullptr);
        if (messenger) {
            auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
            if (destroy) destroy(instance, messenger, nullptr);
        }
        if (instance) vkDestroyInstance(instance, nullptr);
    }

    void finish_setup() {
        vkGetPhysicalDeviceProperties(physical, &props);
        vkGetPhysicalDeviceMemoryProperties(physical, &mem);
        VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        pci.queueFamilyIndex = family;
        VK_CHECK(vkCreateCommandPool(device, &pci, nullptr, &pool));
        VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        VK_CHECK(vkCreateFence(device, &fci, nullptr, &fence));
    }

    void query_vrs(bool enabled_on_device) {
        uint32_t n = 0;
        vkEnumerateDeviceExtensionProperties(physical, nullptr, &n, nullptr);
        std::vector<VkExtensionProperties> exts(n);
        vkEnumerateDeviceExtensionProperties(physical, nullptr, &n, exts.data());
        bool has = false;
        for (const auto& e : exts)
            if (std::strcmp(e.extensionName, VK_KHR_FRAGMENT_SHADING_RATE_EXTENSION_NAME) == 0)
                has = true;
        if (!has) {
            vrs.reason = std::string("device '") + props.deviceName + "' lacks " +
                         VK_KHR_FRAGMENT_SHADING_RATE_EXTENSION_NAME;
            return;
        }
        VkPhysicalDeviceFragmentShadingRatePropertiesKHR fsr{
            VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FRAGMENT_SHADING_RATE_PROPERTIES_KHR};
        VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
        p2.pNext = &fsr;
        vkGetPhysicalDeviceProperties2(physical, &p2);
        VkPhysicalDeviceFragmentShadingRateFeaturesKHR ff{
            VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FRAGMENT_SHADING_RATE_FEATURES_KHR};
        VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
        f2.pNext = &ff;
        vkGetPhysicalDeviceFeatures2(physical, &f2);
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
        impl->owns = true;
        impl->log = options.log;
        impl->sink.log = options.log;
        VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
        app.pApplicationName = "fovea";
        app.apiVersion = VK_API_VERSION_1_2;
        std::vector<const char*> layers, exts;
        const bool validation = options.validation && has_layer("VK_LAYER_KHRONOS_validation");
        if (options.validation && !validation && options.log)
            options.log(LogLevel::kWarning, "VK_LAYER_KHRONOS_validation not installed");
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
        VkResult r = vkCreateInstance(&ici, nullptr, &impl->instance);
        if (r != VK_SUCCESS)
            return make_error(std::string("no Vulkan instance: ") + result_name(r));
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
            if (create) VK_CHECK(create(impl->instance, &mci, nullptr, &impl->messenger));
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
                if (q[k].queueFlags & VK_QUEUE_COMPUTE_BIT) { fam = static_cast<int>(k); break; }
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
        r = vkCreateDevice(impl->physical, &dci, nullptr, &impl->device);
        if (r != VK_SUCCESS) return make_error(std::string("vkCreateDevice: ") + result_name(r));
        vkGetDeviceQueue(impl->device, best_family, 0, &impl->queue);
        impl->finish_setup();
        // A headless compute device has no rasterizer use for VRS; report what the GPU offers.
        impl->query_vrs(false);
        return Device(std::move(impl));
    } catch (const VkError& e) {
        return make_error(e.what(), static_cast<int>(e.result()));
    }
}

Result<Device> Device::wrap(const ExternalDevice& ext, LogFn log) {
    if (!ext.instance || !ext.physical || !ext.device || !ext.queue)
        return make_error("ExternalDevice: instance, physical, device and queue are required");
    try {
        auto impl = std::make_unique<Impl>();
        impl->owns = false;
        impl->log = std::move(log);
        impl->instance = ext.instance;
        impl->physical = ext.physical;
        impl->device = ext.device;
        impl->queue = ext.queue;
        impl->family = ext.queue_family;
        impl->finish_setup();
        impl->query_vrs(ext.fragment_shading_rate_enabled);
        return Device(std::move(impl));
    } catch (const VkError& e) {
        return make_error(e.what(), static_cast<int>(e.result()));
    }
}

VkInstance Device::instance() const { return impl_->instance; }
VkPhysicalDevice Device::physical() const { return impl_->physical; }
VkDevice Device::device() const { return impl_->device; }
VkQueue Device::queue() const { return impl_->queue; }
uint32_t Device::queue_family() const { return impl_->family; }
const VkPhysicalDeviceProperties& Device::properties() const { return impl_->props; }
std::string Device::name() const { return impl_->props.deviceName; }
bool Device::is_software() const {
    return impl_->props.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
}
VrsSupport Device::vrs_support() const { return impl_->vrs; }
uint64_t Device::validation_errors() const { return impl_->sink.errors.load(); }
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

void Device::submit_and_wait(const std::function<void(VkCommandBuffer)>& record) const {
    std::lock_guard<std::mutex> lock(impl_->queue_mutex);
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = impl_->pool;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VK_CHECK(vkAllocateCommandBuffers(impl_->device, &ai, &cmd));
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK_CHECK(vkBeginCommandBuffer(cmd, &bi));
    record(cmd);
    VK_CHECK(vkEndCommandBuffer(cmd));
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cmd;
    VK_CHECK(vkResetFences(impl_->device, 1, &impl_->fence));
    VK_CHECK(vkQueueSubmit(impl_->queue, 1, &si, impl_->fence));
    VK_CHECK(vkWaitForFences(impl_->device, 1, &impl_->fence, VK_TRUE, UINT64_MAX));
    vkFreeCommandBuffers(impl_->device, impl_->pool, 1, &cmd);
}

uint32_t format_bytes(VkFormat f) {
    switch (f) {
        case VK_FORMAT_R8_UINT:
        case VK_FORMAT_R8_UNORM: return 1;
        case VK_FORMAT_R16_SFLOAT: return 2;
        case VK_FORMAT_R8G8B8A8_UNORM:
        case VK_FORMAT_R8G8B8A8_SRGB:
        case VK_FORMAT_R32_SFLOAT:
        case VK_FORMAT_R32_UINT:
        case VK_FORMAT_R16G16_SFLOAT: return 4;
        case VK_FORMAT_R16G16B16A16_SFLOAT:
        case VK_FORMAT_R32G32_SFLOAT: return 8;
        case VK_FORMAT_R32G32B32A32_SFLOAT: return 16;
        default: assert(!"format_bytes: unexpected format"); return 0;
    }
}

std::vector<uint8_t> Device::read_image(const ImageRef& image) const {
    const VkDeviceSize bytes = static_cast<VkDeviceSize>(image.extent.width) *
                               image.extent.height * format_bytes(image.format);
    VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bci.size = bytes;
    bci.usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    VkBuffer buf = VK_NULL_HANDLE;
    VK_CHECK(vkCreateBuffer(impl_->device, &bci, nullptr, &buf));
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(impl_->device, buf, &req);
    VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    mai.allocationSize = req.size;
    mai.memoryTypeIndex = memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                                              VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    VkDeviceMemory mem = VK_NULL_HANDLE;
    VK_CHECK(vkAllocateMemory(impl_->device, &mai, nullptr, &mem));
    VK_CHECK(vkBindBufferMemory(impl_->device, buf, mem, 0));
    submit_and_wait([&](VkCommandBuffer cmd) {
        VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        mb.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
        mb.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                             VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &mb, 0, nullptr, 0, nullptr);
        VkBufferImageCopy region{};
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.imageExtent = {image.extent.width, image.extent.height, 1};
        vkCmdCopyImageToBuffer(cmd, image.image, VK_IMAGE_LAYOUT_GENERAL, buf, 1, &region);
        VkMemoryBarrier hb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        hb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        hb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0,
                             1, &hb, 0, nullptr, 0, nullptr);
    });
    std::vector<uint8_t> out(bytes);
    void* p = nullptr;
    VK_CHECK(vkMapMemory(impl_->device, mem, 0, bytes, 0, &p));
    std::memcpy(out.data(), p, bytes);
    vkUnmapMemory(impl_->device, mem);
    vkDestroyBuffer(impl_->device, buf, nullptr);
    vkFreeMemory(impl_->device, mem, nullptr);
    return out;
}

}  // namespace fovea::vk
