// Test harness for running one post pass on a headless device: upload CPU images, record the
// pass outside a Foveator, read results back as float images. Skips when no Vulkan device.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <ctime>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "../support/vk_test_device.hpp"
#include "fovea/vk/acuity.hpp"
#include "fovea/vk/device.hpp"
#include "gpu.hpp"
#include "image_model.hpp"
#include "post_pass.hpp"

namespace fovea::vk::testing {

inline int format_channels(VkFormat f) {
    switch (f) {
        case VK_FORMAT_R16G16B16A16_SFLOAT:
        case VK_FORMAT_R32G32B32A32_SFLOAT: return 4;
        case VK_FORMAT_R16G16_SFLOAT: return 2;
        default: return 1;
    }
}

inline bool format_is_half(VkFormat f) {
    return f == VK_FORMAT_R16G16B16A16_SFLOAT || f == VK_FORMAT_R16G16_SFLOAT ||
           f == VK_FORMAT_R16_SFLOAT;
}

// Writes `img` (missing channels: colour alpha = 1, others 0) into a GPU image.
inline void upload(const Device& dev, const vk::Image& dst, const post::Image& img) {
    const int ch = format_channels(dst.format());
    const bool half = format_is_half(dst.format());
    const size_t texels = size_t(img.width) * img.height;
    Buffer staging(dev, texels * ch * (half ? 2 : 4), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true);
    for (size_t i = 0; i < texels; ++i) {
        for (int c = 0; c < ch; ++c) {
            const float v =
                c < img.channels ? img.data[i * img.channels + c] : (c == 3 ? 1.f : 0.f);
            if (half) {
                static_cast<uint16_t*>(staging.data())[i * ch + c] = fovea::half_bits(v);
            } else {
                static_cast<float*>(staging.data())[i * ch + c] = v;
            }
        }
    }
    dev.submit_and_wait([&](VkCommandBuffer cmd) {
        VkBufferImageCopy r{};
        r.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        r.imageExtent = {uint32_t(img.width), uint32_t(img.height), 1};
        vkCmdCopyBufferToImage(cmd, staging.get(), dst.get(), VK_IMAGE_LAYOUT_GENERAL, 1, &r);
    });
}

inline post::Image download(const Device& dev, const ImageRef& src, int keep_channels) {
    const std::vector<uint8_t> bytes = dev.read_image(src);
    const int ch = format_channels(src.format);
    const bool half = format_is_half(src.format);
    post::Image img(int(src.extent.width), int(src.extent.height), keep_channels);
    const size_t texels = size_t(img.width) * img.height;
    for (size_t i = 0; i < texels; ++i) {
        for (int c = 0; c < keep_channels; ++c) {
            float v;
            if (half) {
                uint16_t h;
                std::memcpy(&h, bytes.data() + (i * ch + c) * 2, 2);
                v = fovea::half_from_bits(h);
            } else {
                std::memcpy(&v, bytes.data() + (i * ch + c) * 4, 4);
            }
            img.data[i * keep_channels + c] = v;
        }
    }
    return img;
}

// Fixture of the GPU pass tests: a device (skips cleanly without one) whose validation layers
// must report no error by the end of the test (validation as FOVEA_VK_VALIDATION says).
class GpuPassTest : public ::testing::Test {
protected:
    void SetUp() override {
        test::TestDevice t = test::make_test_device();
        FOVEA_ASSERT_TEST_DEVICE(t);
        device_ = std::move(t.device);
    }
    void TearDown() override {
        if (device_) FOVEA_EXPECT_NO_VALIDATION_ERRORS_SINCE(*device_, 0u);
    }
    std::unique_ptr<Device> device_;
};

class PassRunner {
public:
    PassRunner(const Device& dev, VkExtent2D extent, std::vector<std::string> options)
        : dev_(dev), extent_(extent) {
        config_.extent = extent;
        config_.options = std::move(options);
        const VkImageUsageFlags u = VK_IMAGE_USAGE_STORAGE_BIT;
        color_in_ = vk::Image(dev, extent, VK_FORMAT_R16G16B16A16_SFLOAT, u);
        color_out_ = vk::Image(dev, extent, VK_FORMAT_R16G16B16A16_SFLOAT, u);
        depth_ = vk::Image(dev, extent, VK_FORMAT_R32_SFLOAT, u);
        motion_ = vk::Image(dev, extent, VK_FORMAT_R16G16_SFLOAT, u);
        rate_ = vk::Image(dev, extent, VK_FORMAT_R16_SFLOAT, u);
    }

    Result<void> init(PostPass& pass) {
        const ModuleContext ctx{dev_, config_, extent_, VK_NULL_HANDLE, gbuffer_, rate_tiles_};
        return pass.init(ctx);
    }

    void set_inputs(const post::Image& colour, const post::Image& depth, const post::Image& motion,
                    const post::Image& rate) {
        upload(dev_, color_in_, colour);
        upload(dev_, depth_, depth);
        upload(dev_, motion_, motion);
        upload(dev_, rate_, rate);
    }

    // Records `frames` frames of the pass into one submission (inputs unchanged between them).
    void run(PostPass& pass, int frames, bool camera_cut = false, float gaze_x = 0,
             float gaze_y = 0) {
        FrameInputs inputs;
        inputs.camera_cut = camera_cut;
        ResolvedGaze gaze;
        gaze.x_px = gaze_x;
        gaze.y_px = gaze_y;
        FrameUniforms u{};
        u.extent[0] = float(extent_.width);
        u.extent[1] = float(extent_.height);
        u.gaze_px[0] = gaze_x;
        u.gaze_px[1] = gaze_y;
        if (display_) {  // as Foveator fills the frame uniforms
            constexpr double kDegToRad = 0.017453292519943295;
            u.display_size_px[0] = u.extent[0];
            u.display_size_px[1] = u.extent[1];
            u.display_half_tan[0] = float(std::tan(display_->fov_h_deg * 0.5 * kDegToRad));
            u.display_half_tan[1] = float(std::tan(display_->fov_v_deg * 0.5 * kDegToRad));
        }
        dev_.submit_and_wait([&](VkCommandBuffer cmd) {
            for (int i = 0; i < frames; ++i) {
                const PostFrame f{cmd,          VK_NULL_HANDLE, frame_++,        u,
                                  inputs,       gaze,           color_in_.ref(), color_out_.ref(),
                                  depth_.ref(), motion_.ref(),  rate_.ref(),     jitter_};
                pass.record(f);
                compute_barrier(cmd);
                inputs.camera_cut = false;
            }
        });
    }

    // The sub-pixel jitter the frames report (PostFrame::jitter_px); none by default.
    void set_jitter(float x, float y) { jitter_ = {x, y}; }

    // The display the frame uniforms describe (eccentricity, pixels per degree); none by default.
    void set_display(const EyeDisplay& d) { display_ = d; }

    post::Image output(int channels = 3) const {
        return download(dev_, color_out_.ref(), channels);
    }
    FoveatorConfig& config() { return config_; }
    post::Image rate() const { return download(dev_, rate_.ref(), 1); }

private:
    const Device& dev_;
    VkExtent2D extent_;
    FoveatorConfig config_;
    GBufferRefs gbuffer_;
    ImageRef rate_tiles_;
    vk::Image color_in_, color_out_, depth_, motion_, rate_;
    uint64_t frame_ = 0;
    std::array<float, 2> jitter_{0.f, 0.f};
    std::optional<EyeDisplay> display_;
};

// The S_t fields the 1080p cost benchmarks run on: growing with eccentricity (smooth), and per
// centred 16x16 tile, 0 / 0.5 / 1 (as cps quantizes it).
inline post::Image cost_rate_smooth(int w, int h) {
    post::Image r(w, h, 1);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            r.at(x, y) = std::min(1.0f, std::hypot(x - w / 2.0f, y - h / 2.0f) / 600.0f);
    return r;
}
inline post::Image cost_rate_tiles(int w, int h) {
    post::Image r(w, h, 1);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float d = std::hypot(x / 16 * 16 + 8 - w / 2.0f, y / 16 * 16 + 8 - h / 2.0f);
            r.at(x, y) = d < 200.0f ? 0.0f : (d < 450.0f ? 0.5f : 1.0f);
        }
    return r;
}

// Per-frame milliseconds of `batches` runs of 2 frames of `pass` after one warm-up frame, each
// list sorted: wall time, and the process CPU time (every driver thread), which swings far less
// with the machine's load. A measurement for benchmarks, never a pass/fail threshold.
struct PassCost {
    std::vector<double> wall_ms, cpu_ms;
};
inline PassCost measure_pass_cost(PassRunner& run, PostPass& pass, int batches) {
    const auto process_cpu_ms = [] {
        timespec ts{};
        clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
        return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
    };
    run.run(pass, 1);  // warm-up
    PassCost c;
    for (int i = 0; i < batches; ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        const double c0 = process_cpu_ms();
        run.run(pass, 2);
        c.cpu_ms.push_back((process_cpu_ms() - c0) / 2.0);
        c.wall_ms.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count() /
            2.0);
    }
    std::sort(c.wall_ms.begin(), c.wall_ms.end());
    std::sort(c.cpu_ms.begin(), c.cpu_ms.end());
    return c;
}

}  // namespace fovea::vk::testing
