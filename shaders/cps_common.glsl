// Buffers shared by the coarse-pixel-shading passes (method "cps", sdk/src/vk/methods/cps.cpp).
#ifndef FOVEA_CPS_COMMON_GLSL
#define FOVEA_CPS_COMMON_GLSL

// Rate classes: 0 = 1x1, 1 = 2x2, 2 = 4x4; 3 = the edge list (pixels re-shaded at full rate).
layout(std430, set = 1, binding = 0) buffer CpsLists { uint tile[]; } cps_lists;  // [class][capacity]
layout(std430, set = 1, binding = 1) buffer CpsArgs {
    uvec4 cmd[4];    // VkDispatchIndirectCommand x, y, z (+ pad) per class and the edge pass
    uint count[4];   // tiles per class, edge pixels
    uint dropped;    // edge pixels beyond the list's capacity (kept at the coarse shade)
} cps_args;
layout(std430, set = 1, binding = 2) buffer CpsEdges { uint px[]; } cps_edges;  // x | y << 15 | cls << 30

layout(push_constant) uniform CpsPush {
    uint tiles_x;
    uint tiles_y;
    uint capacity;       // tiles per class list
    uint edge_capacity;  // entries of cps_edges
    uint cls;            // rate class of this dispatch (shade pass)
} cps_push;

#endif
