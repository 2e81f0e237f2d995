// Method "cps": coarse pixel shading (Vaidyanathan 2014 as used by Patney 2016) in compute.
// Pass 1 classifies tiles into 1x1 / 2x2 / 4x4 rate lists from the acuity model; pass 2 shades
// one sample per coarse pixel (three indirect dispatches sized by the lists, so the work is
// proportional to the samples shaded); pass 3 re-shades the pixels at surface discontinuities
// inside coarse pixels (indirect, sized by the edge list). shaders/cps_*.
#include <cassert>
#include <cstring>

#include "../method.hpp"

namespace fovea::vk {
namespace {

struct CpsPush {
    uint32_t tiles_x, tiles_y, capacity, edge_capacity, cls;
};

// Matches CpsArgs in shaders/cps_common.glsl.
struct CpsArgs {
    uint32_t cmd[4][4];
    uint32_t count[4];
    uint32_t dropped;
    uint32_t pad[3];
};

class CpsMethod final : public Method {
public:
    Result<void> init(const ModuleContext& ctx) override {
        const uint32_t ts = ctx.config.acuity.tile_size;
        tiles_x_ = div_up(ctx.extent.width, ts);
        tiles_y_ = div_up(ctx.extent.height, ts);
        capacity_ = tiles_x_ * tiles_y_;
        const uint64_t pixels = uint64_t{ctx.extent.width} * ctx.extent.height;
        edge_capacity_ = static_cast<uint32_t>(pixels / 4 + 64);
        lists_ = Buffer(ctx.device, uint64_t{capacity_} * 3 * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                        false);
        args_ = Buffer(ctx.device, sizeof(CpsArgs),
                       VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                       false);
        edges_ = Buffer(ctx.device, uint64_t{edge_capacity_} * 4,
                        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false);
        const Binding sb{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};
        const Binding classify_bindings[] = {sb, sb, sb, {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}};
        const Binding shade_bindings[] = {sb, sb, sb};
        classify_ = ctx.builtin_pipeline("cps_classify.comp", classify_bindings, sizeof(CpsPush),
                                         true);
        auto shade = ctx.shading_pipeline("cps_shade.shade.comp", shade_bindings, sizeof(CpsPush));
        if (!shade) return shade.error();
        shade_ = std::move(*shade);
        auto edge = ctx.shading_pipeline("cps_edge.shade.comp", shade_bindings, sizeof(CpsPush));
        if (!edge) return edge.error();
        edge_ = std::move(*edge);
        VkDevice d = ctx.device.device();
        classify_set_ = classify_.allocate_set();
        DescriptorWriter(d, classify_set_)
            .storage_buffer(0, lists_)
            .storage_buffer(1, args_)
            .storage_buffer(2, edges_)
            .storage_image(3, ctx.rate_tiles.view)
            .commit();
        shade_set_ = shade_.allocate_set();
        DescriptorWriter(d, shade_set_)
            .storage_buffer(0, lists_)
            .storage_buffer(1, args_)
            .storage_buffer(2, edges_)
            .commit();
        edge_set_ = edge_.allocate_set();
        DescriptorWriter(d, edge_set_)
            .storage_buffer(0, lists_)
            .storage_buffer(1, args_)
            .storage_buffer(2, edges_)
            .commit();
        return {};
    }

    void record(const MethodFrame& f) override {
        CpsArgs init{};
        for (auto& c : init.cmd) {
            c[1] = 1;
            c[2] = 1;
        }
        vkCmdUpdateBuffer(f.cmd, args_.get(), 0, sizeof(init), &init);
        compute_barrier(f.cmd);
        CpsPush push{tiles_x_, tiles_y_, capacity_, edge_capacity_, 0};
        classify_.bind(f.cmd, f.frame_set, classify_set_, &push, sizeof(push));
        vkCmdDispatch(f.cmd, div_up(tiles_x_ * tiles_y_, 64), 1, 1);
        indirect_barrier(f.cmd);
        for (uint32_t cls = 0; cls < 3; ++cls) {
            push.cls = cls;
            shade_.bind(f.cmd, f.frame_set, shade_set_, &push, sizeof(push));
            vkCmdDispatchIndirect(f.cmd, args_.get(), cls * 16);
        }
        indirect_barrier(f.cmd);
        edge_.bind(f.cmd, f.frame_set, edge_set_, &push, sizeof(push));
        vkCmdDispatchIndirect(f.cmd, args_.get(), 3 * 16);
    }

private:
    uint32_t tiles_x_ = 0, tiles_y_ = 0, capacity_ = 0, edge_capacity_ = 0;
    Buffer lists_, args_, edges_;
    ComputePipeline classify_, shade_, edge_;
    VkDescriptorSet classify_set_ = VK_NULL_HANDLE, shade_set_ = VK_NULL_HANDLE,
                    edge_set_ = VK_NULL_HANDLE;
};

}  // namespace

std::unique_ptr<Method> make_cps_method() { return std::make_unique<CpsMethod>(); }

}  // namespace fovea::vk
