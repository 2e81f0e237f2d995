// Every pixel finite, nothing missing: over every method on the demo scene and on the glTF
// sample scene (deferred), and over the host-shaded paths on the glTF scene, no output pixel is
// NaN/Inf and none is black (all channels exactly 0) where the G-buffer (or the depth) says
// geometry was hit: every surface of both scenes is lit by at least the environment, so black there
// is a lost sample.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "../vk/vk_test_util.hpp"
#include "fovea/demo/demo.hpp"
#include "fovea/vk/foveator.hpp"
#include "gltf_viewer/frame_host.hpp"

namespace fovea::vk {
namespace {

struct Health {
    size_t non_finite = 0;         // channels
    size_t black_on_geometry = 0;  // pixels
    size_t geometry = 0;           // pixels with geometry
    std::string first_black;       // "x,y" of the first black pixel on geometry
};

// rgba16f: the output; geometry[i]: a surface covers pixel i.
Health health(const std::vector<uint8_t>& rgba16f, const std::vector<bool>& geometry,
              uint32_t width) {
    Health h;
    for (size_t i = 0; i < geometry.size(); ++i) {
        uint16_t c[3];
        std::memcpy(c, &rgba16f[i * 8], 6);
        bool black = true;
        for (uint16_t v : c) {
            const float f = fovea::half_from_bits(v);
            h.non_finite += !std::isfinite(f);
            black &= f == 0.f;
        }
        h.geometry += geometry[i];
        if (geometry[i] && black) {
            if (h.black_on_geometry++ == 0)
                h.first_black = std::to_string(i % width) + "," + std::to_string(i / width);
        }
    }
    return h;
}

// position.w > 0 of a G-buffer read back (RGBA32F).
std::vector<bool> covered_by_gbuffer(const std::vector<uint8_t>& position) {
    std::vector<bool> g(position.size() / 16);
    for (size_t i = 0; i < g.size(); ++i) {
        float w;
        std::memcpy(&w, &position[i * 16 + 12], 4);
        g[i] = w > 0.f;
    }
    return g;
}

// The demo scene's camera path looks over the terrain to the horizon, where distant, thin
// samples are; the frames are small (lavapipe time) but span every eccentricity band.
TEST(FrameHealth, DemoSceneEveryMethodFiniteAndNothingMissing) {
    FOVEA_REQUIRE_DEVICE();
    const EyeDisplay d = EyeDisplay::from_fov(480, 270, 47.8, 28.0);
    FoveatorConfig c;
    c.extent = {d.width_px, d.height_px};
    c.display = d;
    c.method = "full";
    c.shading_glsl = demo::shading_glsl();
    auto f = Foveator::create(*device, c);
    ASSERT_TRUE(f) << f.error().message;
    demo::SceneRenderer scene(*device);
    for (double t : {0.0, 3.5}) {
        const demo::Camera cam = demo::camera_at(t, d), prev = demo::camera_at(t - 1 / 60.0, d);
        FrameInputs in;
        in.camera_pos = cam.pos;
        in.radians_per_pixel = 2.f * cam.tan_y / float(d.height_px);
        in.time_s = t;
        in.gaze.x = 0.3f;
        in.gaze.y = 0.4f;
        std::vector<bool> geometry;
        for (const std::string& m : Foveator::methods()) {
            ASSERT_TRUE(f->set_method(m)) << m;
            const uint64_t index = t == 0.0 ? 0 : 1;
            const auto views = f->views(index, in);
            const bool full = f->needs_full_gbuffer();
            const auto jitter = f->jitter(index);
            f->render_blocking(index, in, [&](VkCommandBuffer cmd) {
                scene.begin_frame();
                if (full)
                    scene.record(cmd, f->gbuffer(), demo::SceneKind::kDemo, cam, prev, t,
                                 {0, 0, 1, 1}, jitter);
                for (const auto& v : views)
                    scene.record(cmd, v.gbuffer, demo::SceneKind::kDemo, cam, prev, t, v.crop,
                                 v.jitter_px);
            });
            if (m == "full")  // the first method: its full-resolution G-buffer is the truth
                geometry =
                    covered_by_gbuffer(device->read_image(f->gbuffer()[GBufferImage::kPosition]));
            const Health h = health(device->read_image(f->output()), geometry, d.width_px);
            EXPECT_GT(h.geometry, geometry.size() / 4);  // the terrain fills most of the frame
            EXPECT_EQ(h.non_finite, 0u) << m << " t=" << t;
            EXPECT_EQ(h.black_on_geometry, 0u) << m << " t=" << t << ": first at " << h.first_black;
        }
    }
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

// The glTF sample scene of real models, loaded once for the suite through the viewer's host code.
class FrameHealthGltf : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        const std::string data = FOVEA_SHARED_DATA_DIR;
        if (!std::filesystem::exists(data + "/scenes/WaterBottle/glTF/WaterBottle.gltf")) {
            skip_ = "no sample models under " + data + "/scenes";
            return;
        }
        gltfv::SceneFile scene;
        const std::string file =
            std::string(FOVEA_SOURCE_DIR) + "/sdk/examples/gltf_viewer/scenes/sample_models.toml";
        if (std::string e = gltfv::load_scene_file(file, data, scene); !e.empty()) {
            error_ = e;
            return;
        }
        const test::TestDevice probe = test::make_test_device();
        skip_ = probe.skip;
        error_ = probe.fail;
        if (!probe.device) return;
        device_ = gltfv::HostDevice::create(true, test::kValidation, error_);
        if (!device_) return;
        std::vector<std::string> warnings;
        host_ = gltfv::FrameHost::create(*device_, scene, warnings, error_);
    }
    static void TearDownTestSuite() {
        host_.reset();
        device_.reset();
    }
    void SetUp() override {
        if (!skip_.empty()) GTEST_SKIP() << skip_;
        ASSERT_TRUE(host_) << error_;
    }
    void TearDown() override {
        if (!device_) return;
        if (!test::kValidation) GTEST_SKIP() << test::kValidationOff;
        EXPECT_EQ(device_->validation_errors(), 0u) << "Vulkan validation errors";
    }
    // Frame i: half a second apart along the camera path, the gaze off-centre.
    static double time(uint64_t i) { return 0.5 * double(i); }
    static FrameInputs inputs(uint64_t i, VkExtent2D extent) {
        FrameInputs in = host_->inputs(time(i), extent);
        in.gaze.x = 0.6f;
        in.gaze.y = 0.45f;
        in.camera_cut = i == 0;
        return in;
    }
    static inline const std::vector<std::vector<std::string>> kChains{
        {}, {"taa", "contrast", "noise"}};  // without and with every post pass
    static inline std::string skip_, error_;
    static inline std::unique_ptr<gltfv::HostDevice> device_;
    static inline std::unique_ptr<gltfv::FrameHost> host_;
};

// The host-shaded paths (colour from the viewer's own forward shaders): geometry is where the
// full-rate frame's depth < 1.
TEST_F(FrameHealthGltf, HostShadedPathsFiniteAndNothingMissing) {
    gltfv::FrameHost* host = host_.get();
    const VkExtent2D extent{480, 270};
    Device& dev = device_->sdk();
    auto reference = Foveator::create(dev, host->config(IntegrationPath::kPostOnly, extent));
    ASSERT_TRUE(reference) << reference.error().message;
    for (IntegrationPath path : {IntegrationPath::kForwardLayers, IntegrationPath::kPostOnly}) {
        for (const std::vector<std::string>& chain : kChains) {
            FoveatorConfig c = host->config(path, extent);
            c.post_chain = chain;
            auto f = Foveator::create(dev, c);
            ASSERT_TRUE(f) << f.error().message;
            for (uint64_t i = 0; i < 2; ++i) {
                const double t = time(i);
                const FrameInputs in = inputs(i, extent);
                for (Foveator* fov : {&*reference, &*f})
                    dev.submit_and_wait([&](VkCommandBuffer cmd) {
                        host->record(cmd, *fov, i, in, t, 1.0 / 60.0);
                        fov->record(cmd, i, in);
                    });
                const auto depth = dev.read_image(reference->host_targets().depth);
                std::vector<bool> geometry(depth.size() / 4);
                for (size_t p = 0; p < geometry.size(); ++p) {
                    float z;
                    std::memcpy(&z, &depth[p * 4], 4);
                    geometry[p] = z < 1.f;
                }
                const Health h = health(dev.read_image(f->output()), geometry, extent.width);
                EXPECT_GT(h.geometry, geometry.size() / 20);
                EXPECT_EQ(h.non_finite, 0u) << int(path) << " chain " << chain.size();
                EXPECT_EQ(h.black_on_geometry, 0u)
                    << int(path) << " chain " << chain.size() << ": first at " << h.first_black;
            }
        }
    }
}

// The deferred path: every method with the viewer's PBR as fovea_shade(), textures read again at
// the footprint's LOD; geometry is where "full"'s G-buffer was hit.
TEST_F(FrameHealthGltf, DeferredEveryMethodFiniteAndNothingMissing) {
    gltfv::FrameHost* host = host_.get();
    const VkExtent2D extent{480, 270};
    Device& dev = device_->sdk();
    for (const std::vector<std::string>& chain : kChains) {
        FoveatorConfig c = host->config(IntegrationPath::kDeferred, extent);
        c.post_chain = chain;
        c.method = "full";
        auto f = Foveator::create(dev, c);
        ASSERT_TRUE(f) << f.error().message;
        for (uint64_t i = 0; i < 2; ++i) {
            const double t = time(i);
            const FrameInputs in = inputs(i, extent);
            std::vector<bool> geometry;
            for (const std::string& m : Foveator::methods()) {
                ASSERT_TRUE(f->set_method(m)) << m;
                f->render_blocking(i, in, [&](VkCommandBuffer cmd) {
                    host->record(cmd, *f, i, in, t, 1.0 / 60.0);
                });
                if (m == "full")
                    geometry =
                        covered_by_gbuffer(dev.read_image(f->gbuffer()[GBufferImage::kPosition]));
                const Health h = health(dev.read_image(f->output()), geometry, extent.width);
                EXPECT_GT(h.geometry, geometry.size() / 20);
                EXPECT_EQ(h.non_finite, 0u) << m << " chain " << chain.size();
                EXPECT_EQ(h.black_on_geometry, 0u)
                    << m << " chain " << chain.size() << ": first at " << h.first_black;
            }
        }
    }
}

}  // namespace
}  // namespace fovea::vk
