// Compiled into fovea_vk only in AddressSanitizer trees (sdk/vk.cmake): `dlclose` does nothing, so
// the Vulkan driver, layers and LLVM that the loader opens stay mapped until the process exits.
//
// Why: the loader unloads lavapipe and the validation layer at vkDestroyInstance. Memory those
// libraries keep for the life of the process (LLVM's JIT registrations, Mesa's caches) is then
// referenced only from globals that are no longer mapped, so LeakSanitizer reports it as leaked
// with "<unknown module>" frames that no suppression can name. Kept mapped, those blocks stay
// reachable and are not reported; a block our code leaks is still unreachable and still reported.
// The sanitizer runtime's own dlclose interceptor forwards here (the next definition after it in
// the lookup order: libfovea_vk comes before libc).
extern "C" __attribute__((visibility("default"))) int dlclose(void* /*handle*/) { return 0; }
