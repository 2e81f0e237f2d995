#include "fovea/metrics/gpu_flip.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <iterator>
#include <string>
#include <vector>

#include "flip_filters.hpp"
#include "gpu.hpp"
#include "shaders.hpp"

namespace fovea::metrics {
namespace {

constexpr uint32_t kBlock = 16;  // kFlipBlock in shaders/flip_common.glsl

struct AxisGpu {  // FlipAxis, std430
    int32_t colour_radius, feature_radius;
    uint32_t colour_offset, feature_offset;
    float cz1_sum, cz2_sum, reserved0, reserved1;
};
static_assert(sizeof(AxisGpu) == 32);

struct ColourGpu {  // FlipColour, std140: a mat3 is 3 columns of vec4
    float rgb_to_xyz[12], xyz_to_rgb[12];
    float white[4], colour[4], feature[4];
};
static_assert(sizeof(ColourGpu) == 144);

struct PreparePush {
    uint32_t width, height;
};
struct HorizontalPush {
    uint32_t width, height, block_offset;
};
struct VerticalPush {
    uint32_t width, height, blocks_x, block_offset, reference_offset;
};

constexpr uint32_t kBackProject = 2;  // kFlipBackProject
constexpr uint32_t kSrgb8 = 3;        // kFlipSrgb8: kSrgb from an 8-bit UNORM image
constexpr uint32_t kPrepareKinds = 4;

// The filters' workgroups (invocations, x a multiple of llvmpipe's 8 lanes; the horizontal pass
// does 4 columns per invocation, the vertical 2 rows): 64 x 8 and 16 x 64 pixels, long along
// the axis filtered so each workgroup re-reads fewer apron texels than a 16 x 16 block does.
// 128 invocations is all Vulkan guarantees: a device with fewer than 512 gets shorter vertical
// workgroups (the shaders take any shape).
constexpr uint32_t kHorizontalGroup[2] = {16, 8};
constexpr uint32_t kVerticalGroupWidth = 16, kVerticalGroupRows = 32;

// kSrgb from an image whose texels are 8-bit codes decodes them through the LUT, exactly.
uint32_t prepare_kind(FlipInput kind, VkFormat format) {
    const bool unorm8 = format == VK_FORMAT_R8G8B8A8_UNORM || format == VK_FORMAT_B8G8R8A8_UNORM;
    return kind == FlipInput::kSrgb && unorm8 ? kSrgb8 : uint32_t(kind);
}

constexpr uint32_t kTimestamps = 4;  // start, after prepare, horizontal, vertical

void fill_mat3(float* out, const detail::Mat3& m) {
    for (int c = 0; c < 3; ++c) {
        for (int r = 0; r < 3; ++r) out[4 * c + r] = float(m[r][c]);
        out[4 * c + 3] = 0.f;
    }
}

// The axis tables: one entry per distinct ppd, its taps as vec4 weights, and per ppd field and
// 16-pixel block the entry it uses (column blocks, then row blocks).
struct AxisTables {
    std::vector<AxisGpu> axes;
    std::vector<float> weights;  // vec4 per tap
    std::vector<uint32_t> block_axis;
    std::vector<uint32_t> field_offset;  // per field, its first column block in block_axis
    std::vector<double> values;          // ppd of each entry of axes
};

// The shaders add each pair of taps i and -i under one weight: every kernel must be even about
// its centre, the first derivative odd.
bool symmetric(const detail::AxisFilters& f) {
    const auto even = [](const std::vector<double>& k, double sign) {
        for (size_t i = 0; i < k.size(); ++i)
            if (float(k[i]) != float(sign * k[k.size() - 1 - i])) return false;
        return true;
    };
    return even(f.y, 1) && even(f.cx, 1) && even(f.cz1, 1) && even(f.cz2, 1) && even(f.g, 1) &&
           even(f.dg, -1) && even(f.ddg, 1);
}

Result<bool> add_field(AxisTables& t, const PpdField& ppd, uint32_t w, uint32_t h) {
    std::vector<double>& values = t.values;
    const auto add_axis = [&](const std::vector<double>& field, uint32_t n) -> Result<bool> {
        for (uint32_t b = 0; b * kBlock < n; ++b) {
            const double p = field[b * kBlock];
            for (uint32_t i = b * kBlock; i < std::min(n, (b + 1) * kBlock); ++i)
                if (field[i] != p)
                    return make_error("GPU FLIP: ppd must be constant over aligned " +
                                      std::to_string(kBlock) + "-pixel blocks");
            if (!(p > 0) || !std::isfinite(p)) return make_error("GPU FLIP: ppd must be > 0");
            auto it = std::find(values.begin(), values.end(), p);
            if (it == values.end()) {
                const detail::AxisFilters f = detail::make_axis_filters(p);
                if (std::max(f.colour_radius, f.feature_radius) > GpuFlip::kMaxRadius)
                    return make_error("GPU FLIP: ppd " + std::to_string(p) +
                                      " needs kernels wider than the GPU version's");
                if (!symmetric(f))
                    return make_error("GPU FLIP: the kernels for ppd " + std::to_string(p) +
                                      " are not even about their centre (the shaders pair taps)");
                AxisGpu a{};
                a.colour_radius = f.colour_radius;
                a.feature_radius = f.feature_radius;
                a.colour_offset = uint32_t(t.weights.size() / 4);
                for (size_t k = 0; k < f.y.size(); ++k)
                    t.weights.insert(t.weights.end(), {float(f.y[k]), float(f.cx[k]),
                                                       float(f.cz1[k]), float(f.cz2[k])});
                a.feature_offset = uint32_t(t.weights.size() / 4);
                for (size_t k = 0; k < f.g.size(); ++k)
                    t.weights.insert(t.weights.end(),
                                     {float(f.g[k]), float(f.dg[k]), float(f.ddg[k]), 0.f});
                a.cz1_sum = float(f.cz1_sum);
                a.cz2_sum = float(f.cz2_sum);
                t.axes.push_back(a);
                values.push_back(p);
                it = values.end() - 1;
            }
            t.block_axis.push_back(uint32_t(it - values.begin()));
        }
        return true;
    };
    if (ppd.x.size() != w || ppd.y.size() != h)
        return make_error("GPU FLIP: the ppd field does not match the image size");
    t.field_offset.push_back(uint32_t(t.block_axis.size()));
    if (auto r = add_axis(ppd.x, w); !r) return r.error();
    if (auto r = add_axis(ppd.y, h); !r) return r.error();
    return true;
}

template <typename T>
vk::Buffer host_buffer(const vk::Device& d, const std::vector<T>& v, VkBufferUsageFlags usage) {
    vk::Buffer b(d, std::max<VkDeviceSize>(16, v.size() * sizeof(T)), usage, true);
    std::memcpy(b.data(), v.data(), v.size() * sizeof(T));
    return b;
}

}  // namespace

PpdField display_ppd_field(const vk::EyeDisplay& display, uint32_t width, uint32_t height) {
    // The metrics run at the rendered image's resolution; the model is in the display's pixels.
    const float sx = float(display.width_px) / float(width);
    const float sy = float(display.height_px) / float(height);
    const float cx = 0.5f * float(display.width_px), cy = 0.5f * float(display.height_px);
    PpdField f;
    f.x.resize(width);
    f.y.resize(height);
    for (uint32_t x = 0; x < width; ++x) {
        const float centre = std::min(float((x / kBlock) * kBlock) + 0.5f * kBlock, float(width));
        f.x[x] = 1.0 / (double(vk::pixel_size_deg_axes(display, centre * sx, cy)[0]) * sx);
    }
    for (uint32_t y = 0; y < height; ++y) {
        const float centre = std::min(float((y / kBlock) * kBlock) + 0.5f * kBlock, float(height));
        f.y[y] = 1.0 / (double(vk::pixel_size_deg_axes(display, cx, centre * sy)[1]) * sy);
    }
    return f;
}

struct GpuFlip::Impl {
    const vk::Device* device = nullptr;
    uint32_t width = 0, height = 0, blocks_x = 0, blocks_y = 0;
    vk::Buffer opponent, horizontal, reference, map, motion, axes, weights, block_axis, colour,
        srgb_lut;
    vk::UniqueBufferView opponent_view, horizontal_view, reference_view, map_view, weights_view,
        axes_view, block_axis_view, srgb_lut_view;
    vk::ComputePipeline prepare[kPrepareKinds], horiz, vert[2];  // per prepare kind, mode
    uint32_t vertical_rows = kVerticalGroupRows;  // the vertical pass's workgroup height
    vk::LinearClampSampler sampler;
    VkDescriptorSet horiz_set = VK_NULL_HANDLE, vert_set = VK_NULL_HANDLE;
    vk::UniqueDescriptorPool prepare_pool;
    std::map<std::pair<VkImageView, VkImageView>, VkDescriptorSet> prepare_sets;
    std::vector<uint32_t> field_offset;  // per reference slot
    vk::UniqueQueryPool queries;         // one timestamp before and after each compare pass

    static constexpr uint32_t kPrepareSets = 64;  // distinct (input, fill) image pairs

    VkDescriptorSet prepare_set(VkImageView a, VkImageView b) {
        const auto key = std::make_pair(a, b);
        if (auto it = prepare_sets.find(key); it != prepare_sets.end()) return it->second;
        if (prepare_sets.size() == kPrepareSets)
            throw vk::VkError(VK_ERROR_OUT_OF_POOL_MEMORY,
                              "GPU FLIP: more than 64 distinct input images since "
                              "forget_inputs()");
        VkDescriptorSetLayout layout = prepare[0].set_layout();  // all kinds' are alike
        VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
        ai.descriptorPool = prepare_pool.get();
        ai.descriptorSetCount = 1;
        ai.pSetLayouts = &layout;
        VkDescriptorSet set = VK_NULL_HANDLE;
        VK_CHECK(vkAllocateDescriptorSets(device->device(), &ai, &set));
        vk::DescriptorWriter(device->device(), set)
            .sampled_image(0, a, sampler.get())
            .sampled_image(1, b, sampler.get())
            .storage_buffer(2, motion)
            .uniform_buffer(4, colour)
            .storage_texel_buffer(3, opponent_view.get())
            .uniform_texel_buffer(5, srgb_lut_view.get())
            .commit();
        prepare_sets.emplace(key, set);
        return set;
    }

    void dispatch(VkCommandBuffer cmd) const { vkCmdDispatch(cmd, blocks_x, blocks_y, 1); }

    void timestamp(VkCommandBuffer cmd, bool timed, uint32_t query) const {
        if (timed && queries)
            vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, queries.get(), query);
    }

    // Inputs and earlier passes' writes -> this filtering; then prepare, horizontal, vertical,
    // each followed by a timestamp when `timed`.
    void record_filter(VkCommandBuffer cmd, VkImageView a, VkImageView b, uint32_t kind,
                       uint32_t mode, int slot, bool timed = false) {
        assert(slot >= 0 && size_t(slot) < field_offset.size());
        // The first timestamp goes before the barrier: lavapipe writes a timestamp when the
        // commands after it are next flushed (a barrier or a later timestamp), so one written
        // after the barrier would read the time after prepare and leave prepare out.
        if (timed && queries) {
            vkCmdResetQueryPool(cmd, queries.get(), 0, kTimestamps);
            vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries.get(), 0);
        }
        vk::compute_barrier(cmd);
        const PreparePush pp{width, height};
        prepare[kind].bind(cmd, VK_NULL_HANDLE, prepare_set(a, b), &pp, sizeof(pp));
        dispatch(cmd);
        timestamp(cmd, timed, 1);
        vk::compute_barrier(cmd);
        const HorizontalPush hp{width, height, field_offset[slot]};
        horiz.bind(cmd, VK_NULL_HANDLE, horiz_set, &hp, sizeof(hp));
        vkCmdDispatch(cmd, vk::div_up(width, 4 * kHorizontalGroup[0]),
                      vk::div_up(height, kHorizontalGroup[1]), 1);
        timestamp(cmd, timed, 2);
        vk::compute_barrier(cmd);
        const VerticalPush vp{width, height, blocks_x, field_offset[slot],
                              uint32_t(2 * slot) * width * height};
        vert[mode].bind(cmd, VK_NULL_HANDLE, vert_set, &vp, sizeof(vp));
        vkCmdDispatch(cmd, vk::div_up(width, kVerticalGroupWidth),
                      vk::div_up(height, 2 * vertical_rows), 1);
        timestamp(cmd, timed, 3);
    }
};

Result<GpuFlip> GpuFlip::create(const vk::Device& device, uint32_t width, uint32_t height,
                                const std::vector<PpdField>& references) {
    if (width == 0 || height == 0) return make_error("GPU FLIP: empty image");
    if (references.empty()) return make_error("GPU FLIP: no reference slot");
    AxisTables tables;
    for (const PpdField& f : references)
        if (auto r = add_field(tables, f, width, height); !r) return r.error();
    try {
        auto m = std::make_unique<Impl>();
        m->device = &device;
        m->width = width;
        m->height = height;
        m->blocks_x = vk::div_up(width, kBlock);
        m->blocks_y = vk::div_up(height, kBlock);
        const VkDeviceSize pixels = VkDeviceSize(width) * height;
        constexpr VkBufferUsageFlags kStorage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
        constexpr VkBufferUsageFlags kTexel =
            VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT;
        const uint64_t texels = 2 * pixels * references.size();  // the largest view
        if (texels > device.properties().limits.maxTexelBufferElements)
            return make_error("GPU FLIP: the image is too large for the device's texel buffers");
        m->vertical_rows =
            std::min(kVerticalGroupRows, device.properties().limits.maxComputeWorkGroupInvocations /
                                             kVerticalGroupWidth);
        m->opponent = vk::Buffer(device, pixels * 16, kTexel, false);
        m->horizontal = vk::Buffer(device, pixels * 32, kTexel, false);
        m->reference = vk::Buffer(device, pixels * 32 * references.size(), kTexel, false);
        m->field_offset = tables.field_offset;
        m->map = vk::Buffer(device, pixels * 4, VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT, true);
        m->motion = vk::Buffer(device, pixels * 8, kStorage, true);
        std::memset(m->motion.data(), 0, pixels * 8);
        constexpr VkBufferUsageFlags kTable = VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT;
        m->axes = host_buffer(device, tables.axes, kTable);
        m->weights = host_buffer(device, tables.weights, kTable);
        m->block_axis = host_buffer(device, tables.block_axis, kTable);
        std::vector<float> lut(256);
        for (int i = 0; i < 256; ++i) lut[i] = float(detail::srgb_to_linear(i / 255.0));
        m->srgb_lut = host_buffer(device, lut, kTable);
        m->opponent_view = vk::texel_view(device, m->opponent);
        m->horizontal_view = vk::texel_view(device, m->horizontal);
        m->reference_view = vk::texel_view(device, m->reference);
        m->map_view = vk::texel_view(device, m->map, VK_FORMAT_R32_SFLOAT, 4);
        m->weights_view = vk::texel_view(device, m->weights);
        m->axes_view = vk::texel_view(device, m->axes, VK_FORMAT_R32G32B32A32_UINT);
        m->block_axis_view = vk::texel_view(device, m->block_axis, VK_FORMAT_R32_UINT, 4);
        m->srgb_lut_view = vk::texel_view(device, m->srgb_lut, VK_FORMAT_R32_SFLOAT, 4);
        ColourGpu c{};
        fill_mat3(c.rgb_to_xyz, detail::rgb_to_xyz());
        fill_mat3(c.xyz_to_rgb, detail::xyz_to_rgb());
        for (int k = 0; k < 3; ++k) c.white[k] = float(detail::white()[k]);
        const double cmax = detail::cmax();
        c.colour[0] = float(cmax);
        c.colour[1] = float(detail::kPc * cmax);
        c.colour[2] = float(detail::kPt);
        c.colour[3] = float(detail::kQc);
        c.feature[0] = float(1.0 / std::sqrt(2.0));
        m->colour = vk::Buffer(device, sizeof(c), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, true);
        std::memcpy(m->colour.data(), &c, sizeof(c));
        m->sampler = vk::LinearClampSampler(device);

        using B = vk::Binding;
        const B sampled{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER};
        const B storage{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};
        const B uniform{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER};
        const B texel{VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER};
        const B out{VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER};
        const B prepare_b[] = {sampled, sampled, storage, out, uniform, texel};
        const B horiz_b[] = {texel, out, texel, texel, texel};
        const B vert_b[] = {texel, out, out, texel, texel, texel, uniform, texel};
        for (uint32_t kind = 0; kind < kPrepareKinds; ++kind) {
            const uint32_t spec[] = {kind};
            m->prepare[kind] =
                vk::ComputePipeline(device, vk::shader_spirv("flip_prepare.comp"), VK_NULL_HANDLE,
                                    prepare_b, sizeof(PreparePush), spec);
        }
        m->horiz =
            vk::ComputePipeline(device, vk::shader_spirv("flip_horizontal.comp"), VK_NULL_HANDLE,
                                horiz_b, sizeof(HorizontalPush), kHorizontalGroup);
        for (uint32_t mode = 0; mode < 2; ++mode) {
            const uint32_t spec[] = {mode, kVerticalGroupWidth, m->vertical_rows};
            m->vert[mode] = vk::ComputePipeline(device, vk::shader_spirv("flip_vertical.comp"),
                                                VK_NULL_HANDLE, vert_b, sizeof(VerticalPush), spec);
        }
        m->horiz_set = m->horiz.allocate_set();
        vk::DescriptorWriter(device.device(), m->horiz_set)
            .uniform_texel_buffer(0, m->opponent_view.get())
            .storage_texel_buffer(1, m->horizontal_view.get())
            .uniform_texel_buffer(2, m->axes_view.get())
            .uniform_texel_buffer(3, m->weights_view.get())
            .uniform_texel_buffer(4, m->block_axis_view.get())
            .commit();
        m->vert_set = m->vert[0].allocate_set();  // used with both modes' alike layouts
        vk::DescriptorWriter(device.device(), m->vert_set)
            .uniform_texel_buffer(0, m->horizontal_view.get())
            .storage_texel_buffer(1, m->reference_view.get())
            .storage_texel_buffer(2, m->map_view.get())
            .uniform_texel_buffer(3, m->axes_view.get())
            .uniform_texel_buffer(4, m->weights_view.get())
            .uniform_texel_buffer(5, m->block_axis_view.get())
            .uniform_buffer(6, m->colour)
            .uniform_texel_buffer(7, m->reference_view.get())
            .commit();
        const VkDescriptorPoolSize sizes[] = {
            {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 2 * Impl::kPrepareSets},
            {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, Impl::kPrepareSets},
            {VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER, Impl::kPrepareSets},
            {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, Impl::kPrepareSets},
            {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, Impl::kPrepareSets}};
        VkDescriptorPoolCreateInfo dpi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        dpi.maxSets = Impl::kPrepareSets;
        dpi.poolSizeCount = uint32_t(std::size(sizes));
        dpi.pPoolSizes = sizes;
        m->prepare_pool = vk::create_handle<vk::UniqueDescriptorPool>(device.device(),
                                                                      vkCreateDescriptorPool, dpi);
        if (device.properties().limits.timestampComputeAndGraphics) {
            VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
            qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
            qi.queryCount = kTimestamps;
            m->queries =
                vk::create_handle<vk::UniqueQueryPool>(device.device(), vkCreateQueryPool, qi);
        }
        return GpuFlip(std::move(m));
    } catch (const vk::VkError& e) { return make_error(std::string("GPU FLIP: ") + e.what()); }
}

GpuFlip::GpuFlip(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
GpuFlip::GpuFlip(GpuFlip&&) noexcept = default;
GpuFlip& GpuFlip::operator=(GpuFlip&&) noexcept = default;
GpuFlip::~GpuFlip() = default;

uint32_t GpuFlip::width() const { return impl_->width; }
uint32_t GpuFlip::height() const { return impl_->height; }

void GpuFlip::record_reference(VkCommandBuffer cmd, const vk::ImageRef& image, FlipInput kind,
                               int slot) {
    impl_->record_filter(cmd, image.view, image.view, prepare_kind(kind, image.format), 0, slot);
}

void GpuFlip::record_back_projected_reference(VkCommandBuffer cmd, const vk::ImageRef& previous,
                                              const vk::ImageRef& current, int slot) {
    impl_->record_filter(cmd, previous.view, current.view, kBackProject, 0, slot);
}

void GpuFlip::set_motion(std::span<const float> motion_px) {
    const size_t bytes = std::min<size_t>(motion_px.size_bytes(), impl_->motion.size());
    std::memcpy(impl_->motion.data(), motion_px.data(), bytes);
}

void GpuFlip::record_compare(VkCommandBuffer cmd, const vk::ImageRef& test, FlipInput kind,
                             int slot) {
    Impl& m = *impl_;
    m.record_filter(cmd, test.view, test.view, prepare_kind(kind, test.format), 1, slot, true);
    VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
    mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0,
                         1, &mb, 0, nullptr, 0, nullptr);
}

void GpuFlip::forget_inputs() {
    Impl& m = *impl_;
    if (m.prepare_sets.empty()) return;
    VK_CHECK(vkResetDescriptorPool(m.device->device(), m.prepare_pool.get(), 0));
    m.prepare_sets.clear();
}

std::span<const float> GpuFlip::map() const {
    return {static_cast<const float*>(impl_->map.data()), size_t(impl_->width) * impl_->height};
}

FlipPassTimes GpuFlip::compare_gpu_times() const {
    const Impl& m = *impl_;
    uint64_t ts[kTimestamps] = {};
    if (!m.queries ||
        vkGetQueryPoolResults(m.device->device(), m.queries.get(), 0, kTimestamps, sizeof(ts), ts,
                              sizeof(uint64_t), VK_QUERY_RESULT_64_BIT) != VK_SUCCESS)
        return {};
    const double period_ms = m.device->properties().limits.timestampPeriod * 1e-6;
    const auto ms = [&](int a, int b) { return double(ts[b] - ts[a]) * period_ms; };
    return {ms(0, 1), ms(1, 2), ms(2, 3), ms(0, 3)};
}

double GpuFlip::compare_gpu_ms() const { return compare_gpu_times().total_ms; }

}  // namespace fovea::metrics
