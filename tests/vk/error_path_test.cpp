// No error path leaks a Vulkan object: every failable call (create, allocate, bind, map, begin,
// end, submit) that the module's constructors, the demo host's and the device's own calls make is
// failed in turn with VK_ERROR_OUT_OF_DEVICE_MEMORY (vk_fault.cpp), and once the failure has
// unwound, nothing is left alive: neither in vk_fault's count of live handles nor in the
// validation layer's object tracker, which reports every undestroyed child when the device goes.
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "../support/vk_test_device.hpp"
#include "fovea/demo/demo.hpp"
#include "fovea/demo/raster.hpp"
#include "fovea/metrics/gpu_flip.hpp"
#include "fovea/vk/foveator.hpp"
#include "fovea/vk/vrs.hpp"
#include "gpu.hpp"
#include "shaders.hpp"
#include "vk_fault.hpp"

namespace fovea::vk {
namespace {

namespace fault = test::fault;

// Validation messages of severity error, counted over a device's whole life (its destruction
// included, when the object tracker reports leaks).
struct ValidationCount {
    long errors = 0;
    long undestroyed = 0;  // the object tracker's "has not been destroyed" reports among them
    std::string first;
    LogFn log() {
        return [this](LogLevel level, const std::string& msg) {
            if (level != LogLevel::kError) return;
            if (errors++ == 0) first = msg;
            if (msg.find("has not been destroyed") != std::string::npos) ++undestroyed;
        };
    }
};

std::unique_ptr<Device> make_device(ValidationCount& count) {
    DeviceOptions o;
    o.validation = test::kValidation;
    o.prefer_software = true;
    o.log = count.log();
    auto d = Device::create_headless(o);
    return d ? std::make_unique<Device>(std::move(*d)) : nullptr;
}

// Makes something on the device; returns false when an entry point reported an error result
// (VkError thrown by the gpu.hpp classes counts as reported too).
using Body = std::function<bool(const Device&)>;

class ErrorPathTest : public ::testing::Test {
protected:
    void SetUp() override {
        fault::arm(-1);
        const test::TestDevice probe = test::make_test_device();
        FOVEA_ASSERT_TEST_DEVICE(probe);
    }

    // Runs `body` once without faults, then once per failable call it made with that call
    // failing, all on one validated device, and checks each run leaves no live object behind.
    void expect_no_leak_on_any_failure(const char* what, const Body& body) {
        ValidationCount validation;
        fault::arm(-1);
        const auto before_device = fault::live();
        {
            auto device = make_device(validation);
            ASSERT_TRUE(device);
            const auto baseline = fault::live();
            fault::arm(-1);
            ASSERT_TRUE(run(body, *device)) << what << " fails without an injected fault";
            const long steps = fault::calls();
            EXPECT_EQ(fault::leaked(baseline, fault::live()), "") << what << " (no fault)";
            ASSERT_GT(steps, 0) << what << " made no failable call";
            for (long step = 0; step < steps; ++step) {
                const auto before = fault::live();
                fault::arm(step);
                const bool ok = run(body, *device);
                const std::string call = fault::injected_call();
                fault::arm(-1);
                EXPECT_FALSE(ok) << what << ": failed " << call << " (step " << step
                                 << ") went unreported";
                EXPECT_EQ(fault::leaked(before, fault::live()), "")
                    << what << ": leaked after failing " << call << " (step " << step << " of "
                    << steps << ")";
            }
            std::printf("%s: %ld failable calls, each failed once\n", what, steps);
        }
        EXPECT_EQ(fault::leaked(before_device, fault::live()), "") << what << ": device teardown";
        EXPECT_EQ(validation.undestroyed, 0) << what << ": objects the validation layer's object "
                                             << "tracker found alive when the device was destroyed";
        EXPECT_EQ(validation.errors, 0)
            << what << ": validation errors; first: " << validation.first;
        // Without the layer only vk_fault's count checked the leaks.
        if (!test::kValidation) GTEST_SKIP() << test::kValidationOff;
    }

    static bool run(const Body& body, const Device& device) {
        try {
            return body(device);
        } catch (const VkError& e) {
            EXPECT_EQ(e.result(), VK_ERROR_OUT_OF_DEVICE_MEMORY) << e.what();
            return false;
        }
    }
};

constexpr const char* kShading = R"(
vec3 fovea_shade(FoveaGSample g, FoveaFootprint fp) { return g.albedo + vec3(0.01) * fp.size_px; }
)";

FoveatorConfig small_config(const char* method, std::vector<std::string> post = {}) {
    FoveatorConfig c;
    c.extent = {64, 48};
    c.display = EyeDisplay::from_fov(64, 48, 40.0, 30.0);
    c.method = method;
    c.post_chain = std::move(post);
    c.shading_glsl = kShading;
    return c;
}

TEST_F(ErrorPathTest, BufferLeaksNothing) {
    expect_no_leak_on_any_failure("Buffer", [](const Device& d) {
        Buffer device_local(d, 4096, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false);
        Buffer host_visible(d, 4096, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, true);
        return device_local.get() && host_visible.data();
    });
}

TEST_F(ErrorPathTest, ImageLeaksNothing) {
    expect_no_leak_on_any_failure("Image", [](const Device& d) {
        Image one(d, {32, 32}, VK_FORMAT_R16G16B16A16_SFLOAT, VK_IMAGE_USAGE_STORAGE_BIT);
        Image mips(d, {32, 32}, VK_FORMAT_R16G16B16A16_SFLOAT, VK_IMAGE_USAGE_STORAGE_BIT, 4);
        return one.view() && mips.mip_view(3);
    });
}

TEST_F(ErrorPathTest, UploadAndReadBackLeakNothing) {
    expect_no_leak_on_any_failure("upload_image + read_image", [](const Device& d) {
        Image img(d, {16, 16}, VK_FORMAT_R8G8B8A8_UNORM, VK_IMAGE_USAGE_STORAGE_BIT);
        std::vector<uint8_t> texels(16 * 16 * 4, 7);
        upload_image(d, img.ref(), texels);
        return d.read_image(img.ref()) == texels;
    });
}

TEST_F(ErrorPathTest, SamplerAndComputePipelineLeakNothing) {
    expect_no_leak_on_any_failure("LinearClampSampler + ComputePipeline", [](const Device& d) {
        LinearClampSampler sampler(d, 4);
        const Binding bindings[] = {{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
                                    {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}};
        ComputePipeline p(d, shader_spirv("post_copy.comp"), VK_NULL_HANDLE, bindings, 0);
        return sampler.get() && p.allocate_set();
    });
}

TEST_F(ErrorPathTest, DeviceCreationLeaksNothing) {
    expect_no_leak_on_any_failure("Device::create_headless", [](const Device&) {
        ValidationCount inner;
        DeviceOptions o;
        o.validation = test::kValidation;
        o.prefer_software = true;
        o.log = inner.log();
        const bool ok = static_cast<bool>(Device::create_headless(o));
        EXPECT_EQ(inner.errors, 0) << inner.first;
        return ok;
    });
}

// Method "full" and one post pass: the Foveator's own objects and its chain. The other methods
// and passes hold only gpu.hpp objects, and compiling cps's pipelines 435 times takes minutes.
TEST_F(ErrorPathTest, FoveatorLeaksNothing) {
    expect_no_leak_on_any_failure("Foveator full + taa", [](const Device& d) {
        auto f = Foveator::create(d, small_config("full", {"taa"}));
        if (!f) return false;
        f->render_blocking(0, {}, {});
        return true;
    });
}

TEST_F(ErrorPathTest, GpuFlipLeaksNothing) {
    expect_no_leak_on_any_failure("metrics::GpuFlip + a compare", [](const Device& d) {
        auto f = metrics::GpuFlip::create(d, 32, 16, {metrics::PpdField::uniform(32, 16, 20.0)});
        if (!f) return false;
        Image img(d, {32, 16}, VK_FORMAT_R8G8B8A8_UNORM, VK_IMAGE_USAGE_SAMPLED_BIT);
        d.submit_and_wait([&](VkCommandBuffer cmd) {
            f->record_reference(cmd, img.ref(), metrics::FlipInput::kSrgb);
            f->record_compare(cmd, img.ref(), metrics::FlipInput::kSrgb);
        });
        return f->map()[0] == 0.f;
    });
}

TEST_F(ErrorPathTest, VrsAttachmentLeaksNothing) {
    expect_no_leak_on_any_failure("VrsAttachment", [](const Device& d) {
        return static_cast<bool>(VrsAttachment::create(d, EyeDisplay::from_fov(64, 48, 40.0, 30.0),
                                                       16, 16, /*allow_unsupported=*/true));
    });
}

TEST_F(ErrorPathTest, DemoSceneLeaksNothing) {
    expect_no_leak_on_any_failure("demo DepthImage + SceneRenderer frame", [](const Device& d) {
        auto f = Foveator::create(d, small_config("full"));
        if (!f) return false;
        demo::DepthImage depth(d, {64, 48});
        demo::SceneRenderer scene(d);
        const demo::Camera cam = demo::target_camera(f->config().display);
        f->render_blocking(0, {}, [&](VkCommandBuffer cmd) {
            scene.begin_frame();
            scene.record(cmd, f->gbuffer(), demo::SceneKind::kZonePlate, cam, cam, 0.0);
        });
        return depth.view() != VK_NULL_HANDLE;
    });
}

}  // namespace
}  // namespace fovea::vk
