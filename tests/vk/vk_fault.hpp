// Fault injection and a live-object count for the Vulkan entry points, for error-path tests.
// Linking vk_fault.cpp into a test binary interposes the loader's exported vkCreate*/vkAllocate*/
// vkDestroy*/vkFree* and the other calls that can fail with an out-of-memory result (bind, map,
// begin/end, submit, fence reset): each forwards to libvulkan (dlsym RTLD_NEXT), counts the handles
// it creates and destroys, and can be told to fail one call with VK_ERROR_OUT_OF_DEVICE_MEMORY
// without calling down, exactly as a driver out of memory would. Pool-owned handles (descriptor
// sets, command buffers) are failable steps but not counted as live objects: their pool frees them.
//
// Threads: any; the counters are process-wide and guarded by one mutex.
#pragma once

#include <map>
#include <string>

namespace fovea::vk::test::fault {

// From now on, the `index`-th failable call (0-based) fails; -1 injects nothing. Resets calls().
void arm(long index);
// Failable calls made since the last arm().
long calls();
// The failing call's name, once it has been injected (else empty).
std::string injected_call();
// Live handles per type name ("VkImage", ...), only types with at least one.
std::map<std::string, long> live();
// "VkImage +1, VkDeviceMemory +1" for what `after` holds beyond `before` (empty when nothing).
std::string leaked(const std::map<std::string, long>& before,
                   const std::map<std::string, long>& after);

}  // namespace fovea::vk::test::fault
