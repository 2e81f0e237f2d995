// The host-shaded integration paths (issue 18): post chain on the host's frame (path 4), the
// host's own images read in place of the module's (any sampleable format, reverse-Z, UV
// motion), and host-rendered eccentricity layers composited by the module (path 2).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <vector>

#include "../vk/vk_test_util.hpp"
#include "fovea/vk/foveator.hpp"
#include "fovea/vk/vrs.hpp"
#include "gpu.hpp"

namespace fovea::vk {
namespace {

constexpr uint32_t kW = 192, kH = 128;

FoveatorConfig path_config(IntegrationPath path, std::vector<std::string> post = {}) {
    FoveatorConfig c;
    c.path = path;
    c.extent = {kW, kH};
    c.display = EyeDisplay::from_fov(kW, kH, 60.0, 40.0);
    c.acuity.mar_slope = 0.1f;  // steep, so a small frame spans every rate (and several layers)
    c.post_chain = std::move(post);
    return c;
}

// A smooth colour field over the full frame, in display pixels: what every layer shows where.
std::array<float, 3> field(double x, double y) {
    return {float(0.5 + 0.4 * std::sin(x * 0.05)), float(0.5 + 0.4 * std::cos(y * 0.07)),
            float(0.3 + 0.2 * std::sin((x + y) * 0.03))};
}

std::vector<uint8_t> rgba16f(uint32_t w, uint32_t h,
                             const std::function<std::array<float, 3>(uint32_t, uint32_t)>& f) {
    std::vector<uint8_t> out(size_t{w} * h * 8);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            const auto c = f(x, y);
            uint16_t t[4] = {fovea::half_bits(c[0]), fovea::half_bits(c[1]), fovea::half_bits(c[2]),
                             fovea::half_bits(1.f)};
            std::memcpy(&out[(size_t{y} * w + x) * 8], t, 8);
        }
    return out;
}

std::vector<uint8_t> filled(uint32_t w, uint32_t h, VkFormat format, const void* texel) {
    const uint32_t b = format_bytes(format);
    std::vector<uint8_t> out(size_t{w} * h * b);
    for (size_t i = 0; i < size_t{w} * h; ++i) std::memcpy(&out[i * b], texel, b);
    return out;
}

std::array<float, 4> texel16(const std::vector<uint8_t>& img, uint32_t w, uint32_t x, uint32_t y) {
    uint16_t t[4];
    std::memcpy(t, &img[(size_t{y} * w + x) * 8], 8);
    return {fovea::half_from_bits(t[0]), fovea::half_from_bits(t[1]), fovea::half_from_bits(t[2]),
            fovea::half_from_bits(t[3])};
}

// Path 4: the host's frame passes through untouched without a chain, S_t is the acuity model's
// and every pixel counts as shaded by the host.
TEST(PostOnlyPath, HostFramePassesThroughWithTheModelsRate) {
    FOVEA_REQUIRE_DEVICE();
    auto f = Foveator::create(*device, path_config(IntegrationPath::kPostOnly));
    ASSERT_TRUE(f) << f.error().message;
    EXPECT_EQ(f->gbuffer().extent.width, 0u);  // no G-buffer on this path
    const HostTargets& t = f->host_targets();
    ASSERT_EQ(t.extent.width, kW);
    const auto color = rgba16f(kW, kH, [](uint32_t x, uint32_t y) { return field(x, y); });
    upload_image(*device, t.color, color);
    const float depth = 0.5f;
    upload_image(*device, t.depth, filled(kW, kH, kHostDepthFormat, &depth));
    FrameInputs in;
    in.gaze.x = 0.3f;
    in.gaze.y = 0.6f;
    f->render_blocking(0, in, {});
    EXPECT_EQ(device->read_image(f->output()), color);
    const FrameStats s = f->stats();
    EXPECT_EQ(s.shaded_samples, uint64_t{kW} * kH);
    EXPECT_DOUBLE_EQ(s.shaded_fraction, 1.0);
    const auto rate = device->read_image(f->rate());
    const FoveatorConfig& c = f->config();
    const uint32_t ts = c.acuity.tile_size;
    size_t mismatches = 0, coarse = 0;
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            const uint32_t x0 = x / ts * ts, y0 = y / ts * ts;
            const float r = tile_rate(c.display, c.acuity, s.gaze, x0, y0, std::min(x0 + ts, kW),
                                      std::min(y0 + ts, kH));
            uint16_t h;
            std::memcpy(&h, &rate[(size_t{y} * kW + x) * 2], 2);
            mismatches += fovea::half_from_bits(h) != normalized_rate(r);
            coarse += r > 1.f;
        }
    EXPECT_EQ(mismatches, 0u);
    EXPECT_GT(coarse, 0u);  // the display spans coarse rates, or the comparison proves little
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

TEST(PostOnlyPath, TaaAndEnhancementRunOnTheHostFrame) {
    FOVEA_REQUIRE_DEVICE();
    auto f = Foveator::create(
        *device, path_config(IntegrationPath::kPostOnly, {"taa", "contrast", "noise"}));
    ASSERT_TRUE(f) << f.error().message;
    const HostTargets& t = f->host_targets();
    upload_image(*device, t.color,
                 rgba16f(kW, kH, [](uint32_t x, uint32_t y) { return field(x, y); }));
    const float depth = 0.5f;
    upload_image(*device, t.depth, filled(kW, kH, kHostDepthFormat, &depth));
    for (uint64_t i = 0; i < 3; ++i) {
        FrameInputs in;
        in.camera_cut = i == 0;
        f->render_blocking(i, in, {});
    }
    const auto out = device->read_image(f->output());
    size_t bad = 0;
    double diff = 0;
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            const auto c = texel16(out, kW, x, y);
            bad += !(std::isfinite(c[0]) && std::isfinite(c[1]) && std::isfinite(c[2]));
            diff += std::abs(c[0] - field(x, y)[0]);
        }
    EXPECT_EQ(bad, 0u);
    EXPECT_LT(diff / (kW * kH), 0.05);  // a still frame stays itself through the chain
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

// A host image the module reads in place of its target: made, filled and transitioned the way an
// engine does (the depth buffer is D32_SFLOAT, sampled through its depth aspect).
class HostOwnedImage {
public:
    HostOwnedImage(const Device& device, VkExtent2D extent, VkFormat format,
                   VkImageAspectFlags aspect, const std::vector<uint8_t>& texels)
        : device_(device.device()) {
        VkImageCreateInfo ici{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
        ici.imageType = VK_IMAGE_TYPE_2D;
        ici.format = format;
        ici.extent = {extent.width, extent.height, 1};
        ici.mipLevels = ici.arrayLayers = 1;
        ici.samples = VK_SAMPLE_COUNT_1_BIT;
        ici.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
        VK_CHECK(vkCreateImage(device_, &ici, nullptr, &image_));
        VkMemoryRequirements req;
        vkGetImageMemoryRequirements(device_, image_, &req);
        VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        mai.allocationSize = req.size;
        mai.memoryTypeIndex =
            device.memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
        VK_CHECK(vkAllocateMemory(device_, &mai, nullptr, &memory_));
        VK_CHECK(vkBindImageMemory(device_, image_, memory_, 0));
        VkImageViewCreateInfo vci{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        vci.image = image_;
        vci.viewType = VK_IMAGE_VIEW_TYPE_2D;
        vci.format = format;
        vci.subresourceRange = {aspect, 0, 1, 0, 1};
        VK_CHECK(vkCreateImageView(device_, &vci, nullptr, &view_));
        Buffer staging(device, texels.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true);
        std::memcpy(staging.data(), texels.data(), texels.size());
        device.submit_and_wait([&](VkCommandBuffer cmd) {
            VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
            b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
            b.image = image_;
            b.subresourceRange = {aspect, 0, 1, 0, 1};
            b.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
            b.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
            vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT,
                                 VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 0, nullptr, 1, &b);
            VkBufferImageCopy region{};
            region.imageSubresource = {aspect, 0, 0, 1};
            region.imageExtent = {extent.width, extent.height, 1};
            vkCmdCopyBufferToImage(cmd, staging.get(), image_, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                                   1, &region);
            b.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
            b.newLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
            b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
            b.dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
            vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                                 VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0, nullptr, 0, nullptr, 1,
                                 &b);
        });
    }
    HostOwnedImage(const HostOwnedImage&) = delete;
    HostOwnedImage& operator=(const HostOwnedImage&) = delete;
    ~HostOwnedImage() {
        vkDestroyImageView(device_, view_, nullptr);
        vkDestroyImage(device_, image_, nullptr);
        vkFreeMemory(device_, memory_, nullptr);
    }
    HostImage host_image() const { return {view_, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL}; }

private:
    VkDevice device_;
    VkImage image_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    VkImageView view_ = VK_NULL_HANDLE;
};

// An engine's own frame: RGBA8 colour, a reverse-Z D32 depth buffer, motion in UV as previous -
// current. The module reads them into its conventions.
TEST(PostOnlyPath, ReadsTheHostsOwnImagesInItsConventions) {
    FOVEA_REQUIRE_DEVICE();
    auto f = Foveator::create(*device, path_config(IntegrationPath::kPostOnly));
    ASSERT_TRUE(f) << f.error().message;
    std::vector<uint8_t> rgba8(size_t{kW} * kH * 4);
    std::vector<float> depth(size_t{kW} * kH), motion(size_t{kW} * kH * 2);
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            const size_t i = size_t{y} * kW + x;
            rgba8[i * 4 + 0] = uint8_t(x);
            rgba8[i * 4 + 1] = uint8_t(y * 2);
            rgba8[i * 4 + 2] = 200;
            rgba8[i * 4 + 3] = 255;
            depth[i] = 0.25f + 0.5f * float(x) / kW;  // reverse-Z
            motion[i * 2 + 0] = -3.0f / kW;           // previous - current, UV
            motion[i * 2 + 1] = 1.5f / kH;
        }
    auto bytes = [](const std::vector<float>& v) {
        std::vector<uint8_t> b(v.size() * 4);
        std::memcpy(b.data(), v.data(), b.size());
        return b;
    };
    HostOwnedImage color(*device, {kW, kH}, VK_FORMAT_R8G8B8A8_UNORM, VK_IMAGE_ASPECT_COLOR_BIT,
                         rgba8);
    HostOwnedImage zbuf(*device, {kW, kH}, VK_FORMAT_D32_SFLOAT, VK_IMAGE_ASPECT_DEPTH_BIT,
                        bytes(depth));
    HostOwnedImage mv(*device, {kW, kH}, VK_FORMAT_R32G32_SFLOAT, VK_IMAGE_ASPECT_COLOR_BIT,
                      bytes(motion));
    HostFrameImages host;
    host.extent = {kW, kH};
    host.color = color.host_image();
    host.depth = zbuf.host_image();
    host.motion = mv.host_image();
    host.depth_mapping = DepthMapping::kReversed;
    host.motion_scale = {-float(kW), -float(kH)};
    FrameInputs in;
    in.host_images = host;
    f->render_blocking(0, in, {});
    const HostTargets& t = f->host_targets();
    const auto c = device->read_image(t.color), d = device->read_image(t.depth),
               m = device->read_image(t.motion);
    size_t wrong = 0;
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            const size_t i = size_t{y} * kW + x;
            const auto col = texel16(c, kW, x, y);
            float dv;
            std::memcpy(&dv, &d[i * 4], 4);
            uint16_t mh[2];
            std::memcpy(mh, &m[i * 4], 4);
            wrong += std::abs(col[0] - x / 255.f) > 1e-3f || std::abs(col[2] - 200 / 255.f) > 1e-3f;
            wrong += std::abs(dv - (1.f - depth[i])) > 1e-6f;  // 0 near .. 1 far
            wrong += std::abs(fovea::half_from_bits(mh[0]) - 3.f) > 1e-2f ||
                     std::abs(fovea::half_from_bits(mh[1]) + 1.5f) >
                         1e-2f;  // pixels, current - previous
        }
    EXPECT_EQ(wrong, 0u);
    EXPECT_EQ(device->read_image(f->output()), c);
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

TEST(PostOnlyPath, MismatchedHostImageIsWarnedNotRead) {
    FOVEA_REQUIRE_DEVICE();
    auto f = Foveator::create(*device, path_config(IntegrationPath::kPostOnly));
    ASSERT_TRUE(f) << f.error().message;
    const std::vector<uint8_t> px(size_t{8} * 8 * 4, 7);
    HostOwnedImage small(*device, {8, 8}, VK_FORMAT_R8G8B8A8_UNORM, VK_IMAGE_ASPECT_COLOR_BIT, px);
    HostFrameImages host;
    host.extent = {8, 8};
    host.color = host.depth = small.host_image();
    FrameInputs in;
    in.host_images = host;
    f->render_blocking(0, in, {});       // must neither crash nor read out of bounds
    EXPECT_FALSE(f->set_method("cps"));  // the method is fixed off the deferred path
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

// Path 2: the host renders each layer views() asks for; the composite shows the field in every
// band and the fovea exactly as the inner layer holds it.
TEST(ForwardLayersPath, HostRenderedLayersCompositeToTheField) {
    FOVEA_REQUIRE_DEVICE();
    auto f = Foveator::create(*device, path_config(IntegrationPath::kForwardLayers, {"taa"}));
    ASSERT_TRUE(f) << f.error().message;
    EXPECT_EQ(f->method(), "layers");
    EXPECT_EQ(f->gbuffer().extent.width, 0u);
    FrameInputs in;
    in.gaze.x = 0.4f;
    in.gaze.y = 0.5f;
    in.camera_cut = true;
    const std::vector<ViewRequest> views = f->views(0, in);
    ASSERT_GE(views.size(), 2u);
    uint64_t texels = 0;
    for (size_t v = 0; v < views.size(); ++v) {
        const ViewRequest& r = views[v];
        ASSERT_EQ(r.targets.extent.width, r.extent.width);
        ASSERT_EQ(r.gbuffer.extent.width, 0u);
        const double sx = (r.crop[2] - r.crop[0]) * kW / r.extent.width;
        const double sy = (r.crop[3] - r.crop[1]) * kH / r.extent.height;
        // Texel k's sample, in display pixels: crop origin + (k + 0.5 + jitter) * s.
        upload_image(*device, r.targets.color,
                     rgba16f(r.extent.width, r.extent.height, [&](uint32_t x, uint32_t y) {
                         return field(r.crop[0] * kW + (x + 0.5 + r.jitter_px[0]) * sx,
                                      r.crop[1] * kH + (y + 0.5 + r.jitter_px[1]) * sy);
                     }));
        const float depth = 0.1f * float(v + 1);
        upload_image(*device, r.targets.depth,
                     filled(r.extent.width, r.extent.height, kHostDepthFormat, &depth));
        texels += uint64_t{r.extent.width} * r.extent.height;
    }
    f->render_blocking(0, in, {});
    const FrameStats s = f->stats();
    EXPECT_EQ(s.shaded_samples, texels);
    EXPECT_LT(s.shaded_fraction, 0.8);
    const auto out = device->read_image(f->shaded());
    const auto jit = f->jitter(0);
    double err = 0, fovea_err = 0;
    size_t n = 0, nf = 0;
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            const auto c = texel16(out, kW, x, y);
            const auto want = field(x + 0.5 + jit[0], y + 0.5 + jit[1]);
            const double e = std::abs(c[0] - want[0]) + std::abs(c[1] - want[1]);
            err += e;
            ++n;
            if (std::hypot(x + 0.5 - s.gaze.x_px, y + 0.5 - s.gaze.y_px) < 6.0) {
                fovea_err = std::max(fovea_err, e);
                ++nf;
            }
        }
    EXPECT_LT(err / n, 0.01);    // coarse layers still show the smooth field (measured 0.002)
    EXPECT_LT(fovea_err, 1e-3);  // the inner layer, texel for pixel (half rounding; 2e-4)
    EXPECT_GT(nf, 20u);
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

// Path 3's density map from the same acuity model: read back texel by texel against the CPU
// model, on devices without VK_EXT_fragment_density_map too (as a storage image).
TEST(RateImagePath, DensityMapMatchesTheCpuModel) {
    FOVEA_REQUIRE_DEVICE();
    const EyeDisplay d = EyeDisplay::desktop_1080p();
    const AcuityParams a;
    GazeState g;
    g.x = 0.7f;
    g.y = 0.35f;
    const ResolvedGaze rg = resolve_gaze(g, d, a);
    for (uint32_t texel : {8u, 16u, 32u}) {
        auto map = DensityMap::create(*device, d, texel, true);
        ASSERT_TRUE(map) << map.error().message;
        EXPECT_EQ(map->texel_size(), texel);
        device->submit_and_wait([&](VkCommandBuffer cmd) { map->record(cmd, a, rg); });
        const auto gpu = device->read_image(map->image());
        const auto cpu = cpu_density_texels(d, a, rg, texel);
        ASSERT_EQ(gpu.size(), cpu.size());
        size_t mismatches = 0;
        for (size_t i = 0; i < cpu.size(); ++i) mismatches += gpu[i] != cpu[i];
        EXPECT_EQ(mismatches, 0u) << "texel " << texel;
        // Densities present: full rate (255), 2x2 (127), 4x4 (63).
        for (uint8_t v : {uint8_t(255), uint8_t(127), uint8_t(63)})
            EXPECT_NE(std::find(gpu.begin(), gpu.end(), v), gpu.end()) << int(v);
    }
    EXPECT_FALSE(DensityMap::create(*device, d, 12, true));  // not a power of two
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

// Where the device lacks the hardware rates (lavapipe), the path fails at creation, saying which
// extension is missing; where it has them, the rate image is there to bind.
TEST(RateImagePath, NeedsTheHardwareItNames) {
    FOVEA_REQUIRE_DEVICE();
    for (RateImageKind kind : {RateImageKind::kShadingRate, RateImageKind::kDensityMap}) {
        FoveatorConfig c = path_config(IntegrationPath::kRateImage, {"taa"});
        c.rate_image = kind;
        const bool supported = kind == RateImageKind::kShadingRate
                                   ? device->vrs_support().supported
                                   : device->density_map_support().supported;
        auto f = Foveator::create(*device, c);
        if (!supported) {
            ASSERT_FALSE(f);
            EXPECT_NE(f.error().message.find(kind == RateImageKind::kShadingRate
                                                 ? "VK_KHR_fragment_shading_rate"
                                                 : "VK_EXT_fragment_density_map"),
                      std::string::npos)
                << f.error().message;
            continue;
        }
        ASSERT_TRUE(f) << f.error().message;
        EXPECT_NE(f->rate_image().image, VkImage(VK_NULL_HANDLE));
        FrameInputs in;
        device->submit_and_wait([&](VkCommandBuffer cmd) { f->record_rate_image(cmd, in); });
        f->render_blocking(0, in, {});
        EXPECT_LT(f->stats().shaded_fraction, 1.0);
    }
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

}  // namespace
}  // namespace fovea::vk
