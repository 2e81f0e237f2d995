#version 450
// TAA pass 3: sorts the resolve's 8×8 tiles into lists by which moment levels their pixels
// read, one thread per tile; each list's indirect dispatch grows by one workgroup per tile.
// lavapipe runs every line of a shader for every lane (a branch only masks lanes), so each list
// has a resolve pipeline with only the reads its tiles need (taa_resolve.glsl, kTileClass):
//   0  some pixel has LOD = 4·S_t < 1, not all 0: the pixel's own 3×3 window (level 0) and the
//      trilinear fetch from the chain
//   1  every LOD ≥ 1: the chain fetch only (most of a foveated frame)
//   2  every LOD 0 (full rate): the 3×3 window only
// Same LOD rule as taa_resolve.glsl (NaN/inf S_t counts as 1, LOD clamped to the chain).
layout(local_size_x = 64) in;
layout(set = 0, binding = 0, r16f) uniform readonly image2D rate_in;
layout(std430, set = 0, binding = 1) buffer TaaTileArgs {
    uvec4 cmd[3];  // VkDispatchIndirectCommand x, y, z (+ pad) per list
} args;
// [3][capacity]: tile x | y << 16
layout(std430, set = 0, binding = 2) buffer TaaTileLists { uint tile[]; } lists;

layout(push_constant) uniform Push {
    uint tiles_x;
    uint tiles_y;
    int levels;  // moment chain levels (LOD clamps to levels - 1)
} pc;

const int kTile = 8;  // the resolve's workgroup

void main() {
    uint tile = gl_GlobalInvocationID.x;
    uint capacity = pc.tiles_x * pc.tiles_y;
    if (tile >= capacity) return;
    ivec2 lo = ivec2(int(tile % pc.tiles_x), int(tile / pc.tiles_x)) * kTile;
    ivec2 hi = min(lo + ivec2(kTile), imageSize(rate_in));
    float max_lod = float(pc.levels - 1);
    float lod_min = max_lod;
    float lod_max = 0.0;
    for (int y = lo.y; y < hi.y; ++y) {
        for (int x = lo.x; x < hi.x; ++x) {
            float s = imageLoad(rate_in, ivec2(x, y)).x;
            s = (isnan(s) || isinf(s)) ? 1.0 : clamp(s, 0.0, 1.0);
            float lod = min(4.0 * s, max_lod);
            lod_min = min(lod_min, lod);
            lod_max = max(lod_max, lod);
        }
    }
    uint list = lod_max == 0.0 ? 2u : (lod_min < 1.0 ? 0u : 1u);
    uint slot = atomicAdd(args.cmd[list].x, 1u);
    // Tile coordinates, not the index: lavapipe divides integers lane by lane (scalar).
    lists.tile[list * capacity + slot] = (tile % pc.tiles_x) | ((tile / pc.tiles_x) << 16);
}
