#include "vk_fault.hpp"

#include <dlfcn.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <set>

#include <vulkan/vulkan.h>

namespace fovea::vk::test::fault {
namespace {

struct State {
    std::mutex mutex;
    long fail_at = -1;
    long calls = 0;
    std::string injected;
    std::map<std::string, std::set<uint64_t>> live;
};

State& state() {
    static State s;
    return s;
}

void* real_symbol(const char* name) {
    void* p = dlsym(RTLD_NEXT, name);
    if (!p) {
        std::fprintf(stderr, "vk_fault: %s not found in libvulkan\n", name);
        std::abort();
    }
    return p;
}

// True when this failable call is the one to fail.
bool inject(const char* call) {
    State& s = state();
    std::lock_guard<std::mutex> lock(s.mutex);
    const bool fail = s.calls++ == s.fail_at;
    if (fail) s.injected = call;
    return fail;
}

template <typename H>
uint64_t key(H h) {
    return reinterpret_cast<uint64_t>(h);
}

template <typename H>
void created(const char* type, const H* handles, uint32_t n) {
    State& s = state();
    std::lock_guard<std::mutex> lock(s.mutex);
    for (uint32_t i = 0; i < n; ++i)
        if (handles[i] != VK_NULL_HANDLE) s.live[type].insert(key(handles[i]));
}

template <typename H>
void destroyed(const char* type, H h) {
    if (h == VK_NULL_HANDLE) return;
    State& s = state();
    std::lock_guard<std::mutex> lock(s.mutex);
    if (s.live[type].erase(key(h)) == 0)
        std::fprintf(stderr, "vk_fault: %s %#llx destroyed but never created here\n", type,
                     static_cast<unsigned long long>(key(h)));
}

}  // namespace

void arm(long index) {
    State& s = state();
    std::lock_guard<std::mutex> lock(s.mutex);
    s.fail_at = index;
    s.calls = 0;
    s.injected.clear();
}

long calls() {
    State& s = state();
    std::lock_guard<std::mutex> lock(s.mutex);
    return s.calls;
}

std::string injected_call() {
    State& s = state();
    std::lock_guard<std::mutex> lock(s.mutex);
    return s.injected;
}

std::map<std::string, long> live() {
    State& s = state();
    std::lock_guard<std::mutex> lock(s.mutex);
    std::map<std::string, long> out;
    for (const auto& [type, handles] : s.live)
        if (!handles.empty()) out[type] = static_cast<long>(handles.size());
    return out;
}

std::string leaked(const std::map<std::string, long>& before,
                   const std::map<std::string, long>& after) {
    std::string out;
    for (const auto& [type, n] : after) {
        const auto it = before.find(type);
        const long extra = n - (it == before.end() ? 0 : it->second);
        if (extra != 0) out += (out.empty() ? "" : ", ") + type + " " + std::to_string(extra);
    }
    return out;
}

}  // namespace fovea::vk::test::fault

namespace fault = fovea::vk::test::fault;

#define FOVEA_REAL(fn) reinterpret_cast<PFN_##fn>(fault::real_symbol(#fn))

// A create call: vkCreateX(parent, info, allocator, out) with one handle of type `Type` out.
#define FOVEA_FAULT_CREATE(fn, Parent, Info, Type)                                            \
    extern "C" VKAPI_ATTR VkResult VKAPI_CALL fn(Parent p, const Info* i,                     \
                                                 const VkAllocationCallbacks* a, Type* out) { \
        static const auto real = FOVEA_REAL(fn);                                              \
        if (fault::inject(#fn)) return VK_ERROR_OUT_OF_DEVICE_MEMORY;                         \
        const VkResult r = real(p, i, a, out);                                                \
        if (r == VK_SUCCESS) fault::created(#Type, out, 1);                                   \
        return r;                                                                             \
    }

// A destroy call: vkDestroyX(parent, handle, allocator).
#define FOVEA_FAULT_DESTROY(fn, Parent, Type)                                                    \
    extern "C" VKAPI_ATTR void VKAPI_CALL fn(Parent p, Type h, const VkAllocationCallbacks* a) { \
        static const auto real = FOVEA_REAL(fn);                                                 \
        fault::destroyed(#Type, h);                                                              \
        real(p, h, a);                                                                           \
    }

extern "C" VKAPI_ATTR VkResult VKAPI_CALL vkCreateInstance(const VkInstanceCreateInfo* i,
                                                           const VkAllocationCallbacks* a,
                                                           VkInstance* out) {
    static const auto real = FOVEA_REAL(vkCreateInstance);
    if (fault::inject("vkCreateInstance")) return VK_ERROR_OUT_OF_DEVICE_MEMORY;
    const VkResult r = real(i, a, out);
    if (r == VK_SUCCESS) fault::created("VkInstance", out, 1);
    return r;
}

extern "C" VKAPI_ATTR void VKAPI_CALL vkDestroyInstance(VkInstance h,
                                                        const VkAllocationCallbacks* a) {
    static const auto real = FOVEA_REAL(vkDestroyInstance);
    fault::destroyed("VkInstance", h);
    real(h, a);
}

extern "C" VKAPI_ATTR void VKAPI_CALL vkDestroyDevice(VkDevice h, const VkAllocationCallbacks* a) {
    static const auto real = FOVEA_REAL(vkDestroyDevice);
    fault::destroyed("VkDevice", h);
    real(h, a);
}

FOVEA_FAULT_CREATE(vkCreateDevice, VkPhysicalDevice, VkDeviceCreateInfo, VkDevice)
FOVEA_FAULT_CREATE(vkCreateBuffer, VkDevice, VkBufferCreateInfo, VkBuffer)
FOVEA_FAULT_DESTROY(vkDestroyBuffer, VkDevice, VkBuffer)
FOVEA_FAULT_CREATE(vkAllocateMemory, VkDevice, VkMemoryAllocateInfo, VkDeviceMemory)
FOVEA_FAULT_DESTROY(vkFreeMemory, VkDevice, VkDeviceMemory)
FOVEA_FAULT_CREATE(vkCreateImage, VkDevice, VkImageCreateInfo, VkImage)
FOVEA_FAULT_DESTROY(vkDestroyImage, VkDevice, VkImage)
FOVEA_FAULT_CREATE(vkCreateImageView, VkDevice, VkImageViewCreateInfo, VkImageView)
FOVEA_FAULT_DESTROY(vkDestroyImageView, VkDevice, VkImageView)
FOVEA_FAULT_CREATE(vkCreateSampler, VkDevice, VkSamplerCreateInfo, VkSampler)
FOVEA_FAULT_DESTROY(vkDestroySampler, VkDevice, VkSampler)
FOVEA_FAULT_CREATE(vkCreateShaderModule, VkDevice, VkShaderModuleCreateInfo, VkShaderModule)
FOVEA_FAULT_DESTROY(vkDestroyShaderModule, VkDevice, VkShaderModule)
FOVEA_FAULT_CREATE(vkCreatePipelineLayout, VkDevice, VkPipelineLayoutCreateInfo, VkPipelineLayout)
FOVEA_FAULT_DESTROY(vkDestroyPipelineLayout, VkDevice, VkPipelineLayout)
FOVEA_FAULT_CREATE(vkCreateDescriptorSetLayout, VkDevice, VkDescriptorSetLayoutCreateInfo,
                   VkDescriptorSetLayout)
FOVEA_FAULT_DESTROY(vkDestroyDescriptorSetLayout, VkDevice, VkDescriptorSetLayout)
FOVEA_FAULT_CREATE(vkCreateDescriptorPool, VkDevice, VkDescriptorPoolCreateInfo, VkDescriptorPool)
FOVEA_FAULT_DESTROY(vkDestroyDescriptorPool, VkDevice, VkDescriptorPool)
FOVEA_FAULT_CREATE(vkCreateQueryPool, VkDevice, VkQueryPoolCreateInfo, VkQueryPool)
FOVEA_FAULT_DESTROY(vkDestroyQueryPool, VkDevice, VkQueryPool)
FOVEA_FAULT_CREATE(vkCreateRenderPass, VkDevice, VkRenderPassCreateInfo, VkRenderPass)
FOVEA_FAULT_DESTROY(vkDestroyRenderPass, VkDevice, VkRenderPass)
FOVEA_FAULT_CREATE(vkCreateFramebuffer, VkDevice, VkFramebufferCreateInfo, VkFramebuffer)
FOVEA_FAULT_DESTROY(vkDestroyFramebuffer, VkDevice, VkFramebuffer)
FOVEA_FAULT_CREATE(vkCreateFence, VkDevice, VkFenceCreateInfo, VkFence)
FOVEA_FAULT_DESTROY(vkDestroyFence, VkDevice, VkFence)
FOVEA_FAULT_CREATE(vkCreateSemaphore, VkDevice, VkSemaphoreCreateInfo, VkSemaphore)
FOVEA_FAULT_DESTROY(vkDestroySemaphore, VkDevice, VkSemaphore)
FOVEA_FAULT_CREATE(vkCreateCommandPool, VkDevice, VkCommandPoolCreateInfo, VkCommandPool)
FOVEA_FAULT_DESTROY(vkDestroyCommandPool, VkDevice, VkCommandPool)
FOVEA_FAULT_DESTROY(vkDestroyPipeline, VkDevice, VkPipeline)

extern "C" VKAPI_ATTR VkResult VKAPI_CALL vkCreateComputePipelines(
    VkDevice d, VkPipelineCache c, uint32_t n, const VkComputePipelineCreateInfo* i,
    const VkAllocationCallbacks* a, VkPipeline* out) {
    static const auto real = FOVEA_REAL(vkCreateComputePipelines);
    if (fault::inject("vkCreateComputePipelines")) {
        for (uint32_t k = 0; k < n; ++k) out[k] = VK_NULL_HANDLE;
        return VK_ERROR_OUT_OF_DEVICE_MEMORY;
    }
    const VkResult r = real(d, c, n, i, a, out);
    fault::created("VkPipeline", out, n);  // the ones that failed are VK_NULL_HANDLE
    return r;
}

extern "C" VKAPI_ATTR VkResult VKAPI_CALL vkCreateGraphicsPipelines(
    VkDevice d, VkPipelineCache c, uint32_t n, const VkGraphicsPipelineCreateInfo* i,
    const VkAllocationCallbacks* a, VkPipeline* out) {
    static const auto real = FOVEA_REAL(vkCreateGraphicsPipelines);
    if (fault::inject("vkCreateGraphicsPipelines")) {
        for (uint32_t k = 0; k < n; ++k) out[k] = VK_NULL_HANDLE;
        return VK_ERROR_OUT_OF_DEVICE_MEMORY;
    }
    const VkResult r = real(d, c, n, i, a, out);
    fault::created("VkPipeline", out, n);
    return r;
}

// Failable calls that create nothing this count tracks (pool-owned handles, state changes).
extern "C" VKAPI_ATTR VkResult VKAPI_CALL
vkAllocateDescriptorSets(VkDevice d, const VkDescriptorSetAllocateInfo* i, VkDescriptorSet* out) {
    static const auto real = FOVEA_REAL(vkAllocateDescriptorSets);
    if (fault::inject("vkAllocateDescriptorSets")) return VK_ERROR_OUT_OF_DEVICE_MEMORY;
    return real(d, i, out);
}

extern "C" VKAPI_ATTR VkResult VKAPI_CALL
vkAllocateCommandBuffers(VkDevice d, const VkCommandBufferAllocateInfo* i, VkCommandBuffer* out) {
    static const auto real = FOVEA_REAL(vkAllocateCommandBuffers);
    if (fault::inject("vkAllocateCommandBuffers")) return VK_ERROR_OUT_OF_DEVICE_MEMORY;
    return real(d, i, out);
}

extern "C" VKAPI_ATTR VkResult VKAPI_CALL vkBindBufferMemory(VkDevice d, VkBuffer b,
                                                             VkDeviceMemory m, VkDeviceSize o) {
    static const auto real = FOVEA_REAL(vkBindBufferMemory);
    if (fault::inject("vkBindBufferMemory")) return VK_ERROR_OUT_OF_DEVICE_MEMORY;
    return real(d, b, m, o);
}

extern "C" VKAPI_ATTR VkResult VKAPI_CALL vkBindImageMemory(VkDevice d, VkImage img,
                                                            VkDeviceMemory m, VkDeviceSize o) {
    static const auto real = FOVEA_REAL(vkBindImageMemory);
    if (fault::inject("vkBindImageMemory")) return VK_ERROR_OUT_OF_DEVICE_MEMORY;
    return real(d, img, m, o);
}

extern "C" VKAPI_ATTR VkResult VKAPI_CALL vkMapMemory(VkDevice d, VkDeviceMemory m, VkDeviceSize o,
                                                      VkDeviceSize s, VkMemoryMapFlags f,
                                                      void** out) {
    static const auto real = FOVEA_REAL(vkMapMemory);
    if (fault::inject("vkMapMemory")) return VK_ERROR_OUT_OF_DEVICE_MEMORY;
    return real(d, m, o, s, f, out);
}

extern "C" VKAPI_ATTR VkResult VKAPI_CALL vkBeginCommandBuffer(VkCommandBuffer c,
                                                               const VkCommandBufferBeginInfo* i) {
    static const auto real = FOVEA_REAL(vkBeginCommandBuffer);
    if (fault::inject("vkBeginCommandBuffer")) return VK_ERROR_OUT_OF_DEVICE_MEMORY;
    return real(c, i);
}

extern "C" VKAPI_ATTR VkResult VKAPI_CALL vkEndCommandBuffer(VkCommandBuffer c) {
    static const auto real = FOVEA_REAL(vkEndCommandBuffer);
    if (fault::inject("vkEndCommandBuffer")) return VK_ERROR_OUT_OF_DEVICE_MEMORY;
    return real(c);
}

extern "C" VKAPI_ATTR VkResult VKAPI_CALL vkQueueSubmit(VkQueue q, uint32_t n,
                                                        const VkSubmitInfo* s, VkFence f) {
    static const auto real = FOVEA_REAL(vkQueueSubmit);
    if (fault::inject("vkQueueSubmit")) return VK_ERROR_OUT_OF_DEVICE_MEMORY;
    return real(q, n, s, f);
}

extern "C" VKAPI_ATTR VkResult VKAPI_CALL vkResetFences(VkDevice d, uint32_t n, const VkFence* f) {
    static const auto real = FOVEA_REAL(vkResetFences);
    if (fault::inject("vkResetFences")) return VK_ERROR_OUT_OF_DEVICE_MEMORY;
    return real(d, n, f);
}
