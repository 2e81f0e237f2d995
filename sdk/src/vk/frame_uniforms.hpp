// C++ mirror of the frame uniform block in shaders/fovea_frame.glsl (std140) and of its stats
// buffer. Change both together.
#pragma once

#include <cstddef>
#include <cstdint>

namespace fovea::vk {

struct FrameUniforms {
    float extent[2];
    float inv_extent[2];
    float gaze_px[2];
    float jitter_px[2];
    float display_size_px[2];  // FoveaDisplay
    float display_half_tan[2];
    float mar_slope;  // FoveaAcuity
    float mar_omega0;
    float foveal_radius_deg;
    float transition_deg;
    float margin_deg;
    float max_rate;
    float tile_size;
    float acuity_reserved;
    float camera_pos[4];  // w = radians per pixel
    float time[4];        // x seconds, y frame index
    float host[64];
};
static_assert(offsetof(FrameUniforms, display_size_px) == 32, "std140 layout");
static_assert(offsetof(FrameUniforms, mar_slope) == 48, "std140 layout");
static_assert(offsetof(FrameUniforms, camera_pos) == 80, "std140 layout");
static_assert(offsetof(FrameUniforms, host) == 112, "std140 layout");
static_assert(sizeof(FrameUniforms) == 368, "std140 layout");

struct FrameStatsGpu {
    uint32_t shaded_samples;
    uint32_t edge_samples;
    uint32_t tiles[4];
    uint32_t background_tiles;
    uint32_t reused_tiles;
    uint32_t flat_tiles;
    uint32_t no_detail_tiles;
    uint32_t reserved[6];
};
static_assert(sizeof(FrameStatsGpu) == 64, "std430 layout");

}  // namespace fovea::vk
