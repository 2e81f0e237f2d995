// Device::requirements() and wrap(): a host's own device is checked before the module uses it,
// and the module's queue use goes through the host's lock.
#include <gtest/gtest.h>

#include <atomic>
#include <mutex>

#include "external_device.hpp"
#include "fovea/vk/foveator.hpp"

namespace fovea::vk {
namespace {

using test::HostVulkan;

TEST(DeviceRequirements, NameVersionQueueFeaturesAndFormats) {
    const DeviceRequirements r = Device::requirements();
    EXPECT_GE(r.api_version, VK_API_VERSION_1_1);
    EXPECT_TRUE(r.queue_flags & VK_QUEUE_COMPUTE_BIT);
    EXPECT_TRUE(r.features.shaderStorageImageExtendedFormats);
    EXPECT_FALSE(r.features.geometryShader);
    bool rgba16f = false;
    for (const auto& f : r.formats)
        rgba16f |= f.format == VK_FORMAT_R16G16B16A16_SFLOAT &&
                   (f.features & VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT);
    EXPECT_TRUE(rgba16f);
}

TEST(DeviceWrap, AcceptsADeviceThatMeetsTheRequirements) {
    HostVulkan host(VK_API_VERSION_1_1, HostVulkan::required_features());
    FOVEA_ASSERT_HOST_VULKAN(host);
    auto d = Device::wrap(host.external());
    ASSERT_TRUE(d) << d.error().message;
    EXPECT_EQ(d->device(), host.device());
    FOVEA_EXPECT_NO_HOST_VALIDATION_ERRORS(host);
}

TEST(DeviceWrap, NamesEveryUnmetRequirement) {
    HostVulkan host(VK_API_VERSION_1_0, VkPhysicalDeviceFeatures{});
    FOVEA_ASSERT_HOST_VULKAN(host);
    ExternalDevice e = host.external();
    auto d = Device::wrap(e);
    ASSERT_FALSE(d);
    EXPECT_NE(d.error().message.find("api_version is 1.0, need 1.1"), std::string::npos)
        << d.error().message;
    EXPECT_NE(d.error().message.find("shaderStorageImageExtendedFormats"), std::string::npos);
    e.api_version = VK_API_VERSION_1_1;
    e.enabled_features = HostVulkan::required_features();
    e.queue_family = 99;
    auto bad_family = Device::wrap(e);
    ASSERT_FALSE(bad_family);
    EXPECT_NE(bad_family.error().message.find("queue_family 99 does not exist"), std::string::npos);
}

// Every submission the module makes on the host's queue happens inside the host's lock, and the
// lock is released again (never held while the module waits for the GPU).
TEST(DeviceWrap, ModuleSubmitsUnderTheHostsQueueLock) {
    HostVulkan host(VK_API_VERSION_1_1, HostVulkan::required_features());
    FOVEA_ASSERT_HOST_VULKAN(host);
    std::mutex queue_mutex;
    std::atomic<int> locks{0}, unlocks{0};
    ExternalDevice e = host.external();
    e.queue_lock.lock = [&] {
        queue_mutex.lock();
        ++locks;
    };
    e.queue_lock.unlock = [&] {
        ++unlocks;
        queue_mutex.unlock();
    };
    auto d = Device::wrap(e);
    ASSERT_TRUE(d) << d.error().message;
    FoveatorConfig c;
    c.extent = {64, 48};
    c.display = EyeDisplay::from_fov(64, 48, 30.0, 22.0);
    c.method = "full";
    c.shading_glsl = "vec3 fovea_shade(FoveaGSample g, FoveaFootprint fp) { return vec3(1.0); }";
    {
        auto f = Foveator::create(*d, c);
        ASSERT_TRUE(f) << f.error().message;
        const int before = locks;
        f->render_blocking(0, FrameInputs{}, [&](VkCommandBuffer) {
            EXPECT_TRUE(queue_mutex.try_lock()) << "lock held while recording";
            queue_mutex.unlock();
        });
        EXPECT_EQ(locks, before + 1);
        EXPECT_TRUE(queue_mutex.try_lock()) << "lock still held after the frame";
        queue_mutex.unlock();
    }
    EXPECT_GT(locks, 1);  // image set-up, the frame, the destructor's wait
    EXPECT_EQ(locks, unlocks);
    FOVEA_EXPECT_NO_HOST_VALIDATION_ERRORS(host);
}

}  // namespace
}  // namespace fovea::vk
