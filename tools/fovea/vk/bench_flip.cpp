#include "bench_flip.hpp"

#include <cmath>
#include <limits>

namespace fovea::bench {

using metrics::FlipInput;

Result<std::unique_ptr<BenchFlip>> BenchFlip::create(const vk::Device& device,
                                                     const vk::EyeDisplay& display) {
    const uint32_t w = display.width_px, h = display.height_px;
    const metrics::PpdField seen = metrics::display_ppd_field(display, w, h);
    auto flip = metrics::GpuFlip::create(
        device, w, h, {seen, seen, metrics::PpdField::uniform(w, h, metrics::kFlipDefaultPpd)});
    if (!flip) return flip.error();
    std::vector<float> ppd(size_t(w) * h);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x)
            ppd[size_t(y) * w + x] = float(std::sqrt(seen.x[x] * seen.y[y]));
    return std::unique_ptr<BenchFlip>(new BenchFlip(device, std::move(*flip), std::move(ppd)));
}

void BenchFlip::begin(size_t methods) {
    flip_.forget_inputs();  // the last configuration's outputs are gone
    while (previous_.size() < methods)
        previous_.emplace_back(*device_, VkExtent2D{flip_.width(), flip_.height()},
                               VK_FORMAT_R16G16B16A16_SFLOAT, VK_IMAGE_USAGE_SAMPLED_BIT);
    previous_frame_.assign(methods, -1);
    sums_.assign(methods, FlipSums{});
}

BenchFlip::BenchFlip(const vk::Device& device, metrics::GpuFlip flip, std::vector<float> ppd_map)
    : device_(&device), flip_(std::move(flip)), ppd_map_(std::move(ppd_map)) {}

void BenchFlip::add_frame(size_t k, int frame, const vk::ImageRef& output,
                          const demo::BandLabels& labels, const std::vector<float>& motion,
                          bool reference) {
    FlipSums& s = sums_[k];
    if (k == 0) flip_.set_motion(motion);
    device_->submit_and_wait([&](VkCommandBuffer cmd) {
        if (reference) {
            flip_.record_reference(cmd, output, FlipInput::kDemoDisplay, kDisplay);
            flip_.record_reference(cmd, output, FlipInput::kDemoDisplay, kTool);
        }
        flip_.record_compare(cmd, output, FlipInput::kDemoDisplay, kDisplay);
    });
    s.display.add(flip_.map(), labels.band);
    s.gpu_ms.push_back(flip_.compare_gpu_ms());
    s.ppd.add(ppd_map_, labels.band);
    device_->submit_and_wait([&](VkCommandBuffer cmd) {
        flip_.record_compare(cmd, output, FlipInput::kDemoDisplay, kTool);
    });
    s.tool.add(flip_.map(), labels.band);
    const bool consecutive = previous_frame_[k] >= 0 && previous_frame_[k] + 1 == frame;
    device_->submit_and_wait([&](VkCommandBuffer cmd) {
        if (consecutive) {
            flip_.record_back_projected_reference(cmd, previous_[k].ref(), output, kTemporal);
            flip_.record_compare(cmd, output, FlipInput::kDemoDisplay, kTemporal);
        }
        vk::compute_barrier(cmd);  // the FLIP passes read previous_[k] before it is replaced
        VkImageCopy c{};
        c.srcSubresource = c.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        c.extent = {output.extent.width, output.extent.height, 1};
        vkCmdCopyImage(cmd, output.image, VK_IMAGE_LAYOUT_GENERAL, previous_[k].get(),
                       VK_IMAGE_LAYOUT_GENERAL, 1, &c);
        vk::compute_barrier(cmd);
    });
    if (consecutive) {
        double sum = 0;
        size_t n = 0;
        for (float v : flip_.map())
            if (std::isfinite(v)) {
                sum += v;
                ++n;
            }
        s.temporal.emplace_back(frame,
                                n ? sum / double(n) : std::numeric_limits<double>::quiet_NaN());
    }
    previous_frame_[k] = frame;
}

}  // namespace fovea::bench
