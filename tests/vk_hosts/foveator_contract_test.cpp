// The Foveator's contract with a host beyond the shading itself: gaze through blinks, views()
// the host forgot. Small frames on lavapipe, validation as FOVEA_VK_VALIDATION says.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

#include "../vk/vk_test_util.hpp"
#include "fovea/vk/foveator.hpp"
#include "gpu.hpp"

namespace fovea::vk {
namespace {

constexpr const char* kFlatShading = R"(
vec3 fovea_shade(FoveaGSample g, FoveaFootprint fp) {
    return g.background ? vec3(0.2) : g.albedo + vec3(0.0 * fp.size_px);
}
)";

FoveatorConfig small_config(const char* method) {
    FoveatorConfig c;
    c.extent = {160, 96};
    c.display = EyeDisplay::from_fov(160, 96, 40.0, 24.0);
    c.method = method;
    c.shading_glsl = kFlatShading;
    return c;
}

// A device of its own whose log the test reads; validation as the build says, and the same
// skip / fail rules as test::make_test_device.
struct LoggedDevice {
    std::mutex mutex;
    std::vector<std::string> warnings;
    test::TestDevice test_device;

    LoggedDevice() {
        DeviceOptions o;
        o.validation = test::kValidation;
        o.log = [this](LogLevel level, const std::string& m) {
            if (level < LogLevel::kWarning) return;
            std::lock_guard<std::mutex> lock(mutex);
            warnings.push_back(m);
        };
        test_device = test::make_test_device(o);
    }
    size_t count(const std::string& needle) {
        std::lock_guard<std::mutex> lock(mutex);
        size_t n = 0;
        for (const auto& w : warnings) n += w.find(needle) != std::string::npos;
        return n;
    }
};

TEST(FoveatorGaze, BlinkHoldsTheLastValidGaze) {
    FOVEA_REQUIRE_DEVICE();
    auto f = Foveator::create(*device, small_config("cps"));
    ASSERT_TRUE(f) << f.error().message;
    FrameInputs in;
    in.gaze.x = 0.15f;
    in.gaze.y = 0.8f;
    in.time_s = 0.0;
    f->render_blocking(0, in, {});
    const ResolvedGaze seen = f->stats().gaze;
    in.gaze.x = in.gaze.y = std::numeric_limits<float>::quiet_NaN();
    in.time_s = 0.1;
    f->render_blocking(1, in, {});
    const ResolvedGaze blink = f->stats().gaze;
    EXPECT_TRUE(blink.held);
    EXPECT_FALSE(blink.fell_back);
    EXPECT_FLOAT_EQ(blink.x_px, seen.x_px);
    EXPECT_FLOAT_EQ(blink.y_px, seen.y_px);
    EXPECT_GT(blink.margin_deg, seen.margin_deg);  // aged by the 100 ms of the blink
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

// Two frames recorded before either runs keep their own uniforms and counters: each frame's
// stats equal what it shows when rendered alone.
TEST(FoveatorFramesInFlight, TwoFramesRecordedAheadKeepTheirOwnCounters) {
    FOVEA_REQUIRE_DEVICE();
    FoveatorConfig c = small_config("cps");
    c.frames_in_flight = 2;
    auto f = Foveator::create(*device, c);
    ASSERT_TRUE(f) << f.error().message;
    std::array<FrameInputs, 2> in;
    in[0].gaze.x = 0.1f;
    in[1].gaze.x = 0.9f;
    in[1].gaze.y = 0.1f;
    std::array<uint64_t, 2> alone{};
    for (int i = 0; i < 2; ++i) {
        f->render_blocking(uint64_t(i), in[i], {});
        alone[i] = f->stats().shaded_samples;
    }
    ASSERT_NE(alone[0], alone[1]);  // the gazes shade differently, or the test proves nothing

    VkDevice d = device->device();
    VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pci.queueFamilyIndex = device->queue_family();
    VkCommandPool pool = VK_NULL_HANDLE;
    ASSERT_EQ(vkCreateCommandPool(d, &pci, nullptr, &pool), VK_SUCCESS);
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = pool;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 2;
    std::array<VkCommandBuffer, 2> cmd{};
    ASSERT_EQ(vkAllocateCommandBuffers(d, &ai, cmd.data()), VK_SUCCESS);
    for (int i = 0; i < 2; ++i) {  // frames 2 and 3, both recorded before any submission
        VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        vkBeginCommandBuffer(cmd[i], &bi);
        f->record(cmd[i], uint64_t(2 + i), in[i]);
        vkEndCommandBuffer(cmd[i]);
    }
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 2;
    si.pCommandBuffers = cmd.data();
    ASSERT_EQ(vkQueueSubmit(device->queue(), 1, &si, VK_NULL_HANDLE), VK_SUCCESS);
    device->wait_idle();
    for (int i = 0; i < 2; ++i) {
        const FrameStats s = f->stats(uint64_t(2 + i));
        EXPECT_EQ(s.frame_index, uint64_t(2 + i));
        EXPECT_EQ(s.shaded_samples, alone[i]) << "frame " << 2 + i;
        EXPECT_FLOAT_EQ(s.gaze.x_px, in[i].gaze.x * 160.f);
    }
    EXPECT_EQ(f->stats().frame_index, 3u);  // the last recorded
    vkDestroyCommandPool(d, pool, nullptr);
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

TEST(FoveatorFramesInFlight, OutOfRangeCountIsAnError) {
    FOVEA_REQUIRE_DEVICE();
    FoveatorConfig c = small_config("full");
    c.frames_in_flight = 0;
    EXPECT_FALSE(Foveator::create(*device, c));
    c.frames_in_flight = kMaxFramesInFlight + 1;
    auto f = Foveator::create(*device, c);
    ASSERT_FALSE(f);
    EXPECT_NE(f.error().message.find("frames_in_flight"), std::string::npos);
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

// The host's own resources reach its shading function through its descriptor set, in every
// method (each compiles the function into its own pipelines).
TEST(FoveatorHostSet, ShadingReadsTheHostsDescriptorSetInEveryMethod) {
    FOVEA_REQUIRE_DEVICE();
    VkDevice d = device->device();
    const VkDescriptorSetLayoutBinding b{0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1,
                                         VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
    VkDescriptorSetLayoutCreateInfo li{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    li.bindingCount = 1;
    li.pBindings = &b;
    VkDescriptorSetLayout layout = VK_NULL_HANDLE;
    ASSERT_EQ(vkCreateDescriptorSetLayout(d, &li, nullptr, &layout), VK_SUCCESS);
    const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1};
    VkDescriptorPoolCreateInfo pi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pi.maxSets = 1;
    pi.poolSizeCount = 1;
    pi.pPoolSizes = &size;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    ASSERT_EQ(vkCreateDescriptorPool(d, &pi, nullptr, &pool), VK_SUCCESS);
    VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    ai.descriptorPool = pool;
    ai.descriptorSetCount = 1;
    ai.pSetLayouts = &layout;
    VkDescriptorSet set = VK_NULL_HANDLE;
    ASSERT_EQ(vkAllocateDescriptorSets(d, &ai, &set), VK_SUCCESS);
    {
        Buffer tint(*device, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true);
        const float rgba[4] = {0.25f, 0.5f, 0.75f, 0.f};
        std::memcpy(tint.data(), rgba, sizeof(rgba));
        const VkDescriptorBufferInfo info = tint.info();
        VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w.dstSet = set;
        w.descriptorCount = 1;
        w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        w.pBufferInfo = &info;
        vkUpdateDescriptorSets(d, 1, &w, 0, nullptr);
        FoveatorConfig c = small_config("full");
        c.host_set_layout = layout;
        c.shading_glsl = R"(
layout(std430, set = FOVEA_HOST_SET, binding = 0) readonly buffer HostTint { vec4 tint; } host;
vec3 fovea_shade(FoveaGSample g, FoveaFootprint fp) { return host.tint.rgb + 0.0 * fp.size_px; }
)";
        auto f = Foveator::create(*device, c);
        ASSERT_TRUE(f) << f.error().message;
        FrameInputs in;
        in.host_set = set;
        for (const std::string& m : Foveator::methods()) {
            ASSERT_TRUE(f->set_method(m)) << m;
            if (m == "layers") f->views(0, in);
            f->render_blocking(0, in, {});
            const auto out = device->read_image(f->output());
            size_t wrong = 0;
            for (size_t i = 0; i < out.size(); i += 8) {
                uint16_t h[3];
                std::memcpy(h, &out[i], 6);
                wrong += std::abs(fovea::half_from_bits(h[0]) - 0.25f) > 1e-3f ||
                         std::abs(fovea::half_from_bits(h[2]) - 0.75f) > 1e-3f;
            }
            EXPECT_EQ(wrong, 0u) << m;
        }
        c.host_set_layout = VK_NULL_HANDLE;
        auto missing = Foveator::create(*device, c);
        ASSERT_FALSE(missing);
        EXPECT_NE(missing.error().message.find("host_set_layout"), std::string::npos);
    }
    vkDestroyDescriptorPool(d, pool, nullptr);
    vkDestroyDescriptorSetLayout(d, layout, nullptr);
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

// A host that never calls views() gets one warning per method, naming the call it skipped.
TEST(FoveatorViews, RecordWithoutViewsWarnsOnce) {
    LoggedDevice logged;
    FOVEA_ASSERT_TEST_DEVICE(logged.test_device);
    auto f = Foveator::create(*logged.test_device.device, small_config("layers"));
    ASSERT_TRUE(f) << f.error().message;
    FrameInputs in;
    f->render_blocking(0, in, {});
    f->render_blocking(1, in, {});
    EXPECT_EQ(logged.count("without views(0)"), 1u);
    EXPECT_EQ(logged.count("without views("), 1u);  // once, not per frame
    ASSERT_TRUE(f->set_method("full"));
    f->render_blocking(2, in, {});  // "full" renders no views: nothing to warn about
    EXPECT_EQ(logged.count("without views("), 1u);
    FOVEA_EXPECT_NO_VALIDATION_ERRORS_SINCE(*logged.test_device.device, 0u);
}

TEST(FoveatorViews, HostThatAsksForViewsIsNotWarned) {
    LoggedDevice logged;
    FOVEA_ASSERT_TEST_DEVICE(logged.test_device);
    auto f = Foveator::create(*logged.test_device.device, small_config("layers"));
    ASSERT_TRUE(f) << f.error().message;
    FrameInputs in;
    for (uint64_t i = 0; i < 2; ++i) {
        EXPECT_FALSE(f->views(i, in).empty());
        f->render_blocking(i, in, {});
    }
    EXPECT_EQ(logged.count("without views("), 0u);
    FOVEA_EXPECT_NO_VALIDATION_ERRORS_SINCE(*logged.test_device.device, 0u);
}

}  // namespace
}  // namespace fovea::vk
