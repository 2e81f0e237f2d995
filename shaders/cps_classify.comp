#version 450
// Coarse pixel shading, pass 1: the rate of every tile from the acuity model (one thread per
// tile), the tile appended to its class list, and the indirect dispatch sizes grown so the shade
// pass launches exactly one thread per coarse pixel of the listed tiles.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;
#include "fovea_frame.glsl"
#include "cps_common.glsl"
layout(set = 1, binding = 3, r8ui) uniform writeonly uimage2D cps_rate_tiles;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= cps_push.tiles_x * cps_push.tiles_y) return;
    uint tx = i % cps_push.tiles_x;
    uint ty = i / cps_push.tiles_x;
    float ts = fovea_frame.acuity.tile_size;
    vec2 lo = vec2(float(tx), float(ty)) * ts;
    vec2 hi = min(lo + vec2(ts), fovea_frame.extent);
    float r = fovea_tile_rate(fovea_frame.display, fovea_frame.acuity, lo, hi, fovea_frame.gaze_px);
    uint cls = r >= 4.0 ? 2u : (r >= 2.0 ? 1u : 0u);
    imageStore(cps_rate_tiles, ivec2(int(tx), int(ty)), uvec4(uint(r)));
    uint slot = atomicAdd(cps_args.count[cls], 1u);
    cps_lists.tile[cls * cps_push.capacity + slot] = i;
    uint side = uint(ts) >> cls;
    atomicMax(cps_args.cmd[cls].x, ((slot + 1u) * side * side + 63u) / 64u);
    atomicAdd(fovea_stats.tiles[cls], 1u);
}
