// Buffers shared by the coarse-pixel-shading passes (method "cps", sdk/src/vk/methods/cps.cpp).
#ifndef FOVEA_CPS_COMMON_GLSL
#define FOVEA_CPS_COMMON_GLSL

// Work lists. 0 = 1x1, 1 = 2x2, 2 = 4x4 (host shading function); 3 = the edge list (pixels
// re-shaded at full rate); 4, 5, 6 = background-only tiles at 1x1 / 2x2 / 4x4 (the host's
// environment function fovea_background). Reused tiles are in no list: they cost no thread.
const uint kCpsEdgeList = 3u;
// Threads per workgroup of the shade and edge passes (the indirect sizes divide by it): large,
// because every workgroup is a task with its own set-up on llvmpipe.
#define CPS_GROUP_SIZE 256
const uint kCpsGroupSize = CPS_GROUP_SIZE;
const uint kCpsBackgroundList = 4u;
uint cps_list_rate_class(uint list) { return list & 3u; }
uint cps_list_base(uint list) { return list < 3u ? list : list - 1u; }  // tile lists, edges skipped

layout(std430, set = 1, binding = 0) buffer CpsLists { uint tile[]; } cps_lists;  // [6][capacity]
layout(std430, set = 1, binding = 1) buffer CpsArgs {
    uvec4 cmd[8];    // VkDispatchIndirectCommand x, y, z (+ pad) per list (7 unused)
    uint count[8];   // tiles per list, edge pixels
    uint dropped;    // edge pixels beyond the list's capacity (kept at the coarse shade)
} cps_args;
layout(std430, set = 1, binding = 2) buffer CpsEdges { uint px[]; } cps_edges;  // x | y << 15 | cls << 30
// Per tile, persistent: luminance range (min, max as float bits; luminance >= 0 so the bits
// order like the values) of the tile's shading, accumulated by the shade and edge passes, reset
// by the classify pass when the tile is shaded again; read next frame to find flat tiles.
layout(std430, set = 1, binding = 4) buffer CpsLuminance { uvec2 range[]; } cps_luminance;

void cps_add_luminance(uint tile, vec3 c) {
    uint l = floatBitsToUint(max(dot(c, vec3(0.2126, 0.7152, 0.0722)), 0.0));
    // A plain read first: most samples change neither bound, and atomics are the cost.
    uvec2 r = cps_luminance.range[tile];
    if (l < r.x) atomicMin(cps_luminance.range[tile].x, l);
    if (l > r.y) atomicMax(cps_luminance.range[tile].y, l);
}

// Classification flags (CpsPush.flags), set on the CPU per frame.
const uint kCpsSkip = 1u;             // option cps.skip: the skip classes below are enabled
const uint kCpsHistory = 2u;          // consecutive frame index, no camera cut: last frame valid
const uint kCpsCameraStill = 4u;      // FrameInputs::camera_pos equal to last frame's
const uint kCpsHostBackground = 8u;   // the host GLSL defines fovea_background()
const uint kCpsReuse = 16u;           // option cps.skip.reuse: still tiles may be reused

layout(push_constant) uniform CpsPush {
    uint tiles_x;
    uint tiles_y;
    uint capacity;         // tiles per list
    uint edge_capacity;    // entries of cps_edges
    uint list;             // list of this dispatch (shade passes)
    uint flags;            // kCps* above
    uint frame;            // frame index, low 32 bits (staggered refresh)
    uint refresh_frames;   // re-shade a reused tile at least every this many frames (0: never)
    uint converge_frames;  // shaded frames of a still tile at the same rate before reuse
    float still_px;        // max |motion + jitter| in pixels of a still tile
    float ecc_deg;         // max eccentricity change of a reused tile since its shading
    float flat_contrast;   // (max - min) / (max + min) of luminance below this: flat
    float saturated;       // luminance of every pixel at or above this: saturated
} cps_push;

#endif
